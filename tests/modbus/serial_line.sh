#!/bin/bash
# The RTU line keys of a map, over a socat pseudo-terminal pair:
# - drive.rtu_frame_gap_ms = 10 (Delta ASDA-A2: 10 ms of silence before and
#   after a frame): popc-servo-sim measures the silence before every request
#   from the end of the last frame it saw (its own clock, a lower bound of the
#   silence popc kept: popc waits from the reply's arrival, which is after the
#   server's write) and it must be at least 10 ms for every request; popc's
#   summary counts the requests it kept the gap before, which must be the
#   server's count of requests after a frame; and the lockstep log still
#   equals the simulated run bit for bit. Without the gap the silence is what
#   the machine takes to turn a request around (well under a millisecond),
#   so a popc that ignored the key fails the first check.
# - drive.rs485 = yes and drive.rts = up on a pseudo-terminal: it has no
#   RS-485 mode and no modem lines (the ioctls fail with ENOTTY), so popc
#   refuses before sending a frame: exit 2, the message naming the key, the
#   device and the reason; the server received no request.
#   serial_line.sh SERVO_SIM
. "$(dirname "$0")/lib.sh"

start_socat
LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
CONNECT="rtu:$WORK/pty-cli:1000000:8N1"

# with_key NAME KEY_LINE: the exact map with KEY_LINE added to [drive]
with_key() {
	sed "/^\[drive\]/a $2" "$EXACT_MAP" >"$WORK/$1.ini"
	echo "$WORK/$1.ini"
}

"$POPC" run "$SCENE" -q --set run.duration=0.2 --variant po-pc \
	--log "$WORK/sim.csv" || fail "simulated run failed"

# the frame gap
map=$(with_key gap 'rtu_frame_gap_ms = 10')
start_server --map "$map" --listen "$LISTEN" --scene "$SCENE" --lockstep --record "$WORK/rec-gap.txt"
rc=0
"$POPC" run "$SCENE" --set run.duration=0.2 --variant po-pc \
	--axis modbus --map "$map" --connect "$CONNECT" --free-run --log "$WORK/gap.csv" \
	2>"$WORK/gap.err" || rc=$?
stop_server
expect_rc gap $rc 0
check_log "$WORK/gap.csv" '^# stop = completed$'
check_last_writes "$WORK/rec-gap.txt" 0x0000
cmp -s <(cols "$WORK/sim.csv") <(cols "$WORK/gap.csv") ||
	fail "gap: the lockstep log differs from the simulated run"
srv=$(grep -o 'shortest silence before a request [0-9.]* ms ([0-9]* requests)' "$WORK/srv.err")
[ -n "$srv" ] || fail "gap: the server reports no silence: $(cat "$WORK/srv.err")"
min_ms=$(echo "$srv" | sed -E 's/.* request ([0-9.]*) ms .*/\1/')
n_srv=$(echo "$srv" | sed -E 's/.*\(([0-9]*) requests\)/\1/')
awk -v m="$min_ms" 'BEGIN { exit !(m >= 10) }' ||
	fail "gap: the server saw a request after only $min_ms ms of silence, want >= 10 ms"
popc_line=$(grep -o 'rtu frame gap: 10 ms kept before [0-9]* requests' "$WORK/gap.err")
n_popc=$(echo "$popc_line" | sed -E 's/.* before ([0-9]*) requests/\1/')
# popc keeps the gap before its first request too (counted from the port's
# opening); the server measures from its first frame on
[ -n "$n_popc" ] && [ -n "$n_srv" ] && [ "$n_popc" -eq $((n_srv + 1)) ] && [ "$n_popc" -gt 200 ] ||
	fail "gap: popc kept the gap before '$n_popc' requests, the server saw '$n_srv' after a frame (want popc = server + 1, > 200): $(grep 'frame gap' "$WORK/gap.err")"

# RS-485 mode and RTS control on a pseudo-terminal: refused before any frame
refused() { # NAME KEY_LINE MESSAGE_PATTERN
	local map
	map=$(with_key "$1" "$2")
	start_server --map "$EXACT_MAP" --listen "$LISTEN" --scene "$SCENE" --lockstep
	local rc=0
	"$POPC" run "$SCENE" -q --set run.duration=0.2 --axis modbus --map "$map" --connect "$CONNECT" \
		--free-run --log "$WORK/$1.csv" 2>"$WORK/$1.err" || rc=$?
	stop_server
	expect_rc "$1" $rc 2
	grep -q "$3" "$WORK/$1.err" || fail "$1 message: $(cat "$WORK/$1.err")"
	grep -q 'stopped after 0 requests (0 malformed)' "$WORK/srv.err" ||
		fail "$1: the drive received frames: $(cat "$WORK/srv.err")"
	[ "$(rows "$WORK/$1.csv")" -eq 0 ] || fail "$1: ticks logged"
}
refused rs485 'rs485 = yes' \
	"$WORK/rs485.ini: drive.rs485 = yes: $WORK/pty-cli cannot be put in RS-485 mode (TIOCSRS485: .*pseudo-terminal"
refused rts 'rts = up' \
	"$WORK/rts.ini: drive.rts = up: the RTS line of $WORK/pty-cli cannot be set (TIOCMGET: .*pseudo-terminal"
stop_socat
finish
