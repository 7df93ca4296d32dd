#!/usr/bin/env bash
# popc sweep as a user runs it: usage errors before anything runs, a small
# sweep with logs, its summary against popc-analyze compare, resume, failed
# runs, shards and merge, Slurm array variables, --no-log, SIGINT, rows files
# of a reused pid, and workers that die or are stopped alone.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
BUILD=${POPC_BUILD_ROOT:?}
SCENE=$SRC/data/scenes/paper.ini
T=$(mktemp -d /tmp/popc-sweep-cli-XXXXXX)
pid=
cleanup() { [ -n "$pid" ] && kill "$pid" 2>/dev/null; rm -rf "$T"; }
trap cleanup EXIT
. "$SRC/tests/check.sh"
# a summary without its last column (wall_time_s): what must be equal
nowall() { sed 's/,[^,]*$//' "$1"; }
same_nowall() { cmp -s <(nowall "$1") <(nowall "$2") || { diff <(nowall "$1") <(nowall "$2") | head -5; return 1; }; }
# every line of a CSV has as many cells as its header
well_formed() { awk -F, 'NR == 1 { n = NF } NF != n { bad = 1 } END { exit bad }' "$1"; }

VARY=(--vary operator.speed=0.02:0.08:3 --vary controller.variant=none,ref-energy,improved)

# ---- usage: refused before anything runs, nothing written
expect_exit 0 "sweep --help" "$POPC" sweep --help
check "  --help shows the range syntax" grep -q "lo:hi:n:log" "$T/out"
expect_exit 2 "sweep without -o" "$POPC" sweep "$SCENE" "${VARY[@]}"
check "  says so" err_has "missing -o DIR"
expect_exit 2 "sweep without --vary" "$POPC" sweep "$SCENE" -o "$T/x"
expect_exit 2 "sweep without a scene" "$POPC" sweep -o "$T/x" "${VARY[@]}"
expect_exit 2 "value out of range" "$POPC" sweep "$SCENE" --vary encoder.resolution=1e-5,2 -o "$T/bad"
check "  names the key, the value and the range" err_has "encoder.resolution=1e-5,2, value 2 of 2 ('2')"
check "  ... the allowed range" err_has "allowed (0, 1] m"
check "  nothing ran: no directory" test ! -e "$T/bad"
expect_exit 2 "unknown key" "$POPC" sweep "$SCENE" --vary operator.nosuch=1 -o "$T/bad"
check "  names it" err_has "operator.nosuch"
expect_exit 2 "unknown variant" "$POPC" sweep "$SCENE" --vary controller.variant=none,fastest -o "$T/bad"
check "  names the variants" err_has "improved"
expect_exit 2 "bad range" "$POPC" sweep "$SCENE" --vary operator.speed=0.01:0.1 -o "$T/bad"
check "  shows the syntax" err_has "lo:hi:n or lo:hi:n:log"
expect_exit 2 "bad log range" "$POPC" sweep "$SCENE" --vary operator.speed=0:0.1:3:log -o "$T/bad"
expect_exit 2 "key given twice" "$POPC" sweep "$SCENE" --vary operator.speed=0.01 --vary operator.speed=0.02 -o "$T/bad"
expect_exit 2 "bad combination (ramp ends where it starts)" "$POPC" sweep "$SCENE" --vary operator.x0=-0.01,0.03 --vary operator.x_end=0.03 -o "$T/bad"
check "  names the run" err_has "run 0001 (operator.x0=0.03 operator.x_end=0.03)"
printf 't,x_d\n0,-0.01\n0.1,0.005\n' > "$T/xd.csv"
printf 't,x_d\n0,-0.01\n0.1,0.005\n0.05,0\n' > "$T/back.csv"
expect_exit 2 "a missing operator table" "$POPC" sweep "$SCENE" --set operator.intent=table --vary "operator.table=$T/xd.csv,$T/none.csv" -o "$T/bad"
check "  names the run and the file (not a failure of each run)" err_has "run 0001 (operator.table=$T/none.csv): $T/none.csv: cannot open table"
expect_exit 2 "a bad operator table, read by the runs of one intent only" "$POPC" sweep "$SCENE" --set "operator.table=$T/back.csv" --vary operator.intent=ramp,table -o "$T/bad"
check "  names the run, file:line and the times" err_has "run 0001 (operator.intent=table): $T/back.csv:4: time 0.05 does not increase"
expect_exit 0 "the base scene need not be valid alone (a table intent, its table varied)" "$POPC" sweep "$SCENE" --set operator.intent=table --set run.duration=0.2 --vary "operator.table=$T/xd.csv" -o "$T/tabs" -q
# relative --vary paths are from the working directory; each run's scene.ini
# names its table absolutely, so that it runs from any directory
printf 't,x_d\n0,-0.01\n0.1,0.002\n' > "$T/xd2.csv"
(cd "$T" && "$POPC" sweep "$SCENE" --set operator.intent=table --set run.duration=0.2 --vary operator.table=xd.csv,xd2.csv -o rel -q 2>"$T/err")
check "a sweep over relative table paths (exit $?)" test -s "$T/rel/summary.csv"
check "  the run's scene.ini names the table absolutely" grep -qx "table = $T/xd2.csv" "$T/rel/runs/0001/scene.ini"
expect_exit 0 "  and runs from another directory" env -C / "$POPC" run "$T/rel/runs/0001/scene.ini" -q
check "  summary.csv shows the values as given" test "$(tail -n +2 "$T/rel/summary.csv" | cut -d, -f2 | tr '\n' ' ')" = "xd.csv xd2.csv "
mkdir -p "$T/other" && cp "$T/xd.csv" "$T/xd2.csv" "$T/other/"
(cd "$T/other" && "$POPC" sweep "$SCENE" --set operator.intent=table --set run.duration=0.2 --vary operator.table=xd.csv,xd2.csv -o "$T/rel" -q 2>"$T/err")
check "  the same list from another directory is another sweep (exit $?)" err_has "holds another sweep"
expect_exit 2 "a key both fixed (--set) and varied" "$POPC" sweep "$SCENE" --set operator.speed=0.03 "${VARY[@]}" -o "$T/bad"
check "  names both" err_has "--set operator.speed=0.03 and --vary operator.speed=0.02:0.08:3: the key is both fixed and varied"
expect_exit 2 "--no-log with --list" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/bad" --list --no-log
check "  says why" err_has "--no-log does not apply to --list"
expect_exit 2 "-j with --list" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/bad" --list -j 2
check "  says what to do" err_has "give GNU parallel its own --jobs"
expect_exit 2 "--program without --list" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/bad" --program /bin/true
check "  says so" err_has "--program applies to --list only"
expect_exit 2 "an empty -o" "$POPC" sweep "$SCENE" "${VARY[@]}" -o ''
check "  says so" err_has "-o '': give a directory name"
touch "$T/afile"
expect_exit 2 "-o names a file: bad usage, before any work" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/afile"
check "  says so" err_has "-o $T/afile: $T/afile is a file, not a directory"
check "  the file is left as it was" test ! -s "$T/afile"
expect_exit 2 "a sweep over a real axis" "$POPC" sweep "$SCENE" --set "axis.map=$SRC/data/drives/generic.ini" --set axis.connect=tcp:127.0.0.1:1 --vary axis.kind=sim,modbus -o "$T/bad"
check "  names the run; nothing ran" err_has "run 0001 (axis.kind=modbus): axis.kind = modbus: a sweep runs the simulated axis only"
expect_exit 2 "bad --shard: past N" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/bad" --shard 3/2
check "  names the range" err_has "I must be a whole number in [1, 2]"
expect_exit 2 "--shard 0/2: shards count from 1" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/bad" --shard 0/2
check "  says so, with the spelling to use" err_has "shards count from 1, as in Playwright, Jest and node --test: --shard 1/2 ... --shard 2/2 make the whole sweep"
expect_exit 2 "bad -j" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/bad" -j 0
check "nothing was written by refused sweeps" test ! -e "$T/bad"

# ---- a small sweep with logs, two jobs
expect_exit 0 "3 x 3 sweep, -j 2" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/s" -j 2
S=$T/s/summary.csv
check "  header" test "$(head -1 "$S")" = "run,operator.speed,controller.variant,exit_status,ticks,pc_rms,pc_max,pc_active,pc_energy,w_minus_eref_min,w_minus_eref_end,vsign_rate,pc_rms_late,vsign_rate_late,integrator_error_m,port_energy_end,port_energy_min,po_error_end,po_error_max,device_energy_end,device_energy_min,rendered_stiffness,chatter_s,chatter_intervals,limit_cycle,wall_time_s"
check "  9 rows in id order" test "$(tail -n +2 "$S" | cut -d, -f1 | tr '\n' ' ')" = "0000 0001 0002 0003 0004 0005 0006 0007 0008 "
check "  last axis fastest" test "$(sed -n 3p "$S" | cut -d, -f2,3)" = "0.02,ref-energy"
check "  all succeeded" test "$(tail -n +2 "$S" | cut -d, -f4 | sort -u)" = "0"
check "  well formed" well_formed "$S"
check "  plain progress lines (not a terminal)" err_has "9/9 runs (100%)"
check "  run directory: log, scene, summary" test -s "$T/s/runs/0004/log.csv" -a -s "$T/s/runs/0004/scene.ini" -a -s "$T/s/runs/0004/summary.csv"
# (0.05 or, from a %.17g formatter, 0.050000000000000003: the same double)
check "  the run's scene holds its values" grep -q "^speed = 0\.050*[0-9]\?$" "$T/s/runs/0004/scene.ini"
check "  ... and its variant" grep -qx "variant = ref-energy" "$T/s/runs/0004/scene.ini"
check "  the run's summary is its row" test "$(tail -1 "$T/s/runs/0004/summary.csv")" = "$(grep '^0004,' "$S")"
check "  the plan names the vary lists" grep -qx "vary = operator.speed=0.02:0.08:3" "$T/s/sweep.plan"
# the seed's findings, as the sweep sees them: ref-energy chatters, improved does not
check "  ref-energy chatters (chatter_s > 0)" awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
	$3 == "ref-energy" && $c["chatter_s"] + 0 <= 0 { e = 1 } END { exit e }' "$S"
check "  improved does not" awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
	$3 == "improved" && $c["chatter_s"] + 0 != 0 { e = 1 } END { exit e }' "$S"

# the sweep's metrics are popc-analyze compare's, cell for cell, from the log
ANA=$BUILD/analysis/popc-analyze
if [ -x "$ANA" ]; then
  for id in 0001 0005 0006; do
    "$ANA" compare --format csv "$T/s/runs/$id/log.csv" > "$T/cmp.csv" 2>/dev/null
    check "  run $id: sweep row equals popc-analyze compare" awk -F, -v id="$id" '
      FNR == 1 { for (i = 1; i <= NF; i++) col[FILENAME, $i] = i; next }
      FILENAME == ARGV[1] { c = $0; next }
      $1 == id { r = $0 }
      END {
        n = split("pc_rms pc_rms_late pc_max pc_active pc_energy w_minus_eref_min w_minus_eref_end vsign_rate vsign_rate_late chatter_s chatter_intervals limit_cycle port_energy_end port_energy_min po_error_end po_error_max rendered_stiffness", k, " ")
        split(c, cc, ","); split(r, rr, ",")
        for (i = 1; i <= n; i++) if (cc[col[ARGV[1], k[i]]] != rr[col[ARGV[2], k[i]]]) { print "   " k[i] ": compare " cc[col[ARGV[1], k[i]]] ", sweep " rr[col[ARGV[2], k[i]]]; e = 1 }
        exit e
      }' "$T/cmp.csv" "$S"
  done
else
  echo "# popc-analyze not built: compare cross-check left out"
fi

# ---- resume: nothing runs again, the summary is unchanged
cp "$S" "$T/s1.csv"
expect_exit 0 "same sweep again" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/s" -j 2
check "  every run already done" err_has "9 of 9 runs already done"
check "  0 run now" err_has "0 run now"
check "  summary unchanged, byte for byte" cmp -s "$S" "$T/s1.csv"
expect_exit 2 "another sweep into the same directory" "$POPC" sweep "$SCENE" --vary operator.speed=0.01,0.02 -o "$T/s"
check "  refused: holds another sweep" err_has "holds another sweep"

# ---- runs too short for a verdict of the chatter detector: chatter_s and
# chatter_intervals empty below one 100 ms window (51 ticks), limit_cycle
# empty below half its 2 s window (501 ticks), never a 0 that reads as "no
# chatter"; filled at 1.5 s. Resume and merge keep the summary byte for byte;
# the --list runs (cells computed from their logs) give the same cells.
SHORT=(--set controller.variant=ref-energy --vary run.duration=0.05,0.5,1.5)
# cell SUMMARY ID COLUMN: the cell of run ID in the named column
cell() { awk -F, -v id="$2" -v name="$3" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $1 == id { print $c[name] }' "$1"; }
expect_exit 0 "a sweep of 0.05, 0.5 and 1.5 s runs" "$POPC" sweep "$SCENE" "${SHORT[@]}" -o "$T/short" -j 2 -q
SH=$T/short/summary.csv
check "  well formed" well_formed "$SH"
check "  0.05 s (51 ticks): chatter and limit-cycle cells empty" test "$(cell "$SH" 0000 ticks),$(cell "$SH" 0000 chatter_s),$(cell "$SH" 0000 chatter_intervals),$(cell "$SH" 0000 limit_cycle)" = "51,,,"
check "  0.5 s: chatter checked (0), limit_cycle empty" test "$(cell "$SH" 0001 chatter_s),$(cell "$SH" 0001 chatter_intervals),$(cell "$SH" 0001 limit_cycle)" = "0.0,0,"
check "  1.5 s: every cell filled" test -n "$(cell "$SH" 0002 chatter_s)" -a -n "$(cell "$SH" 0002 chatter_intervals)" -a -n "$(cell "$SH" 0002 limit_cycle)"
check "  the run's summary is its row" test "$(tail -1 "$T/short/runs/0000/summary.csv")" = "$(grep '^0000,' "$SH")"
if [ -x "$ANA" ]; then
  for id in 0000 0001 0002; do
    "$ANA" compare --format csv "$T/short/runs/$id/log.csv" > "$T/cmp.csv" 2>/dev/null
    # (compare names the row after the log's file: log)
    check "  run $id: chatter cells as popc-analyze compare's" test \
      "$(cell "$T/cmp.csv" log ticks):$(cell "$T/cmp.csv" log chatter_s),$(cell "$T/cmp.csv" log chatter_intervals),$(cell "$T/cmp.csv" log limit_cycle)" = \
      "$(cell "$SH" "$id" ticks):$(cell "$SH" "$id" chatter_s),$(cell "$SH" "$id" chatter_intervals),$(cell "$SH" "$id" limit_cycle)"
  done
fi
cp "$SH" "$T/short1.csv"
expect_exit 0 "  the same sweep again" "$POPC" sweep "$SCENE" "${SHORT[@]}" -o "$T/short" -j 2 -q
check "  summary unchanged, byte for byte" cmp -s "$SH" "$T/short1.csv"
expect_exit 0 "  merge into another directory" "$POPC" sweep merge "$T/short" -o "$T/shortm"
check "  merged summary equal, byte for byte" cmp -s "$T/shortm/summary.csv" "$T/short1.csv"
"$POPC" sweep "$SCENE" "${SHORT[@]}" -o "$T/shortl" --list > "$T/shortl.jobs" 2>"$T/err"
check "  --list: 3 popc run lines" test "$(grep -c ' run ' "$T/shortl.jobs")" -eq 3
sh "$T/shortl.jobs" > /dev/null 2>&1
expect_exit 0 "  merge of the --list runs" "$POPC" sweep merge "$T/shortl"
check "  equal to the in-process sweep (but wall time)" same_nowall "$T/shortl/summary.csv" "$SH"

# ---- a run's own summary.csv that cannot be written (a directory stands at
# its path: rename() fails, as root too): the run keeps its row in the sweep,
# and the failure is reported
mkdir -p "$T/cp/runs/0004/summary.csv"
expect_exit 1 "a run's summary.csv that cannot be written" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/cp" -j 2
check "  names it and why" err_has "$T/cp/runs/0004/summary.csv: Is a directory (the run's copy of its row; the row itself is recorded in the sweep)"
check "  every run has its result (none 'not run')" err_has "9 runs, 9 succeeded, 0 failed, 0 not run"
check "  the same summary as the one-machine sweep" same_nowall "$T/cp/summary.csv" "$S"
expect_exit 0 "  again: nothing left to run" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/cp" -j 2
check "  9 of 9 runs already done" err_has "9 of 9 runs already done"

# ---- rows files left by an earlier process of the same pid (pids repeat in
# containers and across Slurm nodes): one killed mid-row, one killed
# mid-header. The hook names the new rows files after that pid; both workers
# (-j 2) get it, so they collide with each other too. Each must write a file
# of its own: a row appended to the cut line would be lost, rows appended to
# the cut header would make the file unreadable.
expect_exit 0 "shard 1/3 of the sweep, to resume" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/p" --shard 1/3 --no-log -q
H=$(hostname | tr / _)
{ head -1 "$S"; printf '0004,0.05,ref-en'; } > "$T/p/rows/$H.4242.csv"
head -c 20 "$S" > "$T/p/rows/$H.4242.1.csv"
# what popc before this fix made of a cut header: the whole header glued to it
{ head -c 25 "$S"; head -1 "$S"; grep '^0007,' "$S"; } > "$T/p/rows/$H.777.csv"
cp "$T/p/rows/$H.4242.csv" "$T/cut-row.csv"; cp "$T/p/rows/$H.4242.1.csv" "$T/cut-header.csv"
expect_exit 0 "resume with rows files of the same pid left cut" env POPC_SWEEP_TEST_ROWS_PID=4242 "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/p" -j 2 --no-log
check "  every run once, in order" test "$(tail -n +2 "$T/p/summary.csv" | cut -d, -f1 | tr '\n' ' ')" = "0000 0001 0002 0003 0004 0005 0006 0007 0008 "
check "  the same results as the one-machine sweep" same_nowall "$T/p/summary.csv" "$S"
check "  the cut files are left as they were" cmp -s "$T/p/rows/$H.4242.csv" "$T/cut-row.csv"
check "  ... both" cmp -s "$T/p/rows/$H.4242.1.csv" "$T/cut-header.csv"
check "  the workers wrote files of their own" test -s "$T/p/rows/$H.4242.2.csv" -a -s "$T/p/rows/$H.4242.3.csv"
check "  a note names the cut header" err_has "$H.4242.1.csv: a rows file whose header was cut"
check "  the glued header is read" err_has "and 1 more rows files with a note"
expect_exit 0 "merge reads the directory too" "$POPC" sweep merge "$T/p" -o "$T/pm"
check "  equal" same_nowall "$T/pm/summary.csv" "$S"

# ---- --no-log: summaries only
expect_exit 0 "--no-log sweep, -j 1" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/n" -j 1 --no-log -q
check "  -q: nothing on stderr" test ! -s "$T/err"
check "  no run directories" test -z "$(ls "$T/n/runs")"
check "  same results as with logs and 2 jobs" same_nowall "$T/n/summary.csv" "$S"

# ---- failed runs: the others go on, the sweep says which, resume retries them
FAIL=(--set integrator.method=euler --set integrator.substeps=1 --vary environment.stiffness=1000,1e8,2000)
expect_exit 1 "sweep with an unstable run" "$POPC" sweep "$SCENE" "${FAIL[@]}" -o "$T/f" --no-log -j 2
check "  lists the failed run with its values" err_has "0001 (environment.stiffness=1e8): exit 6: closed loop diverged"
check "  the others succeeded" test "$(cut -d, -f1,3 "$T/f/summary.csv" | tr '\n' ' ')" = "run,exit_status 0000,0 0001,6 0002,0 "
check "  well formed" well_formed "$T/f/summary.csv"
expect_exit 1 "again: the failed run is retried, the others skipped" "$POPC" sweep "$SCENE" "${FAIL[@]}" -o "$T/f" --no-log -j 2
check "  2 of 3 already done" err_has "2 of 3 runs already done"
check "  1 run now" err_has "1 run now"
check "  still one row per run" test "$(wc -l < "$T/f/summary.csv")" -eq 4

# ---- shards: no overlap, together the whole sweep; merge equals one machine
# shards count from 1 (Playwright, Jest, node --test): 1/3, 2/3, 3/3
for i in 1 2 3; do
  expect_exit 0 "shard $i/3" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/sh$i" --shard $i/3 --no-log -q
done
check "  shard 2/3 has runs 1, 4, 7" test "$(tail -n +2 "$T/sh2/summary-shard-2-of-3.csv" | cut -d, -f1 | tr '\n' ' ')" = "0001 0004 0007 "
check "  shard 1/3 has runs 0, 3, 6" test "$(tail -n +2 "$T/sh1/summary-shard-1-of-3.csv" | cut -d, -f1 | tr '\n' ' ')" = "0000 0003 0006 "
expect_exit 0 "merge 3 shard directories" "$POPC" sweep merge "$T/sh1" "$T/sh2" "$T/sh3" -o "$T/m"
check "  merged summary equals the one-machine sweep (but wall time)" same_nowall "$T/m/summary.csv" "$S"
expect_exit 1 "merge of two of three shards" "$POPC" sweep merge "$T/sh1" "$T/sh3" -o "$T/m2"
check "  says 3 runs have no result" err_has "3 without a result"
expect_exit 2 "merge of different sweeps" "$POPC" sweep merge "$T/sh1" "$T/f"
# --shard 1/2 and --shard 2/2 make the whole sweep, into one directory
for i in 1 2; do
  expect_exit 0 "--shard $i/2 into one directory" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/half" --shard $i/2 --no-log -q
done
expect_exit 0 "  merge: every run has a result" "$POPC" sweep merge "$T/half"
check "  equals the one-machine sweep" same_nowall "$T/half/summary.csv" "$S"
# the Slurm array variables pick the shard, several shards share one
# directory; the array's first task is shard 1 whatever its index
# (--array=0-1 and --array=1-2 alike)
for first in 0 1; do
  for k in 0 1; do
    id=$((first + k))
    expect_exit 0 "Slurm array task $id of --array=$first-$((first + 1))" env SLURM_ARRAY_TASK_ID=$id SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_MIN=$first SLURM_ARRAY_TASK_STEP=1 \
      "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/sl$first" --no-log -q
  done
  check "  shard summaries named after the shard, from 1" test -s "$T/sl$first/summary-shard-1-of-2.csv" -a -s "$T/sl$first/summary-shard-2-of-2.csv" -a ! -e "$T/sl$first/summary-shard-0-of-2.csv"
  expect_exit 0 "merge the shared directory" "$POPC" sweep merge "$T/sl$first"
  check "  equals the one-machine sweep" same_nowall "$T/sl$first/summary.csv" "$S"
done
check "  --array=1-2's first task ran what --shard 1/2 runs" cmp -s <(nowall "$T/sl1/summary-shard-1-of-2.csv") <(nowall "$T/half/summary-shard-1-of-2.csv")
expect_exit 2 "Slurm array that is not regular" env SLURM_ARRAY_TASK_ID=7 SLURM_ARRAY_TASK_COUNT=2 \
  "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/sl2" --no-log -q
check "  says how to submit" err_has "--array=1-2"

# ---- which popc made a sweep: recorded in the plan; a resume or merge by
# another build is refused unless --allow-other-build, and then recorded.
# "Another build" is made here by editing the plan's popc_build line, as a
# sweep directory made by another popc has it.
VERSION=$("$POPC" --version | sed -n 's/^popc \([^ ]*\) (build \(.*\))$/\1/p')
BUILD_ID=$("$POPC" --version | sed -n 's/^popc \([^ ]*\) (build \(.*\))$/\2/p')
check "popc --version names version and build ('$VERSION', '$BUILD_ID')" test -n "$VERSION" -a -n "$BUILD_ID"
check "  the plan records the version" grep -qx "popc_version = $VERSION" "$T/s/sweep.plan"
check "  the plan records the build" grep -qx "popc_build = $BUILD_ID" "$T/s/sweep.plan"
# resign PLAN: the plan's digest line made again after an edit, as the popc
# that made such a plan wrote it (FNV-1a 64 of the lines above it)
resign() { python3 - "$1" <<'PY'
import sys
p = sys.argv[1]
lines = open(p, 'rb').read().split(b'\n')
body = b''.join(l + b'\n' for l in lines if l and not l.startswith(b'digest = '))
h = 0xcbf29ce484222325
for b in body:
    h = ((h ^ b) * 0x100000001b3) & 0xffffffffffffffff
open(p, 'wb').write(body + b'digest = %016x\n' % h)
PY
}
cp -r "$T/s" "$T/ob"
sed -i 's/^popc_build = .*/popc_build = other-build-1/' "$T/ob/sweep.plan"
resign "$T/ob/sweep.plan"
expect_exit 2 "resume of a sweep another build made" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/ob"
check "  names both builds" err_has "this sweep was made by popc $VERSION (build other-build-1); this is popc $VERSION (build $BUILD_ID)"
check "  says how to go on" err_has "--allow-other-build"
check "  the plan is left as it was" test "$(grep -c also_built_by "$T/ob/sweep.plan")" -eq 0
expect_exit 0 "  --allow-other-build resumes it" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/ob" --allow-other-build
check "  with a note" err_has "was made by another popc build; resuming with popc $VERSION (build $BUILD_ID)"
check "  the plan records the second build" grep -qx "also_built_by = popc $VERSION (build $BUILD_ID)" "$T/ob/sweep.plan"
check "  the first build stays the plan's maker" grep -qx "popc_build = other-build-1" "$T/ob/sweep.plan"
expect_exit 0 "  again" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/ob" --allow-other-build -q
check "  the second build noted once" test "$(grep -c also_built_by "$T/ob/sweep.plan")" -eq 1
expect_exit 0 "the same build resumes without the option" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/s" -q
# a plan of a popc before build ids (no popc_version, popc_build lines)
cp -r "$T/s" "$T/old"
# (nor a digest, which came later still)
sed -i '/^popc_version = /d; /^popc_build = /d; /^digest = /d' "$T/old/sweep.plan"
expect_exit 2 "resume of a plan that records no build" "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/old"
check "  says so" err_has "made by a popc that recorded no version or build (before build ids)"
# merge: shards of two builds
cp -r "$T/sh2" "$T/sh2o"
sed -i 's/^popc_build = .*/popc_build = other-build-2/' "$T/sh2o/sweep.plan"
resign "$T/sh2o/sweep.plan"
expect_exit 2 "merge of shards of two builds" "$POPC" sweep merge "$T/sh1" "$T/sh2o" "$T/sh3" -o "$T/mo"
check "  names both builds" err_has "$T/sh1 was made by popc $VERSION (build $BUILD_ID), $T/sh2o by popc $VERSION (build other-build-2)"
check "  nothing written" test ! -e "$T/mo"
expect_exit 0 "  --allow-other-build merges them" "$POPC" sweep merge "$T/sh1" "$T/sh2o" "$T/sh3" -o "$T/mo" --allow-other-build
check "  equal to the one-machine sweep" same_nowall "$T/mo/summary.csv" "$S"
check "  the merged plan records both builds" grep -qx "also_built_by = popc $VERSION (build other-build-2)" "$T/mo/sweep.plan"
check "  ... and its maker" grep -qx "popc_build = $BUILD_ID" "$T/mo/sweep.plan"

# ---- a sweep caught in a run: SIGINT to the sweep, or SIGKILL or SIGTERM to
# the worker that has the run in hand. Not timed: the runs follow operator
# tables, one file each, and run 0010's table is a FIFO. The sweep's planner
# reads it first (fed once); the worker that takes run 0010 then opens it
# and the test's holder, opening the other end, returns only then: that
# worker has run 0010 in hand. The holder writes nothing, so the worker
# blocks reading until a signal interrupts the read (no byte read: EINTR),
# and the holder goes only after the sweep has ended. So the signal always
# lands in the middle of the sweep, with run 0010 in that worker's hand,
# whatever the machine's speed. Three states are awaited by looking at /proc
# (every 10 ms, 10 s at most; they come within microseconds): the planner
# has closed the FIFO (it reads to the end of the feed, and a holder that
# opened before would be a writer again and keep it waiting); the holder's
# open returns when the worker's open meets it, before the worker's
# descriptor exists, so the worker is found once it holds the FIFO; and the
# signal is sent once the worker is blocked reading it (a signal that came
# between its open and its read would leave it reading, stop flag set,
# until the holder goes). (It was an 8000-run sweep signalled after
# its first progress line in the hope that it was still going, and three
# more run to the end: 187-313 s of the sanitized build.) Once the worker
# has it open, the FIFO's path becomes a plain copy of the table: the run
# made again (a retry, a resume) reads that.
TAB=$T/tab
mkdir -p "$TAB"
printf 't,x_d\n0,-0.01\n0.1,-0.01\n0.5,0.004\n' > "$TAB/table.csv"
tables=
# (names relative to $TAB, where the sweeps run: a --vary list is bounded)
for i in $(seq -w 0 19); do cp "$TAB/table.csv" "$TAB/$i.csv"; tables=$tables${tables:+,}$i.csv; done
MID=(--set operator.intent=table --set run.duration=0.5 --vary "operator.table=$tables" --no-log)
mid() { (cd "$TAB" && "$@"); }
# holds PID PATH: process PID has PATH open
holds() { local f; for f in /proc/$1/fd/*; do [ "$(readlink "$f" 2>/dev/null)" = "$2" ] && return 0; done; return 1; }
# caught DIR JOBS [ENV...]: starts the MID sweep into DIR with -j JOBS (1i,
# 2i: -j 1 or 2 --isolate, workers only) (stderr in $T/err) and returns once
# a worker has run 0010 in hand: sets pid (the sweep), worker (the process
# reading the FIFO: a child, or the sweep itself, which makes runs beside its
# workers without --isolate) and holder.
caught() {
  local dir=$1 jobs=$2 line c f; shift 2
  local jobs_args=(-j "$jobs"); [ "${jobs%i}" != "$jobs" ] && jobs_args=(-j "${jobs%i}" --isolate)
  rm -f "$TAB/10.csv" "$T/held"; mkfifo "$TAB/10.csv" "$T/held"
  cd "$TAB" && { env "$@" "$POPC" sweep "$SCENE" "${MID[@]}" -o "$dir" "${jobs_args[@]}" 2>"$T/err" & }
  pid=$!
  cd - >/dev/null
  # the planner's read (bounded: a sweep that never planned must not hang the test)
  timeout 60 sh -c 'cat "$1" > "$2"' feed "$TAB/table.csv" "$TAB/10.csv"
  local n=0
  while holds "$pid" "$TAB/10.csv" && [ $((n += 1)) -le 1000 ]; do sleep 0.01; done
  # the holder: opens the FIFO for writing (so returns once the worker has
  # opened it), says so, writes nothing; for 60 s at most, so that a sweep
  # that ignored its signal fails (an empty table) instead of hanging
  bash -c 'exec 7>"$1"; echo open; exec sleep 60' holder "$TAB/10.csv" >"$T/held" &
  holder=$!
  worker= line=
  read -r -t 60 line <"$T/held"
  local fd=
  n=0
  while [ "$line" = open ] && [ -z "$worker" ] && [ $((n += 1)) -le 1000 ]; do
    for c in $pid $(cat /proc/$pid/task/*/children 2>/dev/null); do
      for f in /proc/$c/fd/*; do
        [ "$(readlink "$f" 2>/dev/null)" = "$TAB/10.csv" ] && { worker=$c; fd=${f##*/}; }
      done
    done
    [ -n "$worker" ] || sleep 0.01
  done
  # blocked in a system call on that descriptor (its first argument): the read
  n=0
  while [ -n "$worker" ] && [ "$(cut -d' ' -f2 "/proc/$worker/syscall" 2>/dev/null)" != "$(printf '0x%x' "$fd")" ]; do
    [ $((n += 1)) -le 1000 ] || { worker=; break; }
    sleep 0.01
  done
  rm -f "$TAB/10.csv"; cp "$TAB/table.csv" "$TAB/10.csv"
}
# release: waits for the sweep (sets rc), then lets the holder go
release() { wait "$pid"; rc=$?; pid=; kill "$holder" 2>/dev/null; wait "$holder" 2>/dev/null; }
# failed_ids SUMMARY: the ids of the runs whose exit_status is not 0
failed_ids() { awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["exit_status"] != 0 { printf "%s ", $1 }' "$1"; }
id_col() { tail -n +2 "$1" | cut -d, -f1 | tr '\n' ' '; }
expect_exit 0 "the uninterrupted reference sweep (20 tables)" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/ref" -j 2 -q
check "  20 rows, all succeeded" test "$(id_col "$T/ref/summary.csv"),$(failed_ids "$T/ref/summary.csv")" = "$(seq -f '%04g' -s ' ' 0 19) ,"

# SIGINT to the sweep alone: it passes it on to its workers, stops, keeps a
# whole summary; a second run completes the sweep
caught "$T/i" 2
check "SIGINT: a worker has run 0010 in hand (pid ${worker:-none})" test -n "$worker"
kill -INT "$pid"
release
check "  exit 5 (got $rc)" test "$rc" -eq 5
check "  says how to resume" err_has "run the same command again to resume"
n_done=$(($(wc -l < "$T/i/summary.csv") - 1))
check "  a whole summary of the finished runs ($n_done of 20)" test "$n_done" -gt 0 -a "$n_done" -lt 20
check "  run 0010, interrupted, has no row" bash -c "! grep -q '^0010,' '$T/i/summary.csv'"
check "  well formed" well_formed "$T/i/summary.csv"
check "  no temporary files left" test -z "$(find "$T/i" -name '*.tmp.*')"
expect_exit 0 "the same sweep again completes it" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/i" -j 2 -q
check "  20 rows, each run once, in order" test "$(id_col "$T/i/summary.csv")" = "$(id_col "$T/ref/summary.csv")"
check "  equal to the uninterrupted sweep (but wall time)" same_nowall "$T/i/summary.csv" "$T/ref/summary.csv"

# ---- a worker that dies: its run is recorded as failed, the sweep goes on
# SIGKILL (as the OOM killer): a sanitizer build turns SIGSEGV into exit 1.
# --isolate: without it the sweep's own process may be the one making run
# 0010 (it makes runs beside its worker), and SIGKILL there ends the sweep
caught "$T/k" 2i
check "a worker killed by SIGKILL with run 0010 in hand (pid ${worker:-none})" test -n "$worker"
[ -n "$worker" ] && kill -KILL "$worker"
release
check "  names the signal" err_has "died of signal 9"
check "  exactly run 0010 failed (failed: $(failed_ids "$T/k/summary.csv"))" test "$(failed_ids "$T/k/summary.csv")" = "0010 "
check "  every run has a row" test "$(id_col "$T/k/summary.csv")" = "$(id_col "$T/ref/summary.csv")"
check "  exit 1 (got $rc)" test "$rc" -eq 1
expect_exit 0 "again: the crashed run is retried" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/k" -j 2 -q
check "  all 20 succeeded, as in the uninterrupted sweep" same_nowall "$T/k/summary.csv" "$T/ref/summary.csv"
# -j 1 --isolate: the one worker holds the rows of runs 0000-0009 for one
# write (summaries only); killed, it loses them unwritten, and they are made
# again
caught "$T/k1" 1i
check "-j 1 --isolate: the worker killed by SIGKILL with run 0010 in hand (pid ${worker:-none}, sweep $pid)" test -n "$worker" -a "$worker" != "$pid"
[ -n "$worker" ] && kill -KILL "$worker"
release
check "  the ten runs whose rows it held run again" err_has "10 runs taken by a worker that stopped before recording them: running them again"
check "  exactly run 0010 failed (failed: $(failed_ids "$T/k1/summary.csv"))" test "$(failed_ids "$T/k1/summary.csv")" = "0010 "
check "  every run has a row, once" test "$(id_col "$T/k1/summary.csv")" = "$(id_col "$T/ref/summary.csv")"
check "  exit 1 (got $rc)" test "$rc" -eq 1

# -j 1 makes its runs in the sweep's own process: SIGKILL there ends the
# sweep; the held rows (0000-0009) are lost unwritten, nothing recorded is;
# the same command again makes them and the rest
caught "$T/kh" 1
check "-j 1: the sweep itself has run 0010 in hand (pid ${worker:-none})" test -n "$worker" -a "$worker" = "$pid"
[ -n "$worker" ] && kill -KILL "$worker"
release
check "  killed (exit $rc)" test "$rc" -eq 137
check "  no row was written yet (held)" test "$(cat "$T/kh"/rows/*.csv | grep -c '^00')" -eq 0
expect_exit 0 "  the same command again" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/kh" -j 1 -q
check "  all 20 succeeded, as in the uninterrupted sweep" same_nowall "$T/kh/summary.csv" "$T/ref/summary.csv"

# SIGTERM to one worker, not the sweep: it stops its run unrecorded and ends;
# a new worker takes over the runs after 0010, and 0010 runs again at the
# end. With -j 1 --isolate the sweep would otherwise have no worker left.
for j in 1i 2i; do
  caught "$T/t$j" $j
  check "-j $j: a worker sent SIGTERM alone with run 0010 in hand (pid ${worker:-none})" test -n "$worker" -a "$worker" != "$pid"
  [ -n "$worker" ] && kill -TERM "$worker"
  release
  check "  the sweep completes, exit 0 (got $rc)" test "$rc" -eq 0
  check "  says a new worker took over" err_has "stopped by a signal sent to it alone"
  check "  ... and that run 0010 runs again" err_has "1 run taken by a worker that stopped before recording it: running it again"
  check "  every run has a row, once, all as in the uninterrupted sweep" same_nowall "$T/t$j/summary.csv" "$T/ref/summary.csv"
done
# -j 1: SIGTERM to the sweep (its runs' process): stopped, resumable
caught "$T/th" 1
[ -n "$worker" ] && kill -TERM "$worker"
release
check "-j 1: SIGTERM with run 0010 in hand: exit 5 (got $rc)" test "$rc" -eq 5
check "  says how to resume" err_has "run the same command again to resume"
check "  the ten runs before are in its summary" test "$(id_col "$T/th/summary.csv")" = "$(seq -f '%04g' -s ' ' 0 9) "
expect_exit 0 "  the same command again completes it" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/th" -j 1 -q
check "  all 20 succeeded, as in the uninterrupted sweep" same_nowall "$T/th/summary.csv" "$T/ref/summary.csv"

# A run that crashes (the test hook calls abort() in its place). With a
# worker: the worker dies, the run is recorded as failed, the sweep goes on.
# -j 1, runs in the sweep's process: the crash handler writes the held rows
# and starts popc again as --isolate, which makes the run in a worker (where
# it crashes again and is recorded) and the rest.
ulimit -c 0
same_nowall_but() { cmp -s <(nowall "$1" | grep -v "^$3,") <(nowall "$2" | grep -v "^$3,"); }
for j in 1i 2i 2 1; do
  jobs_args=(-j "${j%i}"); [ "${j%i}" != "$j" ] && jobs_args=(-j "${j%i}" --isolate)
  expect_exit 1 "-j $j: run 0010 crashes" mid env POPC_SWEEP_TEST_CRASH_AT=10 "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/x$j" "${jobs_args[@]}"
  check "  exactly run 0010 failed (failed: $(failed_ids "$T/x$j/summary.csv"))" test "$(failed_ids "$T/x$j/summary.csv")" = "0010 "
  check "  its reason names the signal" err_has "0010 (operator.table=10.csv): exit 1: the worker process died of signal 6 (Aborted)"
  check "  every run has a row, once; the others as in the uninterrupted sweep" same_nowall_but "$T/x$j/summary.csv" "$T/ref/summary.csv" 0010
  check "  20 rows" test "$(id_col "$T/x$j/summary.csv")" = "$(id_col "$T/ref/summary.csv")"
done
check "  -j 1: says the sweep's process crashed, and goes on" err_has "run 0010 crashed (signal 6, Aborted) in the sweep's own process (-j 1); the rows so far are written; going on with a worker process (as --isolate)"
check "  -j 1: the rows of the runs before it were written by the crashed process" err_has "10 of 20 runs already done"
check "  -j 1: the process started again has the crashed one's pid (a rows file .N of it)" test -n "$(ls "$T/x1/rows" | grep -E '^[^.]+[.][0-9]+[.]1[.]csv$')"

# -j 2 makes runs in the sweep's own process beside one worker. A crash
# there (SIGABRT sent to it, handled as abort(): a sanitizer build keeps
# SIGSEGV for itself) kills and reaps the worker before popc starts again
# (a worker outlives an execve of its parent, and would go on writing rows
# into the directory the new popc resumes); the new popc makes the runs
# that were in hand, or held unwritten, again, with workers only.
caught "$T/b" 2
kids=$(cat /proc/$pid/task/*/children 2>/dev/null)
check "-j 2: the sweep ($pid) has a worker beside it ($(echo $kids))" test -n "$kids"
kill -ABRT "$pid"
# readiness lines: the handler's, then the new popc's resume line (not
# waited for once the sweep has ended: a popc that did not survive the crash)
running() { local st; st=$(cut -d' ' -f3 "/proc/$1/stat" 2>/dev/null) && [ "$st" != Z ]; }
n=0
until grep -q "runs already done" "$T/err" 2>/dev/null || ! running "$pid" ||
  [ $((n += 1)) -gt 1000 ]; do sleep 0.01; done
check "  says the sweep's process crashed beside its workers, now stopped" err_has "crashed (signal 6, Aborted) in the sweep's own process, beside its workers (now stopped); the rows so far are written; going on with worker processes only (as --isolate)"
alive=; for c in $kids; do kill -0 "$c" 2>/dev/null && alive="$alive $c"; done
check "  the worker ended and was reaped before popc started again (alive:${alive:- none})" test -z "$alive"
release
check "  the sweep completes, exit 0 (got $rc)" test "$rc" -eq 0
check "  every run has a row, once, all as in the uninterrupted sweep" same_nowall "$T/b/summary.csv" "$T/ref/summary.csv"
check "  no run has two rows in the rows files" test "$(cat "$T/b"/rows/*.csv | grep -c '^00')" -eq 20

# A worker that dies between taking a run and saying so in its slot (the test
# hook makes the narrow window certain): the parent finds the taken run
# without a row at the end and runs it again.
for j in 1 2; do
  expect_exit 0 "-j $j: a worker dies just after taking run 0004" env POPC_SWEEP_TEST_DIE_AFTER_CLAIM=4 "$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/c$j" -j $j --no-log
  check "  runs it again" err_has "1 run taken by a worker that stopped before recording it: running it again"
  check "  every run once, all as in the one-machine sweep" same_nowall "$T/c$j/summary.csv" "$S"
done

check_summary
