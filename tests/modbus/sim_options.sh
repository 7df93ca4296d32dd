#!/bin/bash
# popc-servo-sim's fault options are range-checked (issue 10): a request
# number or a count above 10^15, or a delay above a day, is refused with exit
# 2 naming the option. Before, 'first + count' overflowed a long (a UBSan
# report; in a release build the fault silently never happened). The map
# path does not exist: a value that is accepted goes on to fail on the map
# with another message, so the check is on the message, not only the code.
#   sim_options.sh SERVO_SIM
. "$(dirname "$0")/lib.sh"

# refused OPTION VALUE
refused() {
	local rc=0
	"$SIM" --map "$WORK/none.ini" --listen tcp:127.0.0.1:0 --scene "$SCENE" "$1" "$2" \
		>/dev/null 2>"$WORK/err" || rc=$?
	[ $rc -eq 2 ] && grep -q "bad value '$2' for $1" "$WORK/err" ||
		fail "$1 $2: exit $rc, $(cat "$WORK/err"), want 2 and \"bad value '$2' for $1\""
}
# accepted OPTION VALUE: gets as far as the map
accepted() {
	local rc=0
	"$SIM" --map "$WORK/none.ini" --listen tcp:127.0.0.1:0 --scene "$SCENE" "$1" "$2" \
		>/dev/null 2>"$WORK/err" || rc=$?
	grep -q "bad value" "$WORK/err" && fail "$1 $2 refused: $(cat "$WORK/err")"
	grep -q "none.ini" "$WORK/err" || fail "$1 $2: $(cat "$WORK/err")"
}

MAXL=9223372036854775807
for opt in --drop --duplicate --reorder --corrupt-crc --wrong-unit --wrong-tid --wrong-length; do
	refused $opt "1,$MAXL"                  # first + count overflowed
	refused $opt "9223372036854775000,1000"
	refused $opt "1000000000000001"
	refused $opt "1,1000000000000001"
	refused $opt "0"
	refused $opt "1,0"
	refused $opt "1,2,3"
	accepted $opt "1000000000000000,1000000000000000"
	# AT by command (cC[+K]): C and K within the same 10^15
	refused $opt "c0"
	refused $opt "c1000000000000001"
	refused $opt "c1+1000000000000001"
	refused $opt "c5++1"
	refused $opt "c5+"
	accepted $opt "c1000000000000000+1000000000000000,1000000000000000"
done
refused --delay "1,86400001"                # t + MS * 10^6 ns
refused --delay "1,$MAXL"
refused --delay "1,10,$MAXL"
accepted --delay "1000000000000000,86400000,1000000000000000"
refused --exception "1,4,$MAXL"
refused --exception "1,256"
refused --wrong-protocol "1,0"
refused --wrong-protocol "1,65536"
refused --wrong-protocol "1,1,$MAXL"
accepted --wrong-protocol "1,65535,2"

# --record never writes onto an input (issue 28: onto its own --map or
# --scene it emptied that file, exit 0): refused with exit 2 naming both,
# the file left as it was; also through a symbolic link, and onto a table
# intent's operator.table
cp "$EXACT_MAP" "$WORK/own.ini"
cp "$SCENE" "$WORK/own-scene.ini"
printf 't,value\n0,0\n1,0.001\n' >"$WORK/table.csv"
printf '[operator]\nintent = table\ntable = table.csv\n' >"$WORK/table-scene.ini"
ln -s own.ini "$WORK/link.ini"
for c in "map:$WORK/own.ini:$WORK/own.ini:the register map (--map)" \
	"scene:$WORK/own-scene.ini:$WORK/own-scene.ini:the scene (--scene)" \
	"link:$WORK/own.ini:$WORK/link.ini:the register map (--map)" \
	"table:$WORK/table-scene.ini:$WORK/table.csv:the operator table (operator.table)"; do
	IFS=: read -r name input record what <<<"$c"
	map=$WORK/own.ini scene=$SCENE
	[ "$name" = scene ] && scene=$WORK/own-scene.ini
	[ "$name" = table ] && scene=$WORK/table-scene.ini
	before=$(md5sum <"$record")
	# in the background, its stdout through a FIFO: a server that accepted
	# the record says it listens (then it is stopped by its pid: the case
	# fails), one that refused exits and the FIFO ends
	rm -f "$WORK/rec.fifo"
	mkfifo "$WORK/rec.fifo"
	"$SIM" --map "$map" --listen tcp:127.0.0.1:0 --scene "$scene" --record "$record" \
		>"$WORK/rec.fifo" 2>"$WORK/err" </dev/null &
	pid=$!
	if read -r -t 10 line <"$WORK/rec.fifo"; then
		fail "record onto $name: the server started: $line"
		kill -TERM $pid
	fi
	rc=0
	wait $pid || rc=$?
	[ $rc -eq 2 ] || fail "record onto $name: exit $rc, want 2: $(cat "$WORK/err")"
	grep -qF "popc-servo-sim: --record $record is $what" "$WORK/err" ||
		fail "record onto $name: $(cat "$WORK/err")"
	[ "$(md5sum <"$record")" = "$before" ] || fail "record onto $name: the input changed"
done
finish
