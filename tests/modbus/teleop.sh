#!/bin/bash
# The teleoperation slave as a Modbus drive (issue 26): the hard-wall scene
# (data/scenes/teleop-wall.ini, 100 ms each way, shortened to 1.5 s: the
# slave meets the wall from about 0.25 s; 5 ms each way with the PCs off,
# which diverge at 100 ms) with the slave behind
# popc-servo-sim in lockstep (tests/modbus/exact-position.ini and
# exact-velocity.ini) and the master simulated, PCs on and off, gives the
# simulated run's log byte for byte in every column the simulated log has,
# but two:
# - xs_true: a drive has no true position, and the Modbus log has no such
#   column (it has dt and rtt instead);
# - xs_cmd in velocity mode only: a velocity drive has no position set
#   point, so popc's xs_cmd is its velocity commands' integral from the
#   position measured at start (count x resolution), while the simulated
#   slave's starts at its true initial position (the master's): the two
#   differ by less than one encoder count, which is checked instead, as
#   admittance.sh does for x_cmd. (In position mode popc reads the drive's
#   set point back at start and xs_cmd is equal.)
# popc-analyze energy --check recomputes each Modbus log's energies bit for
# bit and gives the simulated log's verdict on the two-port condition: it
# passes with the PCs on (without them the condition breaks, in both logs). The drive saw only well-formed frames, and its last
# writes were the safe stop's: zero velocity, or the last measured slave
# position, then disable.
#   teleop.sh SERVO_SIM tcp|rtu
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
TELE_SCENE="$POPC_SOURCE_ROOT/data/scenes/teleop-wall.ini"

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

for servo in position velocity; do
	MAP=$(test_map "$POPC_SOURCE_ROOT/tests/modbus/exact-$servo.ini")
	for pc in on off; do
		name=$servo-$pc
		set -- --set run.duration=1.5 --set slave.servo=$servo --set teleop.tdpa=$pc
		# without the PCs the 200 ms round trip diverges: 10 ms, where the
		# slave stays within the drive's soft limits (-55 mm at the least)
		[ $pc = off ] && set -- "$@" --set forward.delay_ticks=5 --set backward.delay_ticks=5
		"$POPC" run "$TELE_SCENE" -q "$@" --log "$WORK/sim-$name.csv" ||
			fail "$name: simulated run failed"
		start_server --map "$MAP" --listen "$LISTEN" --scene "$TELE_SCENE" "$@" --lockstep \
			--record "$WORK/rec-$name.txt"
		[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
		rc=0
		"$POPC" run "$TELE_SCENE" -q "$@" --axis modbus --map "$MAP" --connect "$CONNECT" \
			--free-run --log "$WORK/mb-$name.csv" 2>"$WORK/mb-$name.err" || rc=$?
		stop_server
		expect_rc "$name" $rc 0
		grep -q '(0 malformed)' "$WORK/srv.err" || fail "$name: the drive saw malformed frames: $(cat "$WORK/srv.err")"
		grep -q '^# source = modbus$' "$WORK/mb-$name.csv" || fail "$name: log source is not modbus"
		# every column of the simulated log, by name, but xs_true (and
		# xs_cmd in velocity mode)
		names=$(grep -v '^#' "$WORK/sim-$name.csv" | head -n 1 | tr ',' ' ')
		[[ " $names " == *" xs_true "* ]] || fail "$name: the simulated log has no xs_true"
		names=${names/xs_true/}
		[ "$servo" = velocity ] && names=${names/xs_cmd/}
		adm_cols "$WORK/sim-$name.csv" $names >"$WORK/sim-$name.cols"
		adm_cols "$WORK/mb-$name.csv" $names >"$WORK/mb-$name.cols"
		n=$(wc -l <"$WORK/sim-$name.cols")
		[ "$n" -eq 1501 ] || fail "$name: simulated log has $n rows, want 1501"
		cmp -s "$WORK/sim-$name.cols" "$WORK/mb-$name.cols" ||
			fail "$name: $TRANSPORT lockstep log differs from the simulated log: $(diff "$WORK/sim-$name.cols" "$WORK/mb-$name.cols" | head -3)"
		if [ "$servo" = velocity ]; then
			paste -d, <(adm_cols "$WORK/sim-$name.csv" xs_cmd) <(adm_cols "$WORK/mb-$name.csv" xs_cmd) |
				awk -F, '{ d = $1 - $2; if (d < 0) d = -d; if (d >= 1e-5) bad++ } END { exit bad > 0 }' ||
				fail "$name: xs_cmd differs from the simulated run's by a count or more"
		fi
		# the comparison means something: contact (slave force counts),
		# and with the PCs on both PCs acted
		adm_cols "$WORK/mb-$name.csv" fs_count f_pc vs_pc | awk -F, -v pc=$pc '
			$1 != 0 { force = 1 } $2 != 0 { fm = 1 } $3 != 0 { fs = 1 }
			END { exit !(force && (pc == "off" || (fm && fs))) }' ||
			fail "$name: no slave force reading, or a PC that never acted"
		check_log "$WORK/mb-$name.csv" '^# stop = completed$'
		# energy --check: the logged energies recomputed bit for bit ("rows
		# differing 0"), and the verdict on the two-port condition the
		# simulated log's (it holds with the PCs on; off, it breaks, in both)
		for f in sim mb; do
			rc=0
			"$POPC_BUILD_ROOT/analysis/popc-analyze" energy --check "$WORK/$f-$name.csv" \
				>"$WORK/$f-$name.check" || rc=$?
			echo "rc $rc" >>"$WORK/$f-$name.check"
		done
		grep -q 'rows differing 0 ' "$WORK/mb-$name.check" ||
			fail "$name: popc-analyze energy --check: $(cat "$WORK/mb-$name.check")"
		[ $pc = off ] || grep -q '^rc 0$' "$WORK/mb-$name.check" ||
			fail "$name: popc-analyze energy --check fails on the Modbus log: $(cat "$WORK/mb-$name.check")"
		cmp -s <(sed 's/^[^ ]* *//' "$WORK/sim-$name.check") <(sed 's/^[^ ]* *//' "$WORK/mb-$name.check") ||
			fail "$name: energy --check says otherwise on the simulated log: $(cat "$WORK/sim-$name.check")"
		# the safe stop: zero velocity, or the last measured slave position held
		last_xs=$(adm_cols "$WORK/mb-$name.csv" xs | tail -n 1)
		got=$(tail -n 2 "$WORK/rec-$name.txt" | tr '\n' '|')
		if [ "$servo" = velocity ]; then
			[[ $got =~ ^command\ 0\ \[0000(\ 0000)*\]\|enable\ 0x0000\|$ ]] ||
				fail "$name: last writes '$got', want zero velocity then disable"
		else
			[[ $got =~ ^command\ ([^ ]+)\ \[.*\]\|enable\ 0x0000\|$ ]] &&
				awk -v a="${BASH_REMATCH[1]}" -v b="$last_xs" 'BEGIN { exit !(a == b) }' ||
				fail "$name: last writes '$got', want the last measured position $last_xs held, then disable"
		fi
	done
done
# a force-mode map does not fit a teleoperation slave: refused before
# anything connects, naming the key
rc=0
"$POPC" run "$TELE_SCENE" -q --axis modbus --map "$EXACT_MAP" --connect tcp:127.0.0.1:1 \
	2>"$WORK/force-map.err" || rc=$?
expect_rc force-map $rc 2
grep -q "command.mode = force: .* has a teleoperation slave with slave.servo = position, which commands a position" \
	"$WORK/force-map.err" || fail "force-map: message '$(cat "$WORK/force-map.err")'"
[ "$TRANSPORT" = rtu ] && stop_socat
finish
