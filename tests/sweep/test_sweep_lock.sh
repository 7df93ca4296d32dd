#!/usr/bin/env bash
# One sweep per directory (issue 28): a sweep holds DIR/sweep.lock (flock)
# for its life; a second sweep, a resume or a map into DIR meanwhile is
# refused with exit 7, naming the holder's pid, and writes nothing; shards of
# one sweep share DIR; merge reads beside a running sweep. Workers end with
# their sweep (PR_SET_PDEATHSIG): SIGKILL to the sweep leaves no worker
# making runs, and a worker that outlives it (stopped) keeps the lock, so a
# resume never runs beside it.
#
# Not timed: the first sweep is paused by an event. Its runs follow operator
# tables, one file each, and run 0010's table is a FIFO (as in
# test_sweep_cli.sh): the planner reads it first (fed once), then the process
# that takes run 0010 opens it, and the test's holder, opening the other end,
# says "open" only then. From then on the sweep holds its lock (taken before
# any run) and stays in run 0010 until the holder is told to write the table.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/paper.ini
T=$(mktemp -d /tmp/popc-sweep-lock-XXXXXX)
pid= holder=
cleanup() {
  [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null
  [ -n "$holder" ] && kill "$holder" 2>/dev/null
  [ -n "${stopped:-}" ] && kill -CONT "$stopped" 2>/dev/null
  rm -rf "$T"
}
trap cleanup EXIT
. "$SRC/tests/check.sh"
nowall() { sed 's/,[^,]*$//' "$1"; }
same_nowall() { cmp -s <(nowall "$1") <(nowall "$2") || { diff <(nowall "$1") <(nowall "$2") | head -5; return 1; }; }
id_col() { tail -n +2 "$1" | cut -d, -f1 | tr '\n' ' '; }
rows_of() { cat "$1"/rows/*.csv 2>/dev/null | grep -c '^00'; }

TAB=$T/tab
mkdir -p "$TAB"
printf 't,x_d\n0,-0.01\n0.1,-0.01\n0.5,0.004\n' > "$TAB/table.csv"
tables=
for i in $(seq -w 0 19); do cp "$TAB/table.csv" "$TAB/$i.csv"; tables=$tables${tables:+,}$i.csv; done
MID=(--set operator.intent=table --set run.duration=0.5 --vary "operator.table=$tables" --no-log -q)
mid() { (cd "$TAB" && "$@"); }
# holds PID PATH: process PID has PATH open
holds() { local f; for f in /proc/$1/fd/*; do [ "$(readlink "$f" 2>/dev/null)" = "$2" ] && return 0; done; return 1; }
# gone PID...: waits (polled, 10 s at most) until none of the processes exists
gone() { local p n=0; for p in "$@"; do while [ -e "/proc/$p" ] && ! grep -q '^State:.*Z' "/proc/$p/status" 2>/dev/null; do
  [ $((n += 1)) -le 1000 ] || return 1; sleep 0.01; done; done; }

# paused DIR ARGS...: starts the MID sweep into DIR with ARGS (stderr in
# $T/err1) and returns once the process making run 0010 has its table open:
# sets pid (the sweep), worker (that process) and holder; the holder writes
# the table when told (go).
paused() {
  local dir=$1 c f n=0 line=; shift
  rm -f "$TAB/10.csv" "$T/held" "$T/go"; mkfifo "$TAB/10.csv" "$T/held" "$T/go"
  cd "$TAB" && { "$POPC" sweep "$SCENE" "${MID[@]}" -o "$dir" "$@" 2>"$T/err1" & }
  pid=$!
  cd - >/dev/null
  timeout 60 sh -c 'cat "$1" > "$2"' feed "$TAB/table.csv" "$TAB/10.csv"
  while holds "$pid" "$TAB/10.csv" && [ $((n += 1)) -le 1000 ]; do sleep 0.01; done
  bash -c 'exec 7>"$1"; echo open; read -r go <"$2"; cat "$3" >&7' holder "$TAB/10.csv" "$T/go" "$TAB/table.csv" >"$T/held" &
  holder=$!
  read -r -t 60 line <"$T/held"
  worker= n=0
  while [ "$line" = open ] && [ -z "$worker" ] && [ $((n += 1)) -le 1000 ]; do
    for c in $pid $(cat /proc/$pid/task/*/children 2>/dev/null); do
      holds "$c" "$TAB/10.csv" && worker=$c
    done
    [ -n "$worker" ] || sleep 0.01
  done
  # the path becomes a plain table again: a run made again reads that
  rm -f "$TAB/10.csv"; cp "$TAB/table.csv" "$TAB/10.csv"
}
# go: the holder writes run 0010's table; waits for the sweep (sets rc)
go() { echo go > "$T/go"; wait "$holder"; holder=; wait "$pid"; rc=$?; pid=; }

expect_exit 0 "the reference sweep (20 tables)" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/ref" -j 2
check "  20 rows" test "$(id_col "$T/ref/summary.csv")" = "$(seq -f '%04g' -s ' ' 0 19) "

# ---- the lock held by another process (util-linux flock, as any tool may)
mkdir -p "$T/f"
exec 9<>"$T/f/sweep.lock"
flock -x 9
printf '%20d\n' 424242 >&9
expect_exit 7 "a sweep into a directory whose lock another process holds" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/f"
check "  names the lock file and the holder's pid" err_has "$T/f/sweep.lock: $T/f is in use by another popc sweep or map (pid 424242"
check "  nothing written: no plan, no rows" test ! -e "$T/f/sweep.plan" -a ! -e "$T/f/rows"
exec 9>&-
expect_exit 0 "  once it is released, the sweep runs" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/f" -j 2
check "  every run once" same_nowall "$T/f/summary.csv" "$T/ref/summary.csv"

# ---- two sweeps at once: the second is refused, the first completes
for j in 2 1; do
  paused "$T/two$j" -j $j
  check "-j $j: the first sweep is in run 0010 (pid ${worker:-none})" test -n "$worker"
  n_rows=$(rows_of "$T/two$j")
  expect_exit 7 "  the same sweep started again meanwhile" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/two$j" -j 2
  check "  names the first sweep's pid" err_has "(pid $pid, or a worker process it started)"
  check "  made no run (rows $n_rows, then $(rows_of "$T/two$j"))" test "$(rows_of "$T/two$j")" -eq "$n_rows"
  check "  wrote no rows file" test "$(ls "$T/two$j/rows" | wc -l)" -le $j
  expect_exit 7 "  a map into it meanwhile" "$POPC" map "$SCENE" --variant none --stiffness 1000:2000 -o "$T/two$j" -q
  expect_exit 1 "  merge reads it meanwhile (whole rows; runs not made yet have no result)" "$POPC" sweep merge "$T/two$j" -o "$T/two$j-m"
  check "  the merged summary is whole" awk -F, 'NR == 1 { n = NF } NF != n { bad = 1 } END { exit bad }' "$T/two$j-m/summary.csv"
  go
  check "  the first sweep completes, exit 0 (got $rc)" test "$rc" -eq 0
  check "  every run once, as the reference" same_nowall "$T/two$j/summary.csv" "$T/ref/summary.csv"
  check "  every run has exactly one row in the rows files ($(rows_of "$T/two$j"))" test "$(rows_of "$T/two$j")" -eq 20
done

# ---- shards of one sweep share the directory; the same shard twice does not
paused "$T/sh" --shard 1/2 -j 1
check "shard 1/2 is in run 0010 (pid ${worker:-none})" test -n "$worker"
expect_exit 0 "  shard 2/2 into the same directory meanwhile" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/sh" --shard 2/2
expect_exit 7 "  shard 1/2 again meanwhile" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/sh" --shard 1/2
check "  names the shard's lock" err_has "$T/sh/sweep-shard-1-of-2.lock: shard 1/2 of $T/sh is in use"
expect_exit 7 "  the whole sweep meanwhile" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/sh"
expect_exit 7 "  shard 2/3 (another count: it would overlap) meanwhile" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/sh" --shard 2/3
check "  names the running shard" err_has "$T/sh/sweep-shard-1-of-2.lock: $T/sh (shard 1/2 runs there; this is a shard of 3"
go
check "  shard 1/2 completes (exit $rc)" test "$rc" -eq 0
expect_exit 0 "  merge" "$POPC" sweep merge "$T/sh"
check "  equal to the reference" same_nowall "$T/sh/summary.csv" "$T/ref/summary.csv"

# ---- SIGKILL to the sweep: its workers end too, and make no more runs
# (--isolate: workers only; without it the sweep itself may hold run 0010)
paused "$T/k" -j 2 --isolate
check "SIGKILL: -j 2 is in run 0010 (worker ${worker:-none})" test -n "$worker" -a "$worker" != "$pid"
workers=$(cat /proc/$pid/task/*/children 2>/dev/null)
kill -KILL "$pid"; wait "$pid" 2>/dev/null; pid=
check "  every worker ($(echo $workers)) ends" gone $workers
n_rows=$(rows_of "$T/k")
check "  run 0010 was not recorded" bash -c "! cat '$T/k'/rows/*.csv | grep -q '^0010,'"
kill "$holder" 2>/dev/null; wait "$holder" 2>/dev/null; holder=
check "  the rows do not grow after ($n_rows)" test "$(rows_of "$T/k")" -eq "$n_rows"
expect_exit 0 "  the same command resumes it" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/k" -j 2
check "  every run once, as the reference" same_nowall "$T/k/summary.csv" "$T/ref/summary.csv"

# ---- a worker that outlives its sweep (stopped, so the parent-death signal
# waits) keeps the lock: no resume beside it; once it has gone, the resume runs
paused "$T/o" -j 2 --isolate
check "a stopped worker outliving its sweep (worker ${worker:-none})" test -n "$worker" -a "$worker" != "$pid"
stopped=$worker
kill -STOP "$stopped"
kill -KILL "$pid"; wait "$pid" 2>/dev/null; pid=
expect_exit 7 "  a resume while it lives is refused" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/o" -j 2
check "  says the directory is in use" err_has "is in use by another popc sweep or map"
kill -CONT "$stopped"
check "  the worker ends once it runs again (its parent-death signal)" gone "$stopped"
stopped=
kill "$holder" 2>/dev/null; wait "$holder" 2>/dev/null; holder=
expect_exit 0 "  then the resume runs" mid "$POPC" sweep "$SCENE" "${MID[@]}" -o "$T/o" -j 2
check "  every run once, as the reference" same_nowall "$T/o/summary.csv" "$T/ref/summary.csv"

check_summary
