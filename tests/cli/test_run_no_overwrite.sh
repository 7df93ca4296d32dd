#!/usr/bin/env bash
# popc run never overwrites its own inputs: --log onto the scene file, the
# operator table or the register map, --summary onto any of them, and --log
# and --summary onto one file are refused before anything runs (exit 2,
# naming the option and both files), also through a link or another spelling;
# every input stays byte for byte.
set -u
POPC=${POPC:?POPC must name the popc program}
case $POPC in /*) ;; *) POPC=$PWD/$POPC ;; esac
SRC=${POPC_SOURCE_ROOT:?}
T=$(mktemp -d /tmp/popc-noover-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

printf '[run]\nduration = 0.05\n[operator]\nintent = table\ntable = xd.csv\n' > "$T/scene.ini"
printf 't,x_d\n0,-0.01\n0.05,-0.005\n' > "$T/xd.csv"
cp "$SRC/data/drives/generic.ini" "$T/map.ini"
for f in scene.ini xd.csv map.ini; do cp "$T/$f" "$T/keep.$f"; done
intact() { cmp -s "$T/keep.scene.ini" "$T/scene.ini" && cmp -s "$T/keep.xd.csv" "$T/xd.csv" &&
	cmp -s "$T/keep.map.ini" "$T/map.ini"; }
ln -s scene.ini "$T/link.ini"

expect_exit 2 "--log onto the scene file" "$POPC" run "$T/scene.ini" --log "$T/scene.ini"
check "  names --log and the scene" err_has "popc run: --log $T/scene.ini is the scene file $T/scene.ini: refusing to overwrite an input (choose another --log)"
check "  the inputs are intact" intact
expect_exit 2 "--log onto the scene through a link" "$POPC" run "$T/link.ini" --log "$T/scene.ini"
check "  names both spellings" err_has "--log $T/scene.ini is the scene file $T/link.ini"
expect_exit 2 "--log onto the scene, another spelling" env -C "$T" "$POPC" run scene.ini --log ./scene.ini
check "  refused" err_has "--log ./scene.ini is the scene file scene.ini"
expect_exit 2 "--summary onto the scene file" "$POPC" run "$T/scene.ini" --summary "$T/scene.ini"
check "  names --summary and the scene" err_has "--summary $T/scene.ini is the scene file $T/scene.ini"
check "  the inputs are intact" intact
expect_exit 2 "--log onto the operator table" "$POPC" run "$T/scene.ini" --log "$T/xd.csv"
check "  names the table" err_has "--log $T/xd.csv is the operator table (operator.table) $T/xd.csv"
expect_exit 2 "--summary onto the operator table" "$POPC" run "$T/scene.ini" --summary "$T/xd.csv"
check "  names the table" err_has "--summary $T/xd.csv is the operator table (operator.table) $T/xd.csv"
check "  the inputs are intact" intact
# a modbus run: refused before any connection is tried (port 9 on loopback:
# nothing listens there, and nothing is sent)
mb=(--axis modbus --map "$T/map.ini" --connect tcp:127.0.0.1:9)
expect_exit 2 "--log onto the register map" "$POPC" run "$T/scene.ini" "${mb[@]}" --log "$T/map.ini"
check "  names the map" err_has "--log $T/map.ini is the register map (axis.map) $T/map.ini"
check "  no connection was tried" bash -c "! grep -q '127.0.0.1' '$T/err'"
expect_exit 2 "--summary onto the register map" "$POPC" run "$T/scene.ini" "${mb[@]}" --summary "$T/map.ini"
check "  names the map" err_has "--summary $T/map.ini is the register map (axis.map) $T/map.ini"
check "  the inputs are intact" intact
expect_exit 2 "--log and --summary onto one new file" "$POPC" run "$T/scene.ini" --log "$T/both.csv" --summary "$T/both.csv"
check "  says so" err_has "popc run: --log $T/both.csv and --summary $T/both.csv are the same file: give each its own"
check "  nothing written" test ! -e "$T/both.csv"
: > "$T/sum.csv"
ln -s sum.csv "$T/sumlink.csv"
expect_exit 2 "--log onto --summary through a link" "$POPC" run "$T/scene.ini" --log "$T/sumlink.csv" --summary "$T/sum.csv"
check "  says so" err_has "are the same file"
# the map is an input of a modbus run only: a sim run may write where a map
# it does not read lies
expect_exit 0 "a sim run's --log may replace a file named by axis.map (not read)" "$POPC" run "$T/scene.ini" --set "axis.map=$T/other.csv" --log "$T/other.csv" -q
check "  wrote the log" grep -q '^# stop = completed' "$T/other.csv"
expect_exit 0 "other outputs still work" "$POPC" run "$T/scene.ini" --log "$T/run.csv" --summary "$T/sum2.csv" -q
check_summary
