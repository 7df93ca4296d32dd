#!/bin/bash
# Command modes (issue 25): a register map's command.mode must be the scene's.
# Each mismatch is bad input (exit 2) refused before anything connects (the
# URI's port 1 has no listener: a connection attempt would be exit 4), with
# the map's file and the key named: a position or velocity map with an
# impedance scene, a force map with an admittance scene, a servo mode that is
# not the scene's admittance.servo, a servo map without its [force_sensor].
# popc-servo-sim refuses the same mismatches (exit 2, no server). A map that
# fits passes these checks and goes on to connect (exit 4 here: nobody
# listens on port 1).
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
# a servo map that fits its scene is accepted and tries to connect (before
# issue 25's Modbus part: refused, "does not drive an admittance-type device yet")
for map in "$POS_MAP" "$VEL_MAP"; do
	mode=$(sed -n 's/^mode = //p' "$map")
	rc=0
	"$POPC" run "$ADM_SCENE" -q --set admittance.servo=$mode --axis modbus --map "$map" \
		--connect tcp:127.0.0.1:1 --log "$WORK/fits-$mode.csv" 2>"$WORK/fits-$mode.err" || rc=$?
	expect_rc "fits-$mode" $rc 4
	grep -q 'cannot connect' "$WORK/fits-$mode.err" || fail "fits-$mode: $(cat "$WORK/fits-$mode.err")"
done

# a servo map without its force sensor: the key and the file
sed '/^\[force_sensor\]/,/^newton_per_unit/d' "$POS_MAP" >"$WORK/no-sensor.ini"
refused no-sensor \
	"^popc run: $WORK/no-sensor.ini: missing force_sensor.register: a position or velocity command needs the force sensor" \
	"$ADM_SCENE" --set admittance.servo=position --map "$WORK/no-sensor.ini"

# a key of another mode, in a shipped servo map: file, line and key
sed '/^\[command\]/,/^\[force_sensor\]/ s/^counts_per_m = 100000$/&\nlimit_N = 20/' "$POS_MAP" \
	>"$WORK/pos-limit.ini"
line=$(grep -n '^limit_N = 20$' "$WORK/pos-limit.ini" | cut -d: -f1)
[ "$(grep -c '^limit_N = 20$' "$WORK/pos-limit.ini")" -eq 1 ] || fail "pos-limit.ini: $(cat "$WORK/pos-limit.ini")"
refused other-mode-key \
	"$WORK/pos-limit.ini:$line: command.limit_N = 20: only used with command.mode = force (this map's is position)" \
	"$ADM_SCENE" --map "$WORK/pos-limit.ini"

# popc-servo-sim: a map whose mode is not the scene's device is refused
# (exit 2) naming the map and the key, and no server starts (before issue
# 25's Modbus part every servo-mode map was refused, and a force map around
# an admittance scene was served)
# sim_refused NAME PATTERN SIM-ARGS...
sim_refused() {
	local name=$1 pattern=$2 rc=0
	shift 2
	timeout 10 "$SIM" --listen tcp:127.0.0.1:0 "$@" >"$WORK/sim-$name.out" 2>"$WORK/sim-$name.err" || rc=$?
	expect_rc "sim $name" $rc 2
	grep -q -- "$pattern" "$WORK/sim-$name.err" || fail "sim $name: $(cat "$WORK/sim-$name.err")"
	! grep -q listening "$WORK/sim-$name.out" || fail "sim $name: a server started"
}
for map in "$POS_MAP" "$VEL_MAP"; do
	mode=$(sed -n 's/^mode = //p' "$map")
	sim_refused "impedance-$mode" \
		"^popc-servo-sim: $map: command.mode = $mode: $SCENE has device.causality = impedance" \
		--map "$map" --scene "$SCENE"
done
sim_refused force-map \
	"^popc-servo-sim: $DRIVES/popc-exact.ini: command.mode = force: $ADM_SCENE has device.causality = admittance" \
	--map "$DRIVES/popc-exact.ini" --scene "$ADM_SCENE"
sim_refused servo-mismatch \
	"^popc-servo-sim: $VEL_MAP: command.mode = velocity: $ADM_SCENE has admittance.servo = position; the map needs command.mode = position" \
	--map "$VEL_MAP" --scene "$ADM_SCENE" --set admittance.servo=position
sim_refused no-sensor \
	"^popc-servo-sim: $WORK/no-sensor.ini: missing force_sensor.register" \
	--map "$WORK/no-sensor.ini" --scene "$ADM_SCENE"
finish
