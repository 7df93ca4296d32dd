#!/bin/bash
# Injected faults and a SIGINT end in the documented state (docs/MODBUS.md):
# the exit code, the log's final "# stop = ..." line with every completed tick
# before it, and, while the link is up, zero force then disable as the last
# writes the server saw.
#   faults.sh SERVO_SIM tcp|rtu
#
# Request numbering with data/drives/popc-exact.ini (FC23, status in the
# position block): 1 status read, 2 zero command, 3 enable, 4 ready poll,
# 5 first position read (tick 0); request n >= 6 is the exchange that brings
# tick n - 5. So a fault that stops the run at request N leaves N - 5 ticks.
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
DUR=1.5
N=400   # the request the faults hit: tick 395, in contact

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

# run_case NAME WANT_RC STOP_PATTERN WANT_ROWS MAP "SERVER OPTIONS" [popc options...]
# WANT_ROWS: a number, or "all" (1 + duration * rate).
run_case() {
	local name=$1 want=$2 pat=$3 want_rows=$4 map=$5 sopts=$6
	shift 6
	# shellcheck disable=SC2086
	start_server --map "$map" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--record "$WORK/rec-$name.txt" $sopts
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	local rc=0
	"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$map" \
		--connect "$CONNECT" --free-run --log "$WORK/$name.csv" "$@" 2>"$WORK/$name.err" || rc=$?
	expect_rc "$name" $rc "$want"
	check_log "$WORK/$name.csv" "$pat"
	local n
	n=$(rows "$WORK/$name.csv")
	[ "$want_rows" = all ] && want_rows=$(awk -v d=$DUR 'BEGIN { print d * 1000 + 1 }')
	[ "$n" -eq "$want_rows" ] || fail "$name: $n ticks logged, want $want_rows"
}

# 1. replies dropped three times in a row (max_failures = 3): communication lost
run_case drop 4 '^# stop = communication lost: .*3 failed transactions in a row' $((N - 5)) \
	"$EXACT_MAP" "--drop $N,3"
stop_server
check_last_writes "$WORK/rec-drop.txt" 0x0000

# 2. one reply dropped: retried, the run completes (a fresh position, never an old one)
run_case drop1 0 '^# stop = completed$' all "$EXACT_MAP" "--drop $N,1"
stop_server
grep -q '1 failed transactions' "$WORK/drop1.err" || fail "drop1: the failure is not reported"
check_last_writes "$WORK/rec-drop1.txt" 0x0000

# 3. a reply 80 ms late (timeout 50 ms): timeout; TCP reconnects, RTU drains the
#    late reply; the retry is answered: completes. (A single-threaded drive that
#    stays silent for max_failures timeouts is a communication loss, as in 1.)
run_case delay 0 '^# stop = completed$' all "$EXACT_MAP" "--delay $N,80"
stop_server
check_last_writes "$WORK/rec-delay.txt" 0x0000

# 4. exception 4 (server device failure) three times: communication lost
run_case exception 4 '^# stop = communication lost: .*Slave device or server failure' $((N - 5)) \
	"$EXACT_MAP" "--exception $N,4,3"
stop_server
check_last_writes "$WORK/rec-exception.txt" 0x0000

# 5. the drive raises its fault bits: safety stop
run_case fault 3 '^# stop = safety stop: drive fault: status 0x0008' $((N - 5)) \
	"$EXACT_MAP" "--fault-at $N"
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
"$POPC" run "$SCENE" -q --set run.duration=$DUR --log "$WORK/soft-sim.csv" || fail "soft: sim run"
first=$(cols "$WORK/soft-sim.csv" | awk '$2 > 100 { print NR - 1; exit }')
run_case soft 3 '^# stop = safety stop: position 0\.001[0-9]* m is outside the soft limits \[-0\.1, 0\.001\]' "$first" \
	"$WORK/soft.ini" ""
stop_server
check_last_writes "$WORK/rec-soft.txt" 0x0000

# 8. the drive's watchdog: commands 200 ms apart (run.rate = 5 Hz, paced) and a
#    100 ms watchdog: the drive faults before the first command; safety stop
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--watchdog-ms 100 --record "$WORK/rec-watchdog.txt"
[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
rc=0
"$POPC" run "$SCENE" -q --set run.duration=1 --set run.rate=5 --axis modbus --map "$EXACT_MAP" \
	--connect "$CONNECT" --log "$WORK/watchdog.csv" || rc=$?
stop_server
expect_rc watchdog $rc 3
[ "$(tail -n 1 "$WORK/watchdog.csv")" != "" ] &&
	tail -n 1 "$WORK/watchdog.csv" | grep -q '^# stop = safety stop: drive fault' ||
	fail "watchdog: $(tail -n 1 "$WORK/watchdog.csv")"
[ "$(rows "$WORK/watchdog.csv")" -eq 1 ] || fail "watchdog: want tick 0 only"
check_last_writes "$WORK/rec-watchdog.txt" 0x0000

# 9. SIGINT mid-run (real-time pacing at 1 kHz, 5 s): signal after request 300
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--notify-at 300 --record "$WORK/rec-sigint.txt"
[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
"$POPC" run "$SCENE" -q --axis modbus --map "$EXACT_MAP" --connect "$CONNECT" \
	--log "$WORK/sigint.csv" &
POPC_PID=$!
read -r -t 20 -u 3 line || fail "sigint: the server never saw request 300"
kill -INT $POPC_PID
rc=0
wait $POPC_PID || rc=$?
stop_server
expect_rc sigint $rc 5
check_log "$WORK/sigint.csv" '^# stop = signal: interrupted by a signal'
n=$(rows "$WORK/sigint.csv")
[ "$n" -ge 295 ] && [ "$n" -lt 5001 ] || fail "sigint: $n ticks logged"
check_last_writes "$WORK/rec-sigint.txt" 0x0000

if [ "$TRANSPORT" = tcp ]; then
	# 10. the server closes the connection after request N: reconnect, completes
	run_case close 0 '^# stop = completed$' all "$EXACT_MAP" "--close-after $N"
	stop_server
	grep -q '1 reconnects' "$WORK/close.err" || fail "close: the reconnect is not reported"
	check_last_writes "$WORK/rec-close.txt" 0x0000

	# 11. the server goes away after request N: reconnects refused, communication
	#     lost; ticks up to the one request N brought (N - 4 rows)
	run_case gone 4 '^# stop = communication lost' $((N - 4)) "$EXACT_MAP" "--exit-after $N"
	wait_server_exit
else
	# 10. CRC corrupted once: retried, completes
	run_case crc1 0 '^# stop = completed$' all "$EXACT_MAP" "--corrupt-crc $N"
	stop_server
	check_last_writes "$WORK/rec-crc1.txt" 0x0000
	# 11. CRC corrupted three times in a row: communication lost
	run_case crc 4 '^# stop = communication lost: .*Invalid CRC' $((N - 5)) \
		"$EXACT_MAP" "--corrupt-crc $N,3"
	stop_server
	check_last_writes "$WORK/rec-crc.txt" 0x0000
	stop_socat
fi
finish
