#!/bin/bash
# A map can reverse the position and the command (position.direction,
# command.direction = reversed): popc negates what it reads and writes, and
# popc-servo-sim, given the same map, stores minus the position and takes
# minus the force, as a drive whose motor turns the other way. A lockstep
# run through a reversed map (position, command, both) must still equal the
# simulated run bit for bit in x, count, f_c, W and E_ref, and end with zero
# force then disable. Control: popc with a reversed command against a drive
# whose map is not reversed pushes the wrong way, and must not give the
# simulated run.
#   direction.sh SERVO_SIM tcp|rtu
. "$(dirname "$0")/lib.sh"
TRANSPORT=$2

if [ "$TRANSPORT" = rtu ]; then
	start_socat
	LISTEN="rtu:$WORK/pty-srv:1000000:8N1"
	CONNECT="rtu:$WORK/pty-cli:1000000:8N1"
else
	LISTEN="tcp:127.0.0.1:0"
fi

# reversed MAP SECTIONS...: a copy of the exact map with direction = reversed
# in each section given
reversed() {
	local out=$WORK/$1.ini
	shift
	cp "$EXACT_MAP" "$out"
	for sec in "$@"; do
		sed -i "/^\[$sec\]/a direction = reversed" "$out"
	done
	echo "$out"
}

# lockstep NAME POPC_MAP SERVER_MAP: one run; sets RC
lockstep() {
	start_server --map "$3" --listen "$LISTEN" --scene "$SCENE" --lockstep --record "$WORK/rec-$1.txt"
	[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
	RC=0
	"$POPC" run "$SCENE" --set run.duration=1.5 --variant po-pc --axis modbus --map "$2" \
		--connect "$CONNECT" --free-run --log "$WORK/mb-$1.csv" 2>"$WORK/mb-$1.err" || RC=$?
	stop_server
	cols "$WORK/mb-$1.csv" >"$WORK/mb-$1.cols"
}

"$POPC" run "$SCENE" -q --set run.duration=1.5 --variant po-pc --log "$WORK/sim.csv" ||
	fail "simulated run failed"
cols "$WORK/sim.csv" >"$WORK/sim.cols"
[ "$(wc -l <"$WORK/sim.cols")" -eq 1501 ] || fail "simulated log is not 1501 rows"

for case in "position:position" "command:command" "both:position command"; do
	name=${case%%:*}
	# shellcheck disable=SC2086
	map=$(reversed "rev-$name" ${case#*:})
	lockstep "$name" "$map" "$map"
	expect_rc "$name" $RC 0
	cmp -s "$WORK/sim.cols" "$WORK/mb-$name.cols" ||
		fail "$name reversed ($TRANSPORT): the lockstep log differs from the simulated run: $(diff "$WORK/sim.cols" "$WORK/mb-$name.cols" | head -3)"
	check_log "$WORK/mb-$name.csv" '^# stop = completed$'
	check_last_writes "$WORK/rec-$name.txt" 0x0000
	grep -q "direction: position $(case $name in position | both) echo reversed ;; *) echo normal ;; esac), command $(case $name in command | both) echo reversed ;; *) echo normal ;; esac)" \
		"$WORK/mb-$name.err" || fail "$name: the summary does not say the directions: $(grep direction "$WORK/mb-$name.err")"
	# the run saw contact (the comparison means something)
	awk '$2 > 0 { c = 1 } END { exit !c }' "$WORK/mb-$name.cols" || fail "$name: no contact"
done
# the drive really holds minus the position: with the position reversed, the
# register popc reads is the negated count (the server's table, read back
# through the normal map, gives -count: an unreversed popc sees the axis
# at the mirror position and never reaches the wall at +x)
map=$(reversed srv-position position)
lockstep mirror "$EXACT_MAP" "$map"
! cmp -s "$WORK/sim.cols" "$WORK/mb-mirror.cols" ||
	fail "a drive with a reversed position read through a normal map gave the simulated run"
# control: the command reversed on popc's side only pushes the wrong way
map=$(reversed cmd-only command)
lockstep wrong "$map" "$EXACT_MAP"
[ $RC -ne 0 ] || ! cmp -s "$WORK/sim.cols" "$WORK/mb-wrong.cols" ||
	fail "a reversed command against a drive that is not reversed gave the simulated run"
# A zero force goes over the wire as all-zero words: +0.0, never -0.0
# (8000 0000 ...), for a float command normal or reversed. Before issue 28 a
# reversed float command sent the start's and the stop's zero as -0.0, and a
# normal one every zero f_c of a tick (the device receives -f_c). 50 ticks
# at rest before the ramp: every command is zero; the record holds the last
# 8 writes (6 ticks' commands, the stop's zero force, the disable word).
for type in float32 float64; do
	for dir in normal reversed; do
		name=zero-$type-$dir
		sed "s/^type = float64/type = $type/" "$EXACT_MAP" >"$WORK/$name.ini"
		[ $dir = reversed ] && sed -i "/^\[command\]/a direction = reversed" "$WORK/$name.ini"
		start_server --map "$WORK/$name.ini" --listen "$LISTEN" --scene "$SCENE" --lockstep \
			--record "$WORK/rec-$name.txt"
		[ "$TRANSPORT" = rtu ] || CONNECT=$SRV_URI
		RC=0
		"$POPC" run "$SCENE" -q --set run.duration=0.05 --axis modbus --map "$WORK/$name.ini" \
			--connect "$CONNECT" --free-run --log "$WORK/$name.csv" 2>"$WORK/$name.err" || RC=$?
		stop_server
		expect_rc "$name" $RC 0
		check_last_writes "$WORK/rec-$name.txt" 0x0000
		[ "$(grep -c '^command ' "$WORK/rec-$name.txt")" -ge 6 ] ||
			fail "$name: fewer commands recorded than expected: $(tr '\n' '|' <"$WORK/rec-$name.txt")"
		! grep '^command ' "$WORK/rec-$name.txt" | grep -qv '^command 0 \[0000\( 0000\)*\]$' ||
			fail "$name: a zero force not sent as +0.0: $(tr '\n' '|' <"$WORK/rec-$name.txt")"
	done
done

[ "$TRANSPORT" = rtu ] && stop_socat
finish
