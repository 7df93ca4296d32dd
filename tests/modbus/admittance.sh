#!/bin/bash
# The admittance-type device over Modbus (issue 25): the low-force wall scene
# (data/scenes/admittance-wall.ini, 3 s: contact from about 1.1 s, the
# parallel PC acting on 100-250 ticks) through popc-servo-sim in lockstep,
# with a position-mode and a velocity-mode drive (tests/modbus/exact-*.ini),
# gives the simulated run's log byte for byte in every column the simulated
# log has, for every admittance variant. One exception, in velocity mode
# only: x_cmd. A velocity drive has no position set point, so popc's x_cmd
# is its velocity commands' integral from the position measured at start
# (count x resolution), while the simulated device's starts at its true
# initial position: the two differ by less than one encoder count, which is
# checked instead. (In position mode popc reads the drive's set point back
# at start, the drive's actual position to the bit, and x_cmd is equal.)
# popc-analyze energy --check passes on each Modbus log. The drive saw only
# well-formed Modbus frames, and its last writes were the
# safe stop's: zero velocity, or the last measured position, then disable.
#   admittance.sh SERVO_SIM tcp|rtu
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
ADM_SCENE="$POPC_SOURCE_ROOT/data/scenes/admittance-wall.ini"

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

for servo in position velocity; do
	MAP=$(test_map "$POPC_SOURCE_ROOT/tests/modbus/exact-$servo.ini")
	for v in none parallel-pc parallel-ignore parallel-hold parallel-improved; do
		name=$servo-$v
		set -- --set run.duration=3 --set admittance.servo=$servo --set admittance.variant=$v
		"$POPC" run "$ADM_SCENE" -q "$@" --log "$WORK/sim-$name.csv" ||
			fail "$name: simulated run failed"
		start_server --map "$MAP" --listen "$LISTEN" --scene "$ADM_SCENE" "$@" --lockstep \
			--record "$WORK/rec-$name.txt"
		[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
		rc=0
		"$POPC" run "$ADM_SCENE" -q "$@" --axis modbus --map "$MAP" --connect "$CONNECT" \
			--free-run --log "$WORK/mb-$name.csv" 2>"$WORK/mb-$name.err" || rc=$?
		stop_server
		expect_rc "$name" $rc 0
		grep -q '(0 malformed)' "$WORK/srv.err" || fail "$name: the drive saw malformed frames: $(cat "$WORK/srv.err")"
		# every column of the simulated log, by name (the Modbus log adds dt and rtt)
		names=$(grep -v '^#' "$WORK/sim-$name.csv" | head -n 1 | tr ',' ' ')
		[ "$servo" = velocity ] && names=${names/x_cmd/}
		adm_cols "$WORK/sim-$name.csv" $names >"$WORK/sim-$name.cols"
		adm_cols "$WORK/mb-$name.csv" $names >"$WORK/mb-$name.cols"
		n=$(wc -l <"$WORK/sim-$name.cols")
		[ "$n" -eq 3001 ] || fail "$name: simulated log has $n rows, want 3001"
		cmp -s "$WORK/sim-$name.cols" "$WORK/mb-$name.cols" ||
			fail "$name: $TRANSPORT lockstep log differs from the simulated log: $(diff "$WORK/sim-$name.cols" "$WORK/mb-$name.cols" | head -3)"
		if [ "$servo" = velocity ]; then
			paste -d, <(adm_cols "$WORK/sim-$name.csv" x_cmd) <(adm_cols "$WORK/mb-$name.csv" x_cmd) |
				awk -F, '{ d = $1 - $2; if (d < 0) d = -d; if (d >= 1e-5) bad++ } END { exit bad > 0 }' ||
				fail "$name: x_cmd differs from the simulated run's by a count or more"
		fi
		# the comparison means something: contact (force counts), and the PC
		# acted in every variant but none
		adm_cols "$WORK/mb-$name.csv" f_count v_pc | awk -F, -v v=$v '
			$1 != 0 { force = 1 } $2 != 0 { pc = 1 }
			END { exit !(force && (pc || v == "none")) }' ||
			fail "$name: no force reading or no PC action in the run"
		check_log "$WORK/mb-$name.csv" '^# stop = completed$'
		# the Modbus log is an admittance log: popc-analyze recomputes its W
		# from its force counts and velocities bit for bit
		"$POPC_BUILD_ROOT/analysis/popc-analyze" energy --check "$WORK/mb-$name.csv" >/dev/null ||
			fail "$name: popc-analyze energy --check fails on the Modbus log"
		# the safe stop: zero velocity, or the last measured position held
		last_x=$(adm_cols "$WORK/mb-$name.csv" x | tail -n 1)
		got=$(tail -n 2 "$WORK/rec-$name.txt" | tr '\n' '|')
		if [ "$servo" = velocity ]; then
			[[ $got =~ ^command\ 0\ \[0000(\ 0000)*\]\|enable\ 0x0000\|$ ]] ||
				fail "$name: last writes '$got', want zero velocity then disable"
		else
			[[ $got =~ ^command\ ([^ ]+)\ \[.*\]\|enable\ 0x0000\|$ ]] &&
				awk -v a="${BASH_REMATCH[1]}" -v b="$last_x" 'BEGIN { exit !(a == b) }' ||
				fail "$name: last writes '$got', want the last measured position $last_x held, then disable"
		fi
	done
done
# the shipped servo maps (int32 set points and an int32 force sensor in mN,
# which popc re-quantizes to the scene's 0.01 N) dry-run in lockstep: the
# run completes, the set point read back at start (the drive's own counts)
# is taken, and the last writes are the safe stop's (the server's watchdog
# off, as maps.sh runs the force maps)
for servo in position velocity; do
	MAP=$(test_map "$DRIVES/hilo-int32-$servo.ini")
	start_server --map "$MAP" --listen "$LISTEN" --scene "$ADM_SCENE" --set admittance.servo=$servo \
		--lockstep --watchdog-ms 0 --record "$WORK/rec-shipped-$servo.txt"
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	rc=0
	"$POPC" run "$ADM_SCENE" -q --set run.duration=1 --set admittance.servo=$servo --axis modbus \
		--map "$MAP" --connect "$CONNECT" --free-run --log "$WORK/shipped-$servo.csv" \
		2>"$WORK/shipped-$servo.err" || rc=$?
	stop_server
	expect_rc "shipped-$servo" $rc 0
	check_log "$WORK/shipped-$servo.csv" '^# stop = completed$'
	grep -q '(0 malformed)' "$WORK/srv.err" || fail "shipped-$servo: malformed frames: $(cat "$WORK/srv.err")"
	got=$(tail -n 2 "$WORK/rec-shipped-$servo.txt" | tr '\n' '|')
	[[ $got =~ ^command\ [^\ ]+\ \[[0-9a-f]{4}\ [0-9a-f]{4}\]\|enable\ 0x0000\|$ ]] ||
		fail "shipped-$servo: last writes '$got'"
done
[ "$TRANSPORT" = rtu ] && stop_socat
finish
