#!/bin/bash
# Injected faults and signals end in the documented state (docs/MODBUS.md):
# the exit code, the log's final "# stop = ..." line with every completed tick
# before it, and zero force then disable as the last writes the server saw
# (applied even when their replies are dropped). Maps with FC23, with FC16 and
# FC03, and with FC16, FC04 and a separate status read.
#   faults.sh SERVO_SIM tcp|rtu
#
# The faults hit commands, not request numbers (popc-servo-sim's cC[+K]), so
# that they land on the same tick however many transactions were retried
# before: command 1 is the start's zero force, command c >= 2 is the
# exchange that brings tick c - 1 (FC23: one request; FC16: the write, then
# the reads). A fault that stops the run at command C leaves the C - 1 ticks
# 0 .. C - 2. The maps are copies with a 500 ms response timeout (lib.sh).
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
DUR=0.5 # 500 ticks: the faults need no contact (the soft limit below does: 1.5 s)
C=196   # the command the faults hit: the exchange that brings tick 195 (t = 0.195 s,
        # at rest before the ramp; retry.sh hits tick 895, in contact)

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

# run_case NAME WANT_RC STOP_PATTERN WANT_ROWS MAP "SERVER OPTIONS" [popc options...]
# WANT_ROWS: a number, or "all" (1 + duration * rate). The duration is $DUR,
# or RUN_DUR when set.
run_case() {
	local name=$1 want=$2 pat=$3 want_rows=$4 map=$5 sopts=$6 dur=${RUN_DUR:-$DUR}
	shift 6
	# shellcheck disable=SC2086
	start_server --map "$map" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--record "$WORK/rec-$name.txt" $sopts
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	local rc=0
	"$POPC" run "$SCENE" --set run.duration="$dur" --axis modbus --map "$map" \
		--connect "$CONNECT" --free-run --log "$WORK/$name.csv" "$@" 2>"$WORK/$name.err" || rc=$?
	expect_rc "$name" $rc "$want"
	check_log "$WORK/$name.csv" "$pat"
	local n
	n=$(rows "$WORK/$name.csv")
	[ "$want_rows" = all ] && want_rows=$(awk -v d="$dur" 'BEGIN { print d * 1000 + 1 }')
	[ "$n" -eq "$want_rows" ] || fail "$name: $n ticks logged, want $want_rows"
}

# 1. replies dropped three times in a row (max_failures = 3): communication lost
run_case drop 4 '^# stop = communication lost: .*3 failed transactions in a row' $((C - 1)) \
	"$EXACT_MAP" "--drop c$C,3"
stop_server
check_last_writes "$WORK/rec-drop.txt" 0x0000

# 2. one reply dropped: retried, the run completes (a fresh position, never an old one)
run_case drop1 0 '^# stop = completed$' all "$EXACT_MAP" "--drop c$C,1"
stop_server
grep -q ' 1 failed transactions' "$WORK/drop1.err" || fail "drop1: want 1 failed transaction: $(grep 'link:' "$WORK/drop1.err")"
check_last_writes "$WORK/rec-drop1.txt" 0x0000

# 2b. every reply to the first sample's read dropped (max_failures = 3): the
#     start's requests are the status read, command 1 (zero force), the
#     enable word and one ready poll (the lockstep drive is ready at once),
#     so c1+3 is the first position read. Communication lost, exit 4, no
#     tick, the stop line docs/MODBUS.md lists for exit 4 (before issue 28:
#     "axis sample failed: ...", listed nowhere).
run_case first 4 '^# stop = communication lost: .*3 failed transactions in a row \(last: position read' 0 \
	"$EXACT_MAP" "--drop c1+3,3"
stop_server
check_last_writes "$WORK/rec-first.txt" 0x0000

# 3. a reply 750 ms late (timeout 500 ms): timeout; TCP reconnects (the server
#    holds the late reply until popc has closed the old connection), RTU drains
#    the late reply (it comes 250 ms into the drain's 500 ms quiet wait: a
#    margin either side 3.7 times the worst round trip measured under load);
#    the retry is answered: completes, with one failed transaction. (A
#    single-threaded drive that stays silent for max_failures timeouts is a
#    communication loss, as in 1.)
run_case delay 0 '^# stop = completed$' all "$EXACT_MAP" "--delay c$C,750"
stop_server
grep -q ' 1 failed transactions' "$WORK/delay.err" || fail "delay: want 1 failed transaction: $(grep 'link:' "$WORK/delay.err")"
grep 'came before this reply' "$WORK/srv.err" &&
	fail "delay: popc sent its next request before the late reply came: this machine stalled past the 250 ms margin"
check_last_writes "$WORK/rec-delay.txt" 0x0000

# 4. exception 4 (server device failure) three times: communication lost
run_case exception 4 '^# stop = communication lost: .*Slave device or server failure' $((C - 1)) \
	"$EXACT_MAP" "--exception c$C,4,3"
stop_server
check_last_writes "$WORK/rec-exception.txt" 0x0000

# 5. the drive raises its fault bits: safety stop
run_case fault 3 '^# stop = safety stop: drive fault: status 0x0008' $((C - 1)) \
	"$EXACT_MAP" "--fault-at c$C"
stop_server
check_last_writes "$WORK/rec-fault.txt" 0x0000

# 6. a drive that reports a fault is not started; still zeroed and disabled
run_case start-faulted 3 '^# stop = axis start failed: drive fault.*does not start' 0 \
	"$EXACT_MAP" "--start-faulted"
stop_server
check_last_writes "$WORK/rec-start-faulted.txt" 0x0000

# 7. position soft limit (a map whose soft_max_m is 1 mm; contact pushes ~2 mm in):
#    the ticks before the first sample past 1 mm (found in the simulated run)
sed 's/^soft_max_m = .*/soft_max_m = 0.001/' "$EXACT_MAP" >"$WORK/soft.ini"
"$POPC" run "$SCENE" -q --set run.duration=1.5 --log "$WORK/soft-sim.csv" || fail "soft: sim run"
first=$(cols "$WORK/soft-sim.csv" | awk '$2 > 100 { print NR - 1; exit }')
[ -n "$first" ] || fail "soft: the simulated run never passes 1 mm"
RUN_DUR=1.5 run_case soft 3 '^# stop = safety stop: position 0\.001[0-9]* m is outside the soft limits \[-0\.1, 0\.001\]' "$first" \
	"$WORK/soft.ini" ""
stop_server
check_last_writes "$WORK/rec-soft.txt" 0x0000

# 8. the drive's watchdog: commands 1 s apart (run.rate = 1 Hz, paced) and a
#    500 ms watchdog: the drive faults before the first command of the loop;
#    safety stop. Pacing only ever makes the gap longer; what must not take
#    500 ms is popc's start, from the enable write to the tick-0 read (four
#    transactions, under 1 ms unloaded, 67 ms the worst round trip measured
#    under load), or the drive faults during start instead.
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--watchdog-ms 500 --record "$WORK/rec-watchdog.txt"
[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
rc=0
"$POPC" run "$SCENE" -q --set run.duration=1 --set run.rate=1 --axis modbus --map "$EXACT_MAP" \
	--connect "$CONNECT" --log "$WORK/watchdog.csv" || rc=$?
stop_server
expect_rc watchdog $rc 3
[ "$(tail -n 1 "$WORK/watchdog.csv")" != "" ] &&
	tail -n 1 "$WORK/watchdog.csv" | grep -q '^# stop = safety stop: drive fault' ||
	fail "watchdog: $(tail -n 1 "$WORK/watchdog.csv")"
[ "$(rows "$WORK/watchdog.csv")" -eq 1 ] || fail "watchdog: want tick 0 only"
check_last_writes "$WORK/rec-watchdog.txt" 0x0000

# 9. a signal mid-run (real-time pacing at 1 kHz), sent once the server has
#    seen command 100 (tick 99): SIGINT, SIGTERM, SIGHUP and SIGQUIT all stop
#    safely with exit 5. The run is 60 s long, so that it is still going
#    when the signal lands however slow the machine, and a popc that ignored
#    the signal would end in 60 s (exit 0) instead of hanging the test. (A
#    background job of a script starts with SIGINT and SIGQUIT ignored; popc
#    installs its handlers over that. A SIGHUP ignored at start stays ignored,
#    as nohup asks, so popc starts with SIGHUP at its default here: under
#    nohup or a CI runner that ignores it, the HUP case would test nothing.)
signal_case() {
	local sig=$1 name=sig$1
	start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--notify-at c100 --record "$WORK/rec-$name.txt"
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	env --default-signal=HUP "$POPC" run "$SCENE" -q --set run.duration=60 --axis modbus \
		--map "$EXACT_MAP" --connect "$CONNECT" --log "$WORK/$name.csv" &
	local pid=$! line rc=0
	read -r -t 60 -u 3 line || fail "$name: the server never saw command 100"
	kill -"$sig" $pid
	wait $pid || rc=$?
	stop_server
	expect_rc "$name" $rc 5
	check_log "$WORK/$name.csv" '^# stop = signal: interrupted by a signal'
	local n
	n=$(rows "$WORK/$name.csv")
	[ "$n" -ge 99 ] || fail "$name: $n ticks logged, want 99 or more"
	check_last_writes "$WORK/rec-$name.txt" 0x0000
}
for sig in INT TERM HUP QUIT; do
	signal_case $sig
done

# 9b. SIGINT while every reply is dropped: the retry loop sees the signal
#     after the attempt in flight times out and stops with exit 5 (not 4: the
#     run ends because of the signal; the stop line says which transaction was
#     failing), and stop() makes one attempt per write. Before the stop flag
#     reached the axis, the retries ran out first: exit 4, "communication
#     lost". The signal must land before the retries run out, which the maps'
#     2 s silence bound caps: timeout_ms 100 x max_failures 20 gives the test
#     1.9 s from the server's notice of the first dropped attempt to its kill
#     (under 1 ms unloaded; the widest window a map allows).
sed -e 's/^timeout_ms = .*/timeout_ms = 100/' -e 's/^max_failures = .*/max_failures = 20/' \
	"$EXACT_MAP" >"$WORK/slow.ini"
start_server --map "$WORK/slow.ini" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--drop c$C,1000000 --notify-at c$C --record "$WORK/rec-sigretry.txt"
[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$WORK/slow.ini" \
	--connect "$CONNECT" --free-run --log "$WORK/sigretry.csv" 2>"$WORK/sigretry.err" &
POPC_PID=$!
read -r -t 60 -u 3 line || fail "sigretry: the server never saw command $C"
kill -INT $POPC_PID
rc=0
wait $POPC_PID || rc=$?
stop_server
expect_rc sigretry $rc 5
check_log "$WORK/sigretry.csv" \
	'^# stop = signal: interrupted by a signal while retrying the command write \+ position read \(FC23\)'
[ "$(rows "$WORK/sigretry.csv")" -eq $((C - 1)) ] || fail "sigretry: $(rows "$WORK/sigretry.csv") ticks"
grep -q 'safe stop incomplete' "$WORK/sigretry.err" ||
	fail "sigretry: an unconfirmed safe stop is not said: $(cat "$WORK/sigretry.err")"
check_last_writes "$WORK/rec-sigretry.txt" 0x0000

# 9c. SIGINT while start waits for ready bits that never come (enable timeout
#     60 s): start gives up at once, zero force and disable, exit 5, no tick.
#     Requests: 1 status, 2 zero force, 3 enable, 4... ready polls (request 10
#     is a poll however many of the first three were retried: max_failures 3).
sed 's/^enable_timeout_ms = .*/enable_timeout_ms = 60000/' "$EXACT_MAP" >"$WORK/stuck.ini"
start_server --map "$WORK/stuck.ini" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--never-ready --notify-at 10 --record "$WORK/rec-sigenable.txt"
[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
"$POPC" run "$SCENE" -q --axis modbus --map "$WORK/stuck.ini" --connect "$CONNECT" \
	--log "$WORK/sigenable.csv" &
POPC_PID=$!
read -r -t 60 -u 3 line || fail "sigenable: the server never saw request 10"
kill -INT $POPC_PID
rc=0
wait $POPC_PID || rc=$?
stop_server
expect_rc sigenable $rc 5
tail -n 1 "$WORK/sigenable.csv" |
	grep -q '^# stop = signal: interrupted by a signal while waiting for the ready bits' ||
	fail "sigenable: $(tail -n 1 "$WORK/sigenable.csv")"
[ "$(rows "$WORK/sigenable.csv")" -eq 0 ] || fail "sigenable: ticks logged"
check_last_writes "$WORK/rec-sigenable.txt" 0x0000

if [ "$TRANSPORT" = tcp ]; then
	# 10. the server closes the connection after command C: reconnect, completes
	run_case close 0 '^# stop = completed$' all "$EXACT_MAP" "--close-after c$C"
	stop_server
	grep -q ' 1 reconnects' "$WORK/close.err" || fail "close: want 1 reconnect: $(grep 'link:' "$WORK/close.err")"
	check_last_writes "$WORK/rec-close.txt" 0x0000

	# 11. the server goes away after replying to command C: reconnects refused,
	#     communication lost; ticks up to the one command C brought (C rows)
	run_case gone 4 '^# stop = communication lost' $C "$EXACT_MAP" "--exit-after c$C"
	wait_server_exit
else
	# 10. CRC corrupted once: retried, completes
	run_case crc1 0 '^# stop = completed$' all "$EXACT_MAP" "--corrupt-crc c$C"
	stop_server
	check_last_writes "$WORK/rec-crc1.txt" 0x0000
	# 11. CRC corrupted three times in a row: communication lost
	run_case crc 4 '^# stop = communication lost: .*Invalid CRC' $((C - 1)) \
		"$EXACT_MAP" "--corrupt-crc c$C,3"
	stop_server
	check_last_writes "$WORK/rec-crc.txt" 0x0000
fi

# 12. maps without FC23 (the command written with FC16, then the position read)
#     and with the status read on its own: drop once (completes), drop three
#     times (exit 4), the fault bit (exit 3). The exchange of command C is R
#     requests: its write, then the reads (R = 2, or 3 with the status read on
#     its own). The drop once and the fault hit its write; the three drops hit
#     its last request (a read) and the two retries of that read. Each stops
#     before tick C - 1: C - 1 ticks.
# map_cases MAP R LAST: LAST names the exchange's last request in popc's message
map_cases() {
	local map=$1 r=$2 last=$3 tag
	tag=$(basename "$map" .ini)
	run_case "$tag-drop1" 0 '^# stop = completed$' all "$map" "--drop c$C,1"
	stop_server
	grep -q ' 1 failed transactions' "$WORK/$tag-drop1.err" ||
		fail "$tag-drop1: want 1 failed transaction: $(grep 'link:' "$WORK/$tag-drop1.err")"
	check_last_writes "$WORK/rec-$tag-drop1.txt" 0x0000
	run_case "$tag-drop" 4 '^# stop = communication lost: .*3 failed transactions in a row \(last: '"$last" \
		$((C - 1)) "$map" "--drop c$C+$((r - 1)),3"
	stop_server
	check_last_writes "$WORK/rec-$tag-drop.txt" 0x0000
	run_case "$tag-fault" 3 '^# stop = safety stop: drive fault: status 0x0008' $((C - 1)) "$map" "--fault-at c$C"
	stop_server
	check_last_writes "$WORK/rec-$tag-fault.txt" 0x0000
}
HERE=$POPC_SOURCE_ROOT/tests/modbus
map_cases "$(test_map "$HERE/exact-fc16.ini")" 2 'position read'
map_cases "$(test_map "$HERE/exact-fc16-sep.ini")" 3 'status read'

# 13. the log is a pipe whose reader goes away (SIGPIPE ignored): a write
#     error ends the run (exit 1), not death by SIGPIPE (141), and the drive is
#     still zeroed and disabled. 10 s of ticks are far more than a pipe holds.
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--record "$WORK/rec-pipe.txt"
[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
"$POPC" run "$SCENE" -q --set run.duration=10 --axis modbus --map "$EXACT_MAP" \
	--connect "$CONNECT" --free-run --log - 2>"$WORK/pipe.err" | head -n 1 >/dev/null
rc=${PIPESTATUS[0]}
stop_server
expect_rc pipe "$rc" 1
grep -q 'write failed' "$WORK/pipe.err" || fail "pipe: $(cat "$WORK/pipe.err")"
check_last_writes "$WORK/rec-pipe.txt" 0x0000

[ "$TRANSPORT" = rtu ] && stop_socat
finish
