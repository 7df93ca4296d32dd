#!/usr/bin/env bash
# Output paths that cannot be used are bad usage (exit 2), named with their
# option, before any work: popc-analyze -o (energy's file, replay's and
# report's directory, every file a report or replay would write) and
# popc-servo-sim --record (was checked only at exit, after serving the run).
# popc-analyze of 46f30c1 gave exit 1 for a report whose figure path is a
# non-empty directory, after reading every log and drawing.
set -u
POPC=${POPC:?POPC must name the popc program}
case $POPC in /*) ;; *) POPC=$PWD/$POPC ;; esac
SRC=${POPC_SOURCE_ROOT:?}
A=${1:?popc-analyze as argument 1}
SIM=${2:-}   # popc-servo-sim, when this build has it
T=$(mktemp -d /tmp/popc-outpaths-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

"$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=0.2 -q --log "$T/p.csv"
mkdir "$T/adir" "$T/r1" "$T/r1/p.png" "$T/r2" "$T/r2/compare.md" "$T/rp" "$T/rp/p.none.csv"
: > "$T/r1/p.png/keep" ; : > "$T/r2/compare.md/keep"
# no work done: a log that does not exist would be named if it were read
nolog=$T/not-read.csv

expect_exit 2 "energy -o in a missing directory" "$A" energy -o "$T/nodir/e.csv" "$nolog"
check "  names -o, the path and why, before reading the log" err_has "popc-analyze energy: -o $T/nodir/e.csv: its directory $T/nodir cannot be used: No such file or directory"
expect_exit 2 "energy -o onto a directory" "$A" energy -o "$T/adir" "$nolog"
check "  says a file is needed" err_has "popc-analyze energy: -o $T/adir: is a directory; a file path is needed"
expect_exit 2 "energy -o through a file" "$A" energy -o "$T/p.csv/e.csv" "$nolog"
check "  names it" err_has "popc-analyze energy: -o $T/p.csv/e.csv: cannot be used: Not a directory"
expect_exit 2 "replay -o a directory under a file" "$A" replay --variant none -o "$T/p.csv/sub" "$nolog"
check "  names it" err_has "popc-analyze replay: -o $T/p.csv/sub: cannot create directory $T/p.csv/sub: Not a directory"
expect_exit 2 "replay -o a file" "$A" replay --variant none -o "$T/p.csv" "$nolog"
check "  names it" err_has "popc-analyze replay: -o $T/p.csv: exists and is not a directory"
expect_exit 2 "replay -o DIR where its output is a directory" "$A" replay --variant none -o "$T/rp" "$T/p.csv"
check "  names the output" err_has "popc-analyze replay: -o $T/rp/p.none.csv: is a directory; a file path is needed"
expect_exit 2 "replay --prefix in a missing directory" "$A" replay --variant none --prefix "$T/nodir/x-" "$nolog"
check "  names the file it would write" err_has "popc-analyze replay: --prefix $T/nodir/x-none.csv: its directory $T/nodir cannot be used"
expect_exit 2 "report -o under a missing directory" "$A" report --no-draw -o "$T/nodir/deeper" "$nolog"
check "  names it" err_has "popc-analyze report: -o $T/nodir/deeper: its directory $T/nodir cannot be used: No such file or directory"
expect_exit 2 "report -o a file" "$A" report --no-draw -o "$T/p.csv" "$nolog"
check "  names it" err_has "popc-analyze report: -o $T/p.csv: exists and is not a directory"
expect_exit 2 "report -o DIR where a figure path is a directory (was exit 1 after the work)" "$A" report -o "$T/r1" "$T/p.csv"
check "  names the figure, before reading the log (no note about it)" bash -c "[ \"\$(cat '$T/err')\" = 'popc-analyze report: -o $T/r1/p.png: is a directory; a file path is needed' ]"
check "  nothing written" test ! -e "$T/r1/p.dat"
expect_exit 2 "report -o DIR where compare.md is a directory" "$A" report --no-draw -o "$T/r2" "$T/p.csv"
check "  names it" err_has "popc-analyze report: -o $T/r2/compare.md: is a directory; a file path is needed"
expect_exit 0 "usable paths still work" "$A" energy -o "$T/adir/e.csv" "$T/p.csv"

# popc-servo-sim --record: refused at start (exit 2) instead of listening,
# serving a run and failing at exit; timeout bounds a regression, it is no
# synchronisation
if [ -n "$SIM" ]; then
	expect_exit 2 "popc-servo-sim --record in a missing directory" timeout 20 "$SIM" --map "$SRC/data/drives/generic.ini" \
		--listen tcp:127.0.0.1:9 --scene "$SRC/data/scenes/paper.ini" --record "$T/nodir/rec.txt"
	check "  names it and why, before listening" err_has "popc-servo-sim: --record $T/nodir/rec.txt: cannot open for writing: No such file or directory"
	check "  did not listen" bash -c "! grep -q listening '$T/err'"
else
	echo "# no popc-servo-sim in this build (without Modbus): --record not checked"
fi
check_summary
