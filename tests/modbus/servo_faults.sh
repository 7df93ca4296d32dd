#!/bin/bash
# The safe stop of a position- or velocity-mode drive (issue 25): every fault
# kind of docs/MODBUS.md's fault matrix, with the admittance-type device in
# lockstep (tests/modbus/exact-position.ini, exact-velocity.ini; the
# low-force wall scene, data/scenes/admittance-wall.ini), ends in the
# documented state: the exit code, the log's final "# stop = ..." line with
# every completed tick before it, and as the drive's last writes the safe
# stop's: zero velocity (velocity mode) or the last measured position
# (position mode: the x of the last logged row, or the position read at
# start when no tick was logged), then the disable word. The faults hit
# commands, as in faults.sh: command 1 is the start's set point, command c
# the exchange that brings tick c - 1, so a fault that stops the run at
# command C leaves the C - 1 ticks 0 .. C - 2.
#
# With teleop as the third argument (issue 26), the drive is the slave of a
# teleoperation run, the master simulated: the hard-wall scene
# (data/scenes/teleop-wall.ini, PCs on, 100 ms each way), slave.servo for
# admittance.servo, the slave's position xs for x. The same faults end the
# same way. The simulated master gets no command after the slave's failed
# exchange and is stopped before the drive (run_teleop.c); the loop's side
# of it, in-process: tests/unit/test_teleop_slave.c.
#   servo_faults.sh SERVO_SIM tcp|rtu [teleop]
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
TELEOP=${3:-}
ADM_SCENE="$POPC_SOURCE_ROOT/data/scenes/admittance-wall.ini"
SERVO_KEY=admittance.servo
XCOL=x # the drive's position in the log
if [ "$TELEOP" = teleop ]; then
	ADM_SCENE="$POPC_SOURCE_ROOT/data/scenes/teleop-wall.ini"
	SERVO_KEY=slave.servo
	XCOL=xs
fi
DUR=0.5 # 501 ticks
C=196   # the command the faults hit: the exchange that brings tick 195

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

# col LOG NAME: one named column of a log's rows
col() {
	awk -F, -v n="$2" '/^#/ { next } !h { for (i = 1; i <= NF; i++) if ($i == n) c = i; h = 1; next }
		{ print $c }' "$1"
}

# check_hold NAME REC X0: the drive's last command write was the safe
# stop's set point, and its last write the disable word (a write whose reply
# was dropped is retried: the record then repeats it). Velocity: zero
# (all-zero words). Position: the last logged row's x, or X0 (the position
# at start) when the log has no row.
check_hold() {
	local name=$1 rec=$2 x0=$3 got want
	got="$(grep '^command ' "$rec" | tail -n 1)|$(tail -n 1 "$rec")|"
	if [ "$SERVO" = velocity ]; then
		[[ $got =~ ^command\ 0\ \[0000(\ 0000)*\]\|enable\ 0x0000\|$ ]] ||
			fail "$name: last writes '$got', want zero velocity then disable"
		return
	fi
	want=$(col "$WORK/$name.csv" $XCOL | tail -n 1)
	[ -n "$want" ] || want=$x0
	[[ $got =~ ^command\ ([^ ]+)\ \[.*\]\|enable\ 0x0000\|$ ]] &&
		awk -v a="${BASH_REMATCH[1]}" -v b="$want" 'BEGIN { exit !(a == b) }' ||
		fail "$name: last writes '$got', want position $want held, then disable"
}

# run_case NAME WANT_RC STOP_PATTERN WANT_ROWS MAP "SERVER OPTIONS" [popc options...]
run_case() {
	local name=$1 want=$2 pat=$3 want_rows=$4 map=$5 sopts=$6 dur=${RUN_DUR:-$DUR}
	shift 6
	# shellcheck disable=SC2086
	start_server --map "$map" --listen "$LISTEN" --scene "$ADM_SCENE" $SETS --lockstep \
		--record "$WORK/rec-$name.txt" $sopts
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	local rc=0
	# shellcheck disable=SC2086
	"$POPC" run "$ADM_SCENE" $SETS --set run.duration="$dur" --axis modbus --map "$map" \
		--connect "$CONNECT" --free-run --log "$WORK/$name.csv" "$@" 2>"$WORK/$name.err" || rc=$?
	expect_rc "$name" $rc "$want"
	check_log "$WORK/$name.csv" "$pat"
	local n
	n=$(rows "$WORK/$name.csv")
	[ "$want_rows" = all ] && want_rows=$(awk -v d="$dur" 'BEGIN { print d * 1000 + 1 }')
	[ "$n" -eq "$want_rows" ] || fail "$name: $n ticks logged, want $want_rows"
}

for SERVO in position velocity; do
	SETS="--set $SERVO_KEY=$SERVO"
	MAP=$(test_map "$POPC_SOURCE_ROOT/tests/modbus/exact-$SERVO.ini")
	# shellcheck disable=SC2086
	"$POPC" run "$ADM_SCENE" -q $SETS --set run.duration=$DUR --log "$WORK/sim-$SERVO.csv" ||
		fail "$SERVO: simulated run"
	X0=$(col "$WORK/sim-$SERVO.csv" $XCOL | head -n 1)
	s=$SERVO

	# timeout: one reply lost: retried with the same sequence value, the run
	# completes and equals the simulated run (every column but x_cmd, which
	# admittance.sh checks)
	run_case $s-drop1 0 '^# stop = completed$' all "$MAP" "--drop c$C,1"
	# a second run on the same drive starts: its first read (before any
	# command of its own) finds the first run's sequence value, which is
	# no stale reply (before the fix: exit 4 at start, "reply's sequence
	# register 3 holds 502, the last command written carried 0")
	if [ "$TRANSPORT" = tcp ]; then
		rc=0
		# shellcheck disable=SC2086
		"$POPC" run "$ADM_SCENE" $SETS -q --set run.duration=0.01 --axis modbus --map "$MAP" \
			--connect "$CONNECT" --free-run --log "$WORK/$s-again.csv" 2>"$WORK/$s-again.err" || rc=$?
		expect_rc $s-again $rc 0
	fi
	stop_server
	grep -q ' 1 failed transactions' "$WORK/$s-drop1.err" || fail "$s-drop1: want 1 failed transaction"
	cmp_cols="x count f_count W v_pc"
	[ "$TELEOP" = teleop ] && cmp_cols="x count f_c W xs fs_count vs_c Ws"
	for c in $cmp_cols; do
		cmp -s <(col "$WORK/sim-$SERVO.csv" $c) <(col "$WORK/$s-drop1.csv" $c) ||
			fail "$s-drop1: column $c differs from the simulated run"
	done
	# the drive's last writes are the second run's (TCP) or the first's
	if [ "$TRANSPORT" = tcp ]; then
		check_hold $s-again "$WORK/rec-$s-drop1.txt" "$X0"
	else
		check_hold $s-drop1 "$WORK/rec-$s-drop1.txt" "$X0"
	fi

	# timeout max_failures times: communication lost
	run_case $s-drop3 4 '^# stop = communication lost: .*3 failed transactions in a row' $((C - 1)) \
		"$MAP" "--drop c$C,3"
	stop_server
	check_hold $s-drop3 "$WORK/rec-$s-drop3.txt" "$X0"

	# every reply to the first sample's read lost: no tick (the start's
	# requests: position read, [set point read back,] status read, command
	# 1, enable, one ready poll; c1+3 is the first sample's read)
	run_case $s-first 4 '^# stop = communication lost: .*3 failed transactions in a row \(last: position read' 0 \
		"$MAP" "--drop c1+3,3"
	stop_server
	check_hold $s-first "$WORK/rec-$s-first.txt" "$X0"

	# exception 4 three times: communication lost
	run_case $s-exc4 4 '^# stop = communication lost: .*Slave device or server failure' $((C - 1)) \
		"$MAP" "--exception c$C,4,3"
	stop_server
	check_hold $s-exc4 "$WORK/rec-$s-exc4.txt" "$X0"

	# exception 2: the map does not fit the drive, no retry
	run_case $s-exc2 2 '^# stop = axis error: .*rejected the .*Illegal data address' $((C - 1)) \
		"$MAP" "--exception c$C,2"
	stop_server
	check_hold $s-exc2 "$WORK/rec-$s-exc2.txt" "$X0"

	# the drive's fault bit: safety stop
	run_case $s-fault 3 '^# stop = safety stop: drive fault: status 0x0008' $((C - 1)) \
		"$MAP" "--fault-at c$C"
	stop_server
	check_hold $s-fault "$WORK/rec-$s-fault.txt" "$X0"

	# a drive faulted at start: not enabled, held and disabled
	run_case $s-startfault 3 '^# stop = axis start failed: drive fault.*does not start' 0 \
		"$MAP" "--start-faulted"
	stop_server
	check_hold $s-startfault "$WORK/rec-$s-startfault.txt" "$X0"

	# out of range: a position past the soft limit (soft_max_m = -4 mm, which
	# the hand's ramp passes; the teleoperation slave: 0.1 mm, which it
	# passes pushing into the wall): safety stop at the first such sample
	soft=-0.004 soft_re='-0\.00[0-9]*' soft_lim='-0\.004'
	[ "$TELEOP" = teleop ] && soft=0.0001 soft_re='0\.000[0-9]*' soft_lim='0\.0001'
	sed "s/^soft_max_m = .*/soft_max_m = $soft/" "$MAP" >"$WORK/soft-$s.ini"
	first=$(col "$WORK/sim-$SERVO.csv" $XCOL | awk -v lim=$soft '$1 > lim { print NR - 1; exit }')
	[ -n "$first" ] || fail "$s-soft: the simulated run never passes $soft m"
	run_case $s-soft 3 "^# stop = safety stop: position $soft_re m is outside the soft limits \\[-0\\.1, $soft_lim\\]" \
		"${first:-0}" "$WORK/soft-$s.ini" ""
	stop_server
	check_hold $s-soft "$WORK/rec-$s-soft.txt" "$X0"

	# the link lost: the server goes away after command C; reconnects are
	# refused: communication lost, and no safe stop reaches the drive
	# (TCP only, as faults.sh: over RTU the safe stop's unanswered requests
	# stay on the pty for the next case's server)
	if [ "$TRANSPORT" = tcp ]; then
		run_case $s-gone 4 '^# stop = communication lost' $C "$MAP" "--exit-after c$C"
		wait_server_exit
		grep -q 'safe stop incomplete' "$WORK/$s-gone.err" || fail "$s-gone: the failed safe stop is not said"
	fi

	# no reply to the safe stop after a completed run (command 1 + 500
	# exchanges: the stop's set point is command 502)
	run_case $s-nostop 4 "^# stop = safe stop incomplete: $([ $SERVO = velocity ] && echo 'zero velocity' || echo 'position hold') not confirmed: .*; disable not confirmed: " \
		all "$MAP" "--drop c502,100"
	stop_server
	check_hold $s-nostop "$WORK/rec-$s-nostop.txt" "$X0"

	if [ "$TRANSPORT" = tcp ]; then
		# the server closes the connection after command C: reconnect, retry, complete
		run_case $s-closed 0 '^# stop = completed$' all "$MAP" "--close-after c$C"
		stop_server
		check_hold $s-closed "$WORK/rec-$s-closed.txt" "$X0"

		# inherited descriptors: popc with stdin and stderr closed and a
		# reconnect (whose note, and the force sensor's re-quantization
		# note, would go to descriptor 2): the notes go to /dev/null, never
		# into the connection; the drive sees only well-formed frames
		# shellcheck disable=SC2086
		start_server --map "$MAP" --listen "$LISTEN" --scene "$ADM_SCENE" $SETS --lockstep \
			--close-after c$C --record "$WORK/rec-$s-fds.txt"
		rc=0
		# shellcheck disable=SC2086
		"$POPC" run "$ADM_SCENE" $SETS --set run.duration=$DUR --axis modbus --map "$MAP" \
			--connect "$SRV_URI" --free-run --log "$WORK/$s-fds.csv" <&- 2>&- || rc=$?
		stop_server
		expect_rc $s-fds $rc 0
		check_log "$WORK/$s-fds.csv" '^# stop = completed$'
		grep -q '(0 malformed)' "$WORK/srv.err" || fail "$s-fds: the drive saw malformed frames: $(cat "$WORK/srv.err")"
		check_hold $s-fds "$WORK/rec-$s-fds.txt" "$X0"
	fi

	# a signal mid-run (paced at 1 kHz, 60 s), once the server has seen
	# command 100: safe stop, exit 5, whole rows
	for sig in INT TERM; do
		name=$s-sig$sig
		# shellcheck disable=SC2086
		start_server --map "$MAP" --listen "$LISTEN" --scene "$ADM_SCENE" $SETS --lockstep \
			--notify-at c100 --record "$WORK/rec-$name.txt"
		[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
		# shellcheck disable=SC2086
		"$POPC" run "$ADM_SCENE" -q $SETS --set run.duration=60 --axis modbus --map "$MAP" \
			--connect "$CONNECT" --log "$WORK/$name.csv" &
		pid=$!
		read -r -t 60 -u 3 line || fail "$name: the server never saw command 100"
		kill -$sig $pid
		rc=0
		wait $pid || rc=$?
		stop_server
		expect_rc "$name" $rc 5
		check_log "$WORK/$name.csv" '^# stop = signal: interrupted by a signal'
		[ "$(rows "$WORK/$name.csv")" -ge 99 ] || fail "$name: $(rows "$WORK/$name.csv") ticks logged, want 99 or more"
		check_hold $name "$WORK/rec-$name.txt" "$X0"
	done
done
[ "$TRANSPORT" = rtu ] && stop_socat
finish
