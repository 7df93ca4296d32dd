#!/bin/bash
# Closed standard descriptors (issue 10): every program reopens a closed 0, 1
# or 2 on /dev/null before it opens anything, so no file or socket takes that
# number and nothing meant for stderr or stdout reaches the drive or the log;
# '--log -' or '--summary -' onto a closed stdout is refused before anything
# runs. Over TCP loopback with popc-servo-sim --lockstep, which counts the
# malformed frames it receives (a client must send none).
#   stdfds.sh SERVO_SIM POPC_ANALYZE
#
# The faults hit command C (popc-servo-sim's cC[+K], as in faults.sh):
# command 1 is the start's zero force, command c >= 2 the exchange that
# brings tick c - 1, however many transactions were retried before it; the
# map is the tests' copy with a 500 ms response timeout (lib.sh).
. "$(dirname "$0")/lib.sh"
ANALYZE=$2
DUR=0.5
C=296 # the exchange that brings tick 295
LISTEN="tcp:127.0.0.1:0"

# served_cleanly NAME: the server's exit report says 0 malformed frames
served_cleanly() {
	local srv
	srv=$(grep 'stopped after' "$WORK/srv.err")
	echo "$srv" | grep -q ' requests (0 malformed)' ||
		fail "$1: the drive received frames that are not Modbus requests: $srv; $(grep malformed "$WORK/srv.err" | head -3)"
}

# 1. stderr closed, and a reconnect (the server closes the connection after
#    command C's request): the connection took descriptor 2, and the note 'reconnected
#    to ...' went into the new connection. The log goes to stdout, so that no
#    file opens before the connection.
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--close-after c$C --record "$WORK/rec-close.txt"
rc=0
"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$EXACT_MAP" \
	--connect "$SRV_URI" --free-run --log - >"$WORK/close.csv" 2>&- || rc=$?
stop_server
expect_rc close $rc 0
served_cleanly close
check_log "$WORK/close.csv" '^# stop = completed$'
[ "$(rows "$WORK/close.csv")" -eq 501 ] || fail "close: $(rows "$WORK/close.csv") ticks, want 501"
check_last_writes "$WORK/rec-close.txt" 0x0000

# 2. stdin and stderr closed, --rt (its note 'real-time: ...' is written at
#    start, after the connection is open): the drive was left enabled
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--record "$WORK/rec-rt.txt"
rc=0
"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$EXACT_MAP" \
	--connect "$SRV_URI" --free-run --rt --log "$WORK/rt.csv" 0<&- 2>&- || rc=$?
stop_server
expect_rc rt $rc 0
served_cleanly rt
check_log "$WORK/rt.csv" '^# stop = completed$'
check_last_writes "$WORK/rec-rt.txt" 0x0000

# 3. --log FILE with stderr closed: the log took descriptor 2 and began with a
#    popc message; the analyser refused it
start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
	--close-after c$C --record "$WORK/rec-logfile.txt"
rc=0
"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$EXACT_MAP" \
	--connect "$SRV_URI" --free-run --log "$WORK/logfile.csv" 2>&- || rc=$?
stop_server
expect_rc logfile $rc 0
served_cleanly logfile
check_log "$WORK/logfile.csv" '^# stop = completed$'
head -c 6 "$WORK/logfile.csv" | grep -q '^# popc' ||
	fail "logfile: the log does not start with its header: $(head -n 1 "$WORK/logfile.csv")"
"$ANALYZE" energy "$WORK/logfile.csv" --check >"$WORK/logfile.energy" 2>&1 ||
	fail "logfile: popc-analyze energy --check refuses the log: $(cat "$WORK/logfile.energy")"
check_last_writes "$WORK/rec-logfile.txt" 0x0000

# 4. --log - (and --summary -) with stdout closed: refused, exit 2, before
#    anything connects (the whole CSV went to the drive, exit 0)
for opt in --log --summary; do
	name=stdout${opt#--}
	start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep \
		--record "$WORK/rec-$name.txt"
	rc=0
	"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$EXACT_MAP" \
		--connect "$SRV_URI" --free-run $opt - >&- 2>"$WORK/$name.err" || rc=$?
	stop_server
	expect_rc "$name" $rc 2
	grep -q "popc run: $opt -: standard output is closed" "$WORK/$name.err" ||
		fail "$name: no message naming $opt: $(cat "$WORK/$name.err")"
	grep -q 'stopped after 0 requests (0 malformed)' "$WORK/srv.err" ||
		fail "$name: the drive was reached: $(grep 'stopped after' "$WORK/srv.err")"
	[ ! -s "$WORK/rec-$name.txt" ] || fail "$name: the drive saw writes: $(cat "$WORK/rec-$name.txt")"
done

# 5. popc-servo-sim with stderr closed: its socket pair for building replies
#    took descriptor 2, so its note on the injected fault became the next
#    reply popc received (a failed transaction in the safe stop). Requests
#    after it (the safe stop) are answered through that pair (--duplicate).
rm -f "$WORK/srv.fifo"
mkfifo "$WORK/srv.fifo"
"$SIM" --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep --fault-at c$C \
	--duplicate c$C+1,100 --record "$WORK/rec-simerr.txt" >"$WORK/srv.fifo" 2>&- &
SRV_PID=$!
exec 3<"$WORK/srv.fifo"
read -r -t 10 -u 3 line || { fail "simerr: popc-servo-sim did not get ready"; finish; }
SRV_URI=${line#popc-servo-sim: listening on }
rc=0
"$POPC" run "$SCENE" --set run.duration=$DUR --axis modbus --map "$EXACT_MAP" \
	--connect "$SRV_URI" --free-run --log "$WORK/simerr.csv" 2>"$WORK/simerr.err" || rc=$?
kill -TERM "$SRV_PID"
src=0
wait "$SRV_PID" || src=$?
SRV_PID=
exec 3<&-
[ $src -eq 0 ] || fail "simerr: popc-servo-sim exited with $src"
expect_rc simerr $rc 3
check_log "$WORK/simerr.csv" '^# stop = safety stop: drive fault'
grep -q ' 0 failed transactions' "$WORK/simerr.err" ||
	fail "simerr: popc saw bad replies: $(grep 'link:' "$WORK/simerr.err")"
check_last_writes "$WORK/rec-simerr.txt" 0x0000

# 6. popc-analyze energy -o FILE with stdout closed: FILE took descriptor 1
#    and the text summary meant for stdout was written into it
"$POPC" run "$SCENE" -q --set run.duration=$DUR --log "$WORK/sim.csv" || fail "sim run"
"$ANALYZE" energy "$WORK/sim.csv" -o "$WORK/energy-open.txt" >/dev/null || fail "energy, stdout open"
rc=0
"$ANALYZE" energy "$WORK/sim.csv" -o "$WORK/energy-closed.txt" >&- || rc=$?
expect_rc energy-closed $rc 0
cmp -s "$WORK/energy-open.txt" "$WORK/energy-closed.txt" ||
	fail "energy: -o FILE with stdout closed differs: $(diff "$WORK/energy-open.txt" "$WORK/energy-closed.txt" | head -3)"

finish
