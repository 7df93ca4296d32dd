#!/bin/bash
# Command modes (issue 25): a register map's command.mode must be the scene's.
# Each mismatch is bad input (exit 2) refused before anything connects (the
# URI's port 1 has no listener: a connection attempt would be exit 4), with
# the map's file and the key named: a position or velocity map with an
# impedance scene, a force map with an admittance scene, a servo mode that is
# not the scene's admittance.servo. What phase 2 has not built yet is refused
# the same way, saying so: the Modbus axis with an admittance scene, and
# popc-servo-sim with a position- or velocity-mode map.
#   modes.sh SERVO_SIM
. "$(dirname "$0")/lib.sh"

ADM_SCENE="$POPC_SOURCE_ROOT/data/scenes/admittance.ini"
POS_MAP="$DRIVES/hilo-int32-position.ini"
VEL_MAP="$DRIVES/hilo-int32-velocity.ini"

# refused NAME PATTERN POPC-RUN-ARGS...: exit 2 and the message matches
refused() {
	local name=$1 pattern=$2 rc=0
	shift 2
	"$POPC" run "$@" -q --axis modbus --connect tcp:127.0.0.1:1 --log "$WORK/$name.csv" \
		2>"$WORK/$name.err" || rc=$?
	expect_rc "$name" $rc 2
	grep -q -- "$pattern" "$WORK/$name.err" || fail "$name message: $(cat "$WORK/$name.err")"
}

for map in "$POS_MAP" "$VEL_MAP"; do
	mode=$(sed -n 's/^mode = //p' "$map")
	refused "impedance-$mode" \
		"^popc run: $map: command.mode = $mode: $SCENE has device.causality = impedance, which commands a force; the map needs command.mode = force" \
		"$SCENE" --map "$map"
done
for servo in position velocity; do
	refused "force-map-$servo" \
		"^popc run: $DRIVES/popc-exact.ini: command.mode = force: $ADM_SCENE has device.causality = admittance with admittance.servo = $servo, which commands a $servo; the map needs command.mode = $servo and a \[force_sensor\]" \
		"$ADM_SCENE" --set admittance.servo=$servo --map "$DRIVES/popc-exact.ini"
done
refused servo-mismatch \
	"^popc run: $VEL_MAP: command.mode = velocity: $ADM_SCENE has admittance.servo = position; the map needs command.mode = position" \
	"$ADM_SCENE" --set admittance.servo=position --map "$VEL_MAP"
refused not-yet "^popc run: $POS_MAP: command.mode = position: the modbus axis does not drive an admittance-type device yet" \
	"$ADM_SCENE" --set admittance.servo=position --map "$POS_MAP"

# a key of another mode, in a shipped servo map: file, line and key
sed '/^\[command\]/,/^\[force_sensor\]/ s/^counts_per_m = 100000$/&\nlimit_N = 20/' "$POS_MAP" \
	>"$WORK/pos-limit.ini"
line=$(grep -n '^limit_N = 20$' "$WORK/pos-limit.ini" | cut -d: -f1)
[ "$(grep -c '^limit_N = 20$' "$WORK/pos-limit.ini")" -eq 1 ] || fail "pos-limit.ini: $(cat "$WORK/pos-limit.ini")"
refused other-mode-key \
	"$WORK/pos-limit.ini:$line: command.limit_N = 20: only used with command.mode = force (this map's is position)" \
	"$ADM_SCENE" --map "$WORK/pos-limit.ini"

# popc-servo-sim: a servo-mode map is refused (exit 2), no server starts
for map in "$POS_MAP" "$VEL_MAP"; do
	mode=$(sed -n 's/^mode = //p' "$map")
	rc=0
	timeout 10 "$SIM" --map "$map" --listen tcp:127.0.0.1:0 --scene "$ADM_SCENE" \
		>"$WORK/sim-$mode.out" 2>"$WORK/sim-$mode.err" || rc=$?
	expect_rc "sim $mode" $rc 2
	grep -q "$map: command.mode = $mode: popc-servo-sim simulates a drive with a force command only" \
		"$WORK/sim-$mode.err" || fail "sim $mode: $(cat "$WORK/sim-$mode.err")"
	! grep -q listening "$WORK/sim-$mode.out" || fail "sim $mode: a server started"
done
finish
