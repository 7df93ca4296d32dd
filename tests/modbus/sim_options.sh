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
finish
