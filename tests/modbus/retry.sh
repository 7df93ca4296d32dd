#!/bin/bash
# A transient link fault does not break lockstep determinism when the map has
# a command sequence register: popc retries the transaction whose reply was
# lost with the same sequence value, popc-servo-sim --lockstep knows the
# repeat for a retry and answers with the current state without advancing
# the plant, and the log's x, count, f_c, W and E_ref still equal the
# simulated run's bit for bit. Without the register (the old behaviour, kept
# for maps that lack it) the retry advances the plant a second time and the
# log differs: the control case, which also shows that the faults below hit
# a request that moves the plant.
#   retry.sh SERVO_SIM tcp|rtu
#
# The faults hit command C (popc-servo-sim's cC): command 1 is the start's
# zero force, command c >= 2 the exchange that brings tick c - 1 (with FC16,
# its write), however many transactions were retried before it. The maps
# are copies with a 500 ms response timeout (lib.sh), so that only the
# injected faults fail a transaction and the counts below are exact.
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2
DUR=1.5
VARIANT=po-pc
C=896   # the exchange that brings tick 895 (t = 0.895 s), in contact

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
# the FC23 fault hits in contact (count > 0) with the PC acting on the way:
# the retried tick carries a live observer state, not a resting plant
awk -v t=$((C - 1)) 'NR == t + 1 && $2 > 0 { ok = 1 } END { exit !ok }' "$WORK/sim.cols" ||
	fail "tick $((C - 1)) of the simulated run is not in contact"

SEQ_MAP=$EXACT_MAP
grep -q '^sequence_register = ' "$SEQ_MAP" || fail "$SEQ_MAP has no sequence_register"
sed '/^sequence_register = /d' "$EXACT_MAP" >"$WORK/noseq.ini"
sed 's/^limit_N = .*/&\nsequence_register = 14/' "$(test_map "$POPC_SOURCE_ROOT/tests/modbus/exact-fc16.ini")" \
	>"$WORK/fc16-seq.ini"

# retry_case NAME MAP "SERVER OPTIONS" SAME|DIFFERENT FAILED REPEATS PERIODS
# The run completes (exit 0, every tick, zero force then disable last), the
# popc summary reports FAILED failed transactions, and the log equals (SAME)
# or differs from (DIFFERENT) the simulated run. REPEATS: the server's count
# of repeated sequence values ("-": the map has none); PERIODS: how far the
# server's plant advanced (1500 ticks and the safe stop's zero-force write,
# one more for each retry that advanced it again).
retry_case() {
	local name=$1 map=$2 sopts=$3 want=$4 failed=$5 repeats=$6 periods=$7
	# shellcheck disable=SC2086
	start_server --map "$map" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--record "$WORK/rec-$name.txt" $sopts
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	local rc=0
	"$POPC" run "$SCENE" --set run.duration=$DUR --variant $VARIANT --axis modbus --map "$map" \
		--connect "$CONNECT" --free-run --log "$WORK/$name.csv" 2>"$WORK/$name.err" || rc=$?
	stop_server
	expect_rc "$name" $rc 0
	check_log "$WORK/$name.csv" '^# stop = completed$'
	check_last_writes "$WORK/rec-$name.txt" 0x0000
	grep -q " $failed failed transactions" "$WORK/$name.err" ||
		fail "$name: want $failed failed transactions (the faults injected): $(grep -e 'link:' -e 'latency' "$WORK/$name.err")"
	cols "$WORK/$name.csv" >"$WORK/$name.cols"
	if [ "$want" = SAME ]; then
		cmp -s "$WORK/sim.cols" "$WORK/$name.cols" ||
			fail "$name: the lockstep log differs from the simulated run: $(diff "$WORK/sim.cols" "$WORK/$name.cols" | head -3)"
	else
		cmp -s "$WORK/sim.cols" "$WORK/$name.cols" &&
			fail "$name: the log equals the simulated run, but a retry without a sequence register advances the plant again"
	fi
	local srv
	srv=$(grep 'stopped after' "$WORK/srv.err")
	if [ "$repeats" != - ]; then
		echo "$srv" | grep -q "commands ($repeats repeated the sequence value: retries)" ||
			fail "$name: want $repeats repeated sequence values: $srv"
	fi
	echo "$srv" | grep -q ", $periods periods" || fail "$name: want $periods periods: $srv"
}

# 1. FC23, two replies in a row lost (max_failures 3): two retries, no extra period
retry_case fc23-drop "$SEQ_MAP" "--drop c$C,2" SAME 2 2 1501
# 2. FC23, a reply 750 ms late (timeout 500 ms): TCP reconnects (the server
#    holds the late reply until popc has closed the old connection), RTU
#    drains the late reply (250 ms into the drain's 500 ms quiet wait, see
#    faults.sh); the retry repeats the sequence value
retry_case fc23-delay "$SEQ_MAP" "--delay c$C,750" SAME 1 1 1501
grep 'came before this reply' "$WORK/srv.err" &&
	fail "fc23-delay: popc sent its next request before the late reply came: this machine stalled past the 250 ms margin"
# 3. FC16: the command write's reply lost; the read that follows is not retried
retry_case fc16-drop "$WORK/fc16-seq.ini" "--drop c$C" SAME 1 1 1501
if [ "$TRANSPORT" = rtu ]; then
	# 4. RTU: a reply with a bad CRC (the drive applied the request)
	retry_case fc23-crc "$SEQ_MAP" "--corrupt-crc c$C" SAME 1 1 1501
fi
# 5. control: the same lost reply on a map without the sequence register
#    advances the plant twice (the documented behaviour of such maps)
retry_case noseq-drop "$WORK/noseq.ini" "--drop c$C" DIFFERENT 1 - 1502

[ "$TRANSPORT" = rtu ] && stop_socat
finish
