#!/usr/bin/env bash
# What a sweep reads back is checked (issue 28): an edited sweep.plan (its
# digest; its vary lines against the sweep resumed), a rows file or a --list
# run's run.csv with a cell no run writes (nan, inf, a value not the plan's),
# a directory where sweep.plan should be: refused with exit 2 naming the file
# and line, before any run, nothing overwritten. And an -o that cannot be a
# sweep directory (a file, the scene, a read-only directory) is exit 2 before
# any work, for popc sweep, sweep merge and map.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/paper.ini
T=$(mktemp -d /tmp/popc-sweep-trust-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

ARGS=(--set run.duration=0.2 --vary operator.speed=0.02,0.03,0.04 --vary controller.variant=none,improved --no-log -q -j 1)
expect_exit 0 "a small sweep" "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/s"
check "  its plan ends with its digest" grep -qE '^digest = [0-9a-f]{16}$' <(tail -1 "$T/s/sweep.plan")
# fresh DIR: a copy of the finished sweep
fresh() { rm -rf "$T/$1"; cp -r "$T/s" "$T/$1"; }

# ---- an edited vary line
fresh v
sed -i 's/^vary = operator.speed=0.02,0.03,0.04$/vary = operator.speed=0.02,0.03,0.05/' "$T/v/sweep.plan"
cp "$T/v/summary.csv" "$T/v.before"
expect_exit 2 "a resume of a plan whose vary line was edited" "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/v"
digest_line=$(grep -n '^digest = ' "$T/v/sweep.plan" | cut -d: -f1)
check "  names the plan and its digest line ($digest_line)" err_has "$T/v/sweep.plan:$digest_line: the digest does not match the plan's lines above it"
check "  summary.csv left as it was" cmp -s "$T/v/summary.csv" "$T/v.before"
expect_exit 2 "  merge of it" "$POPC" sweep merge "$T/v" -o "$T/vm"
expect_exit 2 "  stats read summary.csv only, merge refuses the plan: merge into itself" "$POPC" sweep merge "$T/v"
check "  summary.csv still as it was" cmp -s "$T/v/summary.csv" "$T/v.before"
# a plan of popc before digests (no digest line): the vary lines are
# compared with the sweep resumed
sed -i '/^digest = /d' "$T/v/sweep.plan"
expect_exit 2 "the same edit in a plan without a digest (popc before them)" "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/v"
check "  names the line's value and the sweep's" err_has "$T/v/sweep.plan: vary = operator.speed=0.02,0.03,0.05, but this sweep's --vary 1 is operator.speed=0.02,0.03,0.04 under the same plan id: the plan was edited"
check "  summary.csv left as it was" cmp -s "$T/v/summary.csv" "$T/v.before"
fresh v2
sed -i '/^digest = /d' "$T/v2/sweep.plan"
expect_exit 0 "a plan without a digest, not edited, resumes" "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/v2"

# ---- cells no run writes, in a rows file
rows_file() { ls "$T/$1"/rows/*.csv | head -1; }
for bad in nan inf -inf 0x1p1 1e999; do
  fresh r
  f=$(rows_file r)
  # the pc_rms cell (6th) of run 0003's row
  line=$(grep -n '^0003,' "$f" | cut -d: -f1)
  awk -F, -v OFS=, -v bad="$bad" '$1 == "0003" { $6 = bad } { print }' "$f" > "$T/tmp" && cat "$T/tmp" > "$f"
  cp "$T/r/summary.csv" "$T/r.before"
  expect_exit 2 "a rows file with '$bad' in a cell: resume refused" "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/r"
  check "  names file, line, run and column" err_has "$f:$line: run 0003: column pc_rms: '$bad' is not a finite number"
  check "  summary.csv left as it was" cmp -s "$T/r/summary.csv" "$T/r.before"
  expect_exit 2 "  merge refuses it too" "$POPC" sweep merge "$T/r" -o "$T/rm"
  check "  and writes no summary" test ! -e "$T/rm/summary.csv"
done
# an axis cell that is not the plan's value of that run
fresh a
f=$(rows_file a)
line=$(grep -n '^0002,' "$f" | cut -d: -f1)
sed -i 's/^0002,0.03,none,/0002,0.07,none,/' "$f"
expect_exit 2 "a rows file whose varied value is not the plan's" "$POPC" sweep merge "$T/a"
check "  names it" err_has "$f:$line: run 0002: column operator.speed: '0.07', but the plan's value of this run is '0.03'"

# ---- a --list run's run.csv with nan
expect_exit 0 "a --list sweep" "$POPC" sweep "$SCENE" --set run.duration=0.2 --vary operator.speed=0.02,0.03 -o "$T/l" --list
sh "$T/out" >/dev/null 2>&1
expect_exit 0 "  merged" "$POPC" sweep merge "$T/l"
awk -F, -v OFS=, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i } NR == 2 { $c["pc_rms"] = "nan" } { print }' "$T/l/runs/0001/run.csv" > "$T/tmp" && cat "$T/tmp" > "$T/l/runs/0001/run.csv"
cp "$T/l/summary.csv" "$T/l.before"
expect_exit 2 "  a run.csv with nan: merge refused" "$POPC" sweep merge "$T/l"
check "  names run.csv, its line and the column" err_has "$T/l/runs/0001/run.csv:2: column pc_rms: 'nan' is not a finite number"
check "  summary.csv left as it was" cmp -s "$T/l/summary.csv" "$T/l.before"

# ---- a directory where sweep.plan should be
mkdir -p "$T/p/sweep.plan"
expect_exit 2 "a directory where sweep.plan should be" "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/p"
check "  says so" err_has "$T/p/sweep.plan: not a plan file (a directory stands there)"
check "  before any other work: no rows, no runs" test ! -e "$T/p/rows" -a ! -e "$T/p/runs"
expect_exit 2 "  merge of it" "$POPC" sweep merge "$T/p"
check "  says so" err_has "$T/p/sweep.plan: not a plan file"
expect_exit 2 "  a map into it" "$POPC" map "$SCENE" --variant none --stiffness 1000:2000 -o "$T/p" -q
check "  says so" err_has "$T/p/sweep.plan: not a plan file"

# ---- an -o that cannot be a sweep directory: exit 2 before any work
touch "$T/afile"
cp "$SCENE" "$T/scene.ini"
for o in "$T/afile" "$T/scene.ini" "$T/afile/sub"; do
  cp "$T/scene.ini" "$T/scene.before"
  expect_exit 2 "sweep -o $o" "$POPC" sweep "$T/scene.ini" "${ARGS[@]}" -o "$o"
  check "  names -o" err_has "-o $o: "
  expect_exit 2 "sweep merge -o $o" "$POPC" sweep merge "$T/s" -o "$o"
  check "  names -o" err_has "-o $o: "
  expect_exit 2 "map -o $o" "$POPC" map "$T/scene.ini" --variant none --stiffness 1000:2000 -o "$o" -q
  check "  names -o" err_has "-o $o: "
  check "  the scene is left as it was" cmp -s "$T/scene.ini" "$T/scene.before"
done
check "  the file is left as it was (empty)" test ! -s "$T/afile"
# a read-only directory: as root every directory is writable, so the
# programs run as nobody (setpriv, util-linux)
if [ "$(id -u)" -eq 0 ] && command -v setpriv >/dev/null && setpriv --reuid=65534 --regid=65534 --clear-groups true 2>/dev/null; then
  as_nobody() { setpriv --reuid=65534 --regid=65534 --clear-groups "$@"; }
  chmod 755 "$T"; chmod -R a+rX "$T/s"
  mkdir -p "$T/ro"; chmod 555 "$T/ro"
  if as_nobody test -x "$POPC" && as_nobody test -r "$SCENE"; then
    expect_exit 2 "sweep -o a read-only directory" as_nobody "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/ro"
    check "  says so" err_has "-o $T/ro: no file can be made in $T/ro"
    expect_exit 2 "sweep -o a new directory inside a read-only one" as_nobody "$POPC" sweep "$SCENE" "${ARGS[@]}" -o "$T/ro/new/sub"
    check "  names the parent" err_has "-o $T/ro/new/sub: no file can be made in $T/ro"
    expect_exit 2 "sweep merge -o a read-only directory" as_nobody "$POPC" sweep merge "$T/s" -o "$T/ro"
    expect_exit 2 "map -o a read-only directory" as_nobody "$POPC" map "$SCENE" --variant none --stiffness 1000:2000 -o "$T/ro" -q
    check "  nothing made in it" test -z "$(ls -A "$T/ro")"
  else
    echo "# the build cannot be run by nobody here: read-only cases left out"
  fi
else
  echo "# not root or no setpriv: read-only cases left out"
fi

check_summary
