#!/usr/bin/env bash
# The delay study's figures (docs/TELEOPERATION.md, README "Teleoperation over
# delay"): tools/teleop-figures.sh draws them with gnuplot from popc's own
# output (popc run logs, popc map's boundary.csv). Run into a scratch
# directory: both PNGs drawn, and the numbers the script prints, the figures'
# content, are the study's: with the PCs every round trip completes, without
# them 50, 200 and 700 ms diverge; the map holds the 20 kN/m wall with the PCs
# at every delay, not without them from 10 ms on.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
command -v gnuplot >/dev/null || { echo "1..0 # SKIP gnuplot not installed"; exit 77; }
T=$(mktemp -d /tmp/popc-teleop-figures-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
png() { test "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a; }

expect_exit 0 "tools/teleop-figures.sh draws the figures" sh "$SRC/tools/teleop-figures.sh" "$POPC" "$T/fig"
check "  teleop-delay.png is a PNG" png "$T/fig/teleop-delay.png"
check "  teleop-map.png is a PNG" png "$T/fig/teleop-map.png"
check "  gnuplot warned of nothing" test ! -s "$T/err"
for rt in 0 50 200 700; do
  check "  $rt ms, PCs on: completed" grep -q "^$rt ms, PCs on: completed" "$T/out"
done
check "  0 ms, PCs off: completed" grep -q "^0 ms, PCs off: completed" "$T/out"
for rt in 50 200 700; do
  check "  $rt ms, PCs off: diverged" grep -q "^$rt ms, PCs off: diverged at t = " "$T/out"
done
check "  18 map lines (9 delays x PCs off, on)" test "$(grep -c '^map: PCs' "$T/out")" -eq 18
# "stable up to" of each map line, against the study's 20 kN/m wall
check "  PCs on: stable up to 20 kN/m or more at every delay" \
  awk '/^map: PCs on/ { n++; if ($NF != "N/m" || $(NF - 1) + 0 < 20000) bad = 1 } END { exit bad || n != 9 }' "$T/out"
check "  PCs off: stable only below 1 kN/m from 10 ms on" \
  awk '/^map: PCs off, round trip/ && $6 != "0" { n++; if ($(NF - 1) + 0 >= 1000) bad = 1 } END { exit bad || n != 8 }' "$T/out"
check_summary
