#!/bin/bash
# A position popc uses is the reply to the request it sent (issue 10). popc
# flushes the line before every request and checks every reply against its
# request (src/axes/modbus/modbus_axis.c, check_reply); with
# data/drives/popc-exact.ini the block it reads every tick covers the command
# sequence register, whose value ties the reply to the command. Stray frames
# (a reply sent twice, replies out of order, a reply 2.5 and 3.5 timeouts
# late) and, over TCP, replies with a wrong unit id, transaction id,
# protocol id or MBAP length field, and over RTU a wrong slave address, are
# injected by popc-servo-sim --lockstep; the log must still equal the
# simulated run's bit for bit (x, count, f_c, W, E_ref): never a position one
# period old. A reply that fails the checks is a failed transaction (retried;
# max_failures in a row: communication lost, exit 4, naming the check).
#   frames.sh SERVO_SIM tcp|rtu
#
# What main did (libmodbus 3.1.6 checks the TCP transaction id and a protocol
# id whose two bytes are both non-zero, nothing else of the MBAP header, and
# nothing ties an RTU reply to its request): over RTU the duplicated, the
# reordered and the 2.5-timeouts-late reply each left a position one period
# old in the log; over TCP a unit id + 1, protocol id 1 or 256 and a length
# field + 1 were accepted (the run completed with 0 failed transactions).
#
# The faults hit command C (popc-servo-sim's cC, as in retry.sh and
# faults.sh): command 1 is the start's zero force, command c >= 2 the
# exchange that brings tick c - 1 (with fc16-seq.ini, FC16 write then FC03
# read of a block that covers the sequence register, cC is its write and
# cC+1 its read), however many transactions were retried before it. (By
# request number, N = 900, a timeout retry earlier in a run on a loaded
# machine moved the fault: exc2 logged 894 ticks, not 895.) The maps are
# copies with the tests' 500 ms response timeout (lib.sh), so that only the
# injected faults fail a transaction; the late replies are 2.5 and 3.5 of
# those timeouts.
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
DUR=1.5
VARIANT=po-pc
C=896  # the exchange that brings tick 895 (t = 0.895 s), in contact
T=$LINK_TIMEOUT_MS
# max_failures of the test maps: a late reply costs up to 3 timeouts over
# TCP; 4 x 500 ms is the maps' 2 s silence bound
MAXF=4

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

"$POPC" run "$SCENE" -q --set run.duration=$DUR --variant $VARIANT --log "$WORK/sim.csv" ||
	fail "simulated run failed"
cols "$WORK/sim.csv" >"$WORK/sim.cols"
[ "$(wc -l <"$WORK/sim.cols")" -eq 1501 ] || fail "simulated log: want 1501 rows"

sed "s/^max_failures = .*/max_failures = $MAXF/" "$EXACT_MAP" >"$WORK/fc23.ini"
sed -e "s/^max_failures = .*/max_failures = $MAXF/" -e 's/^limit_N = .*/&\nsequence_register = 14/' \
	"$(test_map "$POPC_SOURCE_ROOT/tests/modbus/exact-fc16.ini")" >"$WORK/fc16-seq.ini"

# run NAME MAP "SERVER OPTIONS": sets RC; popc's stderr in $WORK/NAME.err
run() {
	local name=$1 map=$2 sopts=$3
	# shellcheck disable=SC2086
	start_server --map "$map" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--record "$WORK/rec-$name.txt" $sopts
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	RC=0
	"$POPC" run "$SCENE" --set run.duration=$DUR --variant $VARIANT --axis modbus --map "$map" \
		--connect "$CONNECT" --free-run --log "$WORK/$name.csv" 2>"$WORK/$name.err" || RC=$?
	stop_server
	grep -q 'stopped after [0-9]* requests (0 malformed)' "$WORK/srv.err" ||
		fail "$name: the drive received malformed frames: $(grep 'stopped after' "$WORK/srv.err")"
	check_last_writes "$WORK/rec-$name.txt" 0x0000
}

# same NAME MAP "SERVER OPTIONS" FAILURES: completes, every tick, the log
# equals the simulated run; FAILURES: "some" (the fault was seen: at least
# one failed transaction reported) or "any"
same() {
	local name=$1
	run "$@"
	expect_rc "$name" $RC 0
	check_log "$WORK/$name.csv" '^# stop = completed$'
	cols "$WORK/$name.csv" >"$WORK/$name.cols"
	cmp -s "$WORK/sim.cols" "$WORK/$name.cols" ||
		fail "$name: the log differs from the simulated run ($(diff "$WORK/sim.cols" "$WORK/$name.cols" | grep -c '^>') rows): $(diff "$WORK/sim.cols" "$WORK/$name.cols" | head -3)"
	if [ "$4" = some ]; then
		grep -Eq ' [1-9][0-9]* failed transactions' "$WORK/$name.err" ||
			fail "$name: no failed transaction reported (the fault was not seen): $(grep 'link:' "$WORK/$name.err")"
	fi
}

# refused NAME MAP "SERVER OPTIONS" REASON: the fault on MAXF replies in a row
# is communication lost, the stop line names the check that failed
refused() {
	local name=$1
	run "$1" "$2" "$3"
	expect_rc "$name" $RC 4
	check_log "$WORK/$name.csv" "^# stop = communication lost: .*$MAXF failed transactions in a row \\(last: .*$4"
	[ "$(rows "$WORK/$name.csv")" -eq $((C - 1)) ] || fail "$name: $(rows "$WORK/$name.csv") ticks, want $((C - 1))"
}

M=$WORK/fc23.ini
# stray frames: never taken for the answer to a later request
same dup "$M" "--duplicate c$C" any
same dup50 "$M" "--duplicate c$C,50" any
same reorder "$M" "--reorder c$C" some
same late25 "$M" "--delay c$C,$((T * 5 / 2))" some # 2.5 timeouts
same late35 "$M" "--delay c$C,$((T * 7 / 2))" some # 3.5 timeouts
same fc16-dup-write "$WORK/fc16-seq.ini" "--duplicate c$C" any
same fc16-dup-read "$WORK/fc16-seq.ini" "--duplicate c$C+1" any
same fc16-late-read "$WORK/fc16-seq.ini" "--delay c$C+1,$((T * 5 / 2))" some

# replies that name another unit, transaction, protocol or length
same unit1 "$M" "--wrong-unit c$C" some
if [ "$TRANSPORT" = rtu ]; then
	refused unit "$M" "--wrong-unit c$C,$MAXF" 'reply from slave 2, not 1'
else
	same tid1 "$M" "--wrong-tid c$C" some
	same protocol1 "$M" "--wrong-protocol c$C,1" some
	same length1 "$M" "--wrong-length c$C" some
	refused unit "$M" "--wrong-unit c$C,$MAXF" 'reply from unit id 2, not 1'
	refused tid "$M" "--wrong-tid c$C,$MAXF" 'reply with transaction id [0-9]* to the request with'
	for id in 1 256 257; do
		refused protocol$id "$M" "--wrong-protocol c$C,$id,$MAXF" "reply with protocol id $id, not 0"
	done
	refused length "$M" "--wrong-length c$C,$MAXF" "reply's MBAP length field says 12 bytes, 11 followed"
fi

# an exception that means the map does not fit the drive (2, illegal data
# address): not retried, exit 2 naming the map
run exc2 "$M" "--exception c$C,2"
expect_rc exc2 $RC 2
check_log "$WORK/exc2.csv" '^# stop = axis error: .*fc23.ini: the drive at .* rejected the command write \+ position read \(FC23\): Illegal data address \(check the register map'
[ "$(rows "$WORK/exc2.csv")" -eq $((C - 1)) ] || fail "exc2: $(rows "$WORK/exc2.csv") ticks, want $((C - 1))"

[ "$TRANSPORT" = rtu ] && stop_socat
finish
