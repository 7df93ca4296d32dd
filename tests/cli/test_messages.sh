#!/usr/bin/env bash
# Messages that name what to do (issue 27):
# - "--set KEY VALUE" (two words) named as such, with the one word to give,
#   not "more than one SCENE file" (run, sweep, map; --vary too);
# - a run without --log says the log was not kept (not with -q);
# - a log of 100 MB or more is announced before the run, with its size;
# - --free-run and --rt on the simulated axis are refused (exit 2), as
#   --map and --connect are (they do nothing there);
# - a drive that refuses the connection: the error and a hint naming the
#   URI, not ten lines of zero statistics;
# - map: a probe past the edge that diverges is a verdict, labelled as
#   expected, not a failure; two --vary keys of one name (operator.damping,
#   environment.damping) head their columns section.key;
# - a directory named paper in the working directory does not hide the
#   scene paper.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
BUILD=${POPC_BUILD_ROOT:?}
T=$(mktemp -d /tmp/popc-messages-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
export POPC_DATA_PATH="$SRC/data"
cd "$T" || exit 1

expect_exit 2 "run --set KEY VALUE (two words)" "$POPC" run paper --set environment.stiffness 2000
check "  says to give --set KEY=VALUE as one word, with the fix" err_has "--set environment.stiffness 2000: give --set KEY=VALUE as one word, with '=': --set environment.stiffness=2000"
check "  not 'more than one SCENE file'" bash -c "! grep -q 'more than one SCENE' '$T/err'"
expect_exit 2 "  the value before the scene" "$POPC" run --set run.duration 3 paper
check "  the word after the key is the value" err_has "--set run.duration=3"
expect_exit 2 "sweep --vary KEY LIST" "$POPC" sweep paper --vary controller.variant none,improved -o sw
check "  named, with the fix" err_has "--vary controller.variant=none,improved"
check "  nothing made" test ! -e sw
expect_exit 2 "map --set KEY VALUE" "$POPC" map paper --variant none --set run.duration 2 -o mp
check "  named, with the fix" err_has "--set run.duration=2"

expect_exit 0 "run without --log" "$POPC" run paper --set run.duration=0.2
check "  says the log was not kept, and how to keep it" err_has "no --log given, so the run's log was not kept (--log FILE keeps it"
expect_exit 0 "  with -q" "$POPC" run paper --set run.duration=0.2 -q
check "  says nothing" test ! -s "$T/err"
expect_exit 0 "run with --log" "$POPC" run paper --set run.duration=0.2 --log a.csv
check "  no note about the log" bash -c "! grep -q 'note' '$T/err'"

# a 5000 s run: its log is announced before the first row; the pipe's reader
# leaves after 100 bytes, so the run ends on its first write error, whatever
# the machine's speed
set +o pipefail
"$POPC" run paper --set run.duration=5000 --log - 2>"$T/big.err" | head -c 100 >/dev/null
check "a long run announces its log's size before it starts" grep -q "note: the log - will be about 840 MB (5000001 rows of 12 cells, run.duration = 5000 s at 1000 Hz)" "$T/big.err"
check "  first, before anything else" test "$(head -c 27 "$T/big.err")" = "popc run: note: the log - w"
"$POPC" run paper --set run.duration=50 --log - 2>"$T/small.err" | head -c 100 >/dev/null
check "  a 50 s log (8 MB) is not announced" bash -c "! grep -q 'will be about' '$T/small.err'"

expect_exit 2 "--free-run on the simulated axis refused" "$POPC" run paper --set run.duration=0.2 --free-run
check "  says it is for axis.kind = modbus" err_has "--free-run: only for axis.kind = modbus, and axis.kind is sim"
expect_exit 2 "--rt on the simulated axis refused" "$POPC" run paper --set run.duration=0.2 --rt
check "  says so" err_has "--rt: only for axis.kind = modbus"

if [ -x "$BUILD/src/servo_sim/popc-servo-sim" ]; then
  # a loopback port nothing listens on: bound, then closed, by python3
  port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1]); s.close()')
  expect_exit 4 "a refused connection: exit 4" "$POPC" run paper --axis modbus --map generic --connect "tcp:127.0.0.1:$port" --log c.csv
  check "  the error" err_has "tcp:127.0.0.1:$port: cannot connect: Connection refused"
  check "  a hint naming the URI to check" err_has "hint: is the drive (or popc-servo-sim) on and listening at tcp:127.0.0.1:$port?"
  check "  no statistics of a run that never ticked" bash -c "! grep -qE 'PC active|period dt|latency rtt|real time' '$T/err'"
fi
# a map whose scan passes the edge: the probes beyond it diverge (exit 6)
"$POPC" map paper --variant none --stiffness 1e4:1e7 --tol 0.1 --criterion diverged -o edge -j 1 >edge.out 2>edge.err
check "map past the edge: exit 0" test $? -eq 0
check "  a diverged probe is labelled expected" grep -q 'diverged, as a probe past the edge is expected to: a verdict, not a failure' edge.err
check "  no probe called failed" bash -c "! grep -q 'failed, exit 6' '$T/edge.err'"
check "  the counts say diverged (verdicts)" grep -q 'diverged (verdicts) or failed' edge.err

"$POPC" map paper --variant none --vary operator.damping=0.5,1 --vary environment.damping=0,0.2 \
  --set run.duration=0.3 --stiffness 1e3:1e4 --tol 0.5 -o damp -q -j 1 >damp.out 2>damp.err
check "map over two dampings: exit 0" test $? -eq 0
check "  the table's headings tell them apart" grep -qE '^variant +operator.damping +environment.damping +criterion' damp.out
check "  boundary.csv's too" grep -q '^controller.variant,operator.damping,environment.damping,criterion' damp/boundary.csv
check "  the figure names the x axis' section" grep -q "K against operator.damping" damp/map.gp

mkdir -p here/paper
( cd here && "$POPC" run paper --set run.duration=0.2 -q ) 2>paper.err
check "a directory named paper does not hide the scene paper" test $? -eq 0 -a ! -s paper.err
mkdir -p here/nosuch
( cd here && "$POPC" run nosuch -q ) 2>nosuch.err
check "  a name found nowhere says the local one is a directory" grep -q 'nosuch: no such file in the working directory (a directory of that name, not a file)' nosuch.err
check_summary
