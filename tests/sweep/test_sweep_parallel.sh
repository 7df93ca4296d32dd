#!/usr/bin/env bash
# A sweep run by GNU parallel over `popc sweep --list` (one `popc run` line
# per run), gathered by `popc sweep merge`: its summary equals the in-process
# sweep's but for wall time. Then a failed job retried with --resume-failed.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/paper.ini
command -v parallel >/dev/null || { echo "GNU parallel is not installed"; exit 77; }
T=$(mktemp -d /tmp/popc-sweep-par-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
nowall() { sed 's/,[^,]*$//' "$1"; }
same_nowall() { cmp -s <(nowall "$1") <(nowall "$2") || { diff <(nowall "$1") <(nowall "$2") | head -5; return 1; }; }

# a fixed --set too: the listed lines must carry it (the runs of the plan)
VARY=(--set run.duration=3 --vary operator.speed=0.02:0.08:3 --vary controller.variant=none,ref-energy,filtered-velocity,improved)

# the scene is a copy that is edited between --list and the runs: the listed
# lines run the plan's resolved scenes, so the edit must change nothing
cp "$SCENE" "$T/scene.ini"
"$POPC" sweep "$T/scene.ini" "${VARY[@]}" -o "$T/p" --list > "$T/jobs" 2>"$T/err"
check "--list exits 0" test $? -eq 0
check "  one line per run (12)" test "$(wc -l < "$T/jobs")" -eq 12
check "  popc run lines, each on its run's scene.ini" test "$(grep -c " run $T/p/runs/00[01][0-9]/scene.ini --log " "$T/jobs")" -eq 12
check "  run 0005: its scene, log and summary" grep -q " run $T/p/runs/0005/scene.ini --log $T/p/runs/0005/log.csv --summary $T/p/runs/0005/run.csv -q$" "$T/jobs"
check "  run 0005's scene: speed 0.05, ref-energy" grep -qx "variant = ref-energy" "$T/p/runs/0005/scene.ini"
check "  ... speed 0.05" grep -q "^speed = 0\.050*[0-9]\?$" "$T/p/runs/0005/scene.ini"
check "  ... and the fixed --set (duration 3)" grep -qx "duration = 3" "$T/p/runs/0005/scene.ini"
sed -i 's/^pc_bound = 5 /pc_bound = 1 /; s/^stiffness = 1000 /stiffness = 2000 /' "$T/scene.ini"
check "the scene file is edited after --list" grep -q "^pc_bound = 1 " "$T/scene.ini"

# the GNU parallel recipe of docs/SWEEPS.md (here on this machine only)
parallel --will-cite --jobs 2 --joblog "$T/joblog" < "$T/jobs" > "$T/par.out" 2>&1
check "parallel ran every job (exit $?)" test "$(awk 'NR > 1 && $7 == 0' "$T/joblog" | wc -l)" -eq 12
"$POPC" sweep merge "$T/p" 2>"$T/err"
check "merge exits 0" test $? -eq 0

"$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/s" -j 2 -q --no-log
check "the in-process sweep exits 0" test $? -eq 0
check "parallel + merge equals the in-process sweep of the scene as listed (but wall time)" same_nowall "$T/p/summary.csv" "$T/s/summary.csv"
check "  3 s runs (3001 ticks)" test "$(cut -d, -f5 "$T/p/summary.csv" | sort -u | tr '\n' ' ')" = "3001 ticks "
check "  including the chatter columns" test "$(cut -d, -f19-21 "$T/p/summary.csv" | sort -u | wc -l)" -gt 2

# a job that failed (here: its run.csv taken away and the job marked failed)
# is retried by parallel --resume-failed; merge then finds the run again
rm "$T/p/runs/0003/run.csv" "$T/p/runs/0003/log.csv"
"$POPC" sweep merge "$T/p" -o "$T/p" 2>"$T/err"
check "merge without run 0003: exit 1" test $? -eq 1
check "  says one run has no result" grep -q "1 without a result" "$T/err"
awk -F'\t' 'BEGIN { OFS = "\t" } NR > 1 && $0 ~ /runs\/0003\// { $7 = 1 } { print }' "$T/joblog" > "$T/joblog2" && mv "$T/joblog2" "$T/joblog"
parallel --will-cite --jobs 2 --joblog "$T/joblog" --resume-failed < "$T/jobs" > "$T/par.out" 2>&1
check "parallel --resume-failed reran run 0003" test -s "$T/p/runs/0003/run.csv"
"$POPC" sweep merge "$T/p" 2>"$T/err"
check "merge complete again" test $? -eq 0
check "  equal to the in-process sweep" same_nowall "$T/p/summary.csv" "$T/s/summary.csv"

check_summary
