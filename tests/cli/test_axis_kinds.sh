#!/usr/bin/env bash
# The axis kinds of this build (meson option modbus): a scene's axis.kind is
# the same scene format in every build, and the factory says what this build
# can drive. Argument: "modbus" (built with libmodbus) or "no-modbus".
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
BUILD=${1:?modbus or no-modbus}
T=$(mktemp -d /tmp/popc-axis-kinds-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

SCENE=$SRC/data/scenes/paper.ini
MAP=$SRC/data/drives/generic.ini
# port 1 on loopback: nothing listens there, the connection is refused at once
DRIVE=(--axis modbus --map "$MAP" --connect tcp:127.0.0.1:1 --free-run -q)
NO_SUPPORT="axis.kind = modbus: this build of popc has no Modbus support"

expect_exit 0 "the simulated axis runs" "$POPC" run "$SCENE" --set run.duration=0.01 -q
if [ "$BUILD" = modbus ]; then
	expect_exit 4 "a drive that does not answer: communication lost" \
		"$POPC" run "$SCENE" "${DRIVE[@]}" --log "$T/drive.csv"
	check "  the Modbus axis tried the link" err_has "tcp:127.0.0.1:1: cannot connect"
	check "  not the message of a build without Modbus" sh -c "! grep -qF '$NO_SUPPORT' '$T/err'"
else
	expect_exit 2 "axis.kind = modbus in a build without libmodbus" \
		"$POPC" run "$SCENE" "${DRIVE[@]}" --log "$T/drive.csv"
	check "  names the scene, the kind and the build" err_has "popc run: $SCENE: $NO_SUPPORT"
	check "  nothing ran: no log written" test ! -e "$T/drive.csv"
	printf '[run]\nduration = 0.01\n[axis]\nkind = modbus\nmap = %s\nconnect = tcp:127.0.0.1:1\n' \
		"$MAP" >"$T/drive.ini"
	expect_exit 2 "the same from the scene file" "$POPC" run "$T/drive.ini" -q
	check "  names the scene file" err_has "popc run: $T/drive.ini: $NO_SUPPORT"
fi
# a sweep refuses a real axis whatever the build: its runs share no drive
expect_exit 2 "a sweep over the drive" "$POPC" sweep "$SCENE" --set "axis.map=$MAP" \
	--set axis.connect=tcp:127.0.0.1:1 --set axis.kind=modbus --vary run.duration=0.01,0.02 -o "$T/sweep"
check "  a sweep runs the simulated axis only" err_has "axis.kind = modbus: a sweep runs the simulated axis only"
check_summary
