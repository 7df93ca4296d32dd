#!/bin/bash
# The paper scene through popc-servo-sim in lockstep gives the simulated run's
# x, count, f_c, W and E_ref bit for bit, for every variant (issue 4), and
# with a loop delay (improved+delay: run.delay_ticks = 2, which the run loop
# applies before any axis, so the drive receives the same delayed commands).
#   lockstep.sh SERVO_SIM tcp|rtu
# The run is shortened to 1.5 s: the contact starts at about 0.7 s (ramp from
# -0.01 m at 0.5 s, 0.05 m/s), so the PO/PC acts in every variant.
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"  # a pty does not care for the baud
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

for v in none po-pc ref-energy filtered-velocity ignore hold improved pc-off-reversals \
	energy-bounding windowed-po improved+delay; do
	set -- --variant "${v%+delay}"
	[ "$v" = improved+delay ] && set -- "$@" --set run.delay_ticks=2
	"$POPC" run "$SCENE" -q --set run.duration=1.5 "$@" --log "$WORK/sim-$v.csv" ||
		fail "$v: simulated run failed"
	# a fresh server per variant: the plant starts from the scene's initial state
	start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--record "$WORK/rec-$v.txt"
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	rc=0
	"$POPC" run "$SCENE" -q --set run.duration=1.5 "$@" --axis modbus \
		--map "$EXACT_MAP" --connect "$CONNECT" --free-run --log "$WORK/mb-$v.csv" || rc=$?
	stop_server
	expect_rc "$v" $rc 0
	cols "$WORK/sim-$v.csv" >"$WORK/sim-$v.cols"
	cols "$WORK/mb-$v.csv" >"$WORK/mb-$v.cols"
	n=$(wc -l <"$WORK/sim-$v.cols")
	[ "$n" -eq 1501 ] || fail "$v: simulated log has $n rows, want 1501"
	cmp -s "$WORK/sim-$v.cols" "$WORK/mb-$v.cols" ||
		fail "$v: $TRANSPORT lockstep log differs from the simulated log: $(diff "$WORK/sim-$v.cols" "$WORK/mb-$v.cols" | head -3)"
	# the run must have seen contact and PC action for the comparison to mean
	# something: count > 0, and f_pc != 0 in some tick for every variant but
	# none and energy-bounding (whose K_b = 2 b / T equals the paper's wall:
	# f_c = f_e up to rounding) (1.5 s of the paper scene: 7 ticks with
	# filtered-velocity, 57 to 565 with the others)
	awk -F, -v v=$v '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
		$c["count"] > 0 { contact = 1 } $c["f_pc"] != 0 { pc = 1 }
		END { exit !(c["count"] && c["f_pc"] && contact && (pc || v == "none" || v == "energy-bounding")) }' \
		"$WORK/mb-$v.csv" || fail "$v: no contact or no PC action in the run"
	check_log "$WORK/mb-$v.csv" '^# stop = completed$'
	check_last_writes "$WORK/rec-$v.txt" 0x0000
	grep -q '^source = modbus\|^# source = modbus' "$WORK/mb-$v.csv" || fail "$v: log source is not modbus"
done
[ "$TRANSPORT" = rtu ] && stop_socat
finish
