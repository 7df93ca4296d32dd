#!/bin/bash
# Every force-mode register map shipped in data/drives/ dry-runs against popc-servo-sim
# (lockstep, TCP): the run completes (exit 0) and the server's last writes are
# zero force and the map's disable word. What is dry-run is the map's layout
# (registers, types, word orders, scales, enable words); its timing is not:
# the maps' 20 ms response timeouts and 50-100 ms drive watchdogs are made
# for a drive's own firmware, and here they would time this machine's
# scheduler (a lockstep reply waited up to 67 ms under load), so each map
# runs as a copy with the tests' 500 ms timeout (lib.sh) and the server's
# watchdog off (faults.sh tests the watchdog). A bad map (among them: no soft
# limits, a silent link allowed too long) and a bad URI are usage errors
# (exit 2) naming the file, line and key.
#   maps.sh SERVO_SIM
. "$(dirname "$0")/lib.sh"

for map in "$DRIVES"/*.ini; do
	name=$(basename "$map" .ini)
	# a position- or velocity-mode drive runs an admittance scene (modes.sh)
	grep -q '^mode = \(position\|velocity\)$' "$map" && continue
	off=$(awk -F= '/^\[enable\]/ { e = 1 } e && $1 ~ /^off/ { gsub(/[ \t]|;.*/, "", $2); print $2; exit }' "$map")
	tmap=$(test_map "$map")
	start_server --map "$tmap" --listen tcp:127.0.0.1:0 --scene "$SCENE" --lockstep \
		--watchdog-ms 0 --record "$WORK/rec-$name.txt"
	rc=0
	"$POPC" run "$SCENE" -q --set run.duration=1.5 --axis modbus --map "$tmap" --connect "$SRV_URI" \
		--free-run --log "$WORK/$name.csv" || rc=$?
	stop_server
	expect_rc "$name" $rc 0
	check_log "$WORK/$name.csv" '^# stop = completed$'
	[ "$(rows "$WORK/$name.csv")" -eq 1501 ] || fail "$name: not every tick logged"
	check_last_writes "$WORK/rec-$name.txt" "$(printf '0x%04x' "$off")"
	# the drive's own counts and units: the contact still happens (count > 0)
	cols "$WORK/$name.csv" | awk '$2 > 0 { c = 1 } END { exit !c }' || fail "$name: no contact"
done

# Issue 10: a command on the wire is finite and within limit_N. A float64
# command with newton_per_unit = 1e-320 put f / 1e-320 = -inf on the wire
# (the server, on the same layout with newton_per_unit = 1, recorded
# 'command -inf'); now popc refuses the map at load (exit 2, the keys and
# their lines named) and the drive receives no command at all.
sed 's/^newton_per_unit = 1$/newton_per_unit = 1e-320/' "$EXACT_MAP" >"$WORK/npu-tiny.ini"
start_server --map "$EXACT_MAP" --listen tcp:127.0.0.1:0 --scene "$SCENE" --lockstep \
	--record "$WORK/rec-npu-tiny.txt"
rc=0
"$POPC" run "$SCENE" -q --set run.duration=1.5 --axis modbus --map "$WORK/npu-tiny.ini" \
	--connect "$SRV_URI" --free-run --log "$WORK/npu-tiny.csv" 2>"$WORK/npu-tiny.err" || rc=$?
stop_server
expect_rc npu-tiny $rc 2
grep -q "$WORK/npu-tiny.ini:[0-9]*: command.newton_per_unit = 1e-320 (line [0-9]*), command.limit_N = 100 (line [0-9]*): limit_N is inf command units" \
	"$WORK/npu-tiny.err" || fail "npu-tiny message: $(cat "$WORK/npu-tiny.err")"
! grep -q '^command' "$WORK/rec-npu-tiny.txt" || fail "npu-tiny: the drive received $(cat "$WORK/rec-npu-tiny.txt")"
# the smallest scale that is usable (1e-300: 2e301 units on the wire for
# 20 N) runs, clamped at limit_N = 1 N (the paper's contact needs about 2.4 N):
# every command the drive recorded is finite and within 1 N, and the run ends
# with zero force and disable
sed -e 's/^newton_per_unit = 1$/newton_per_unit = 1e-300/' -e 's/^limit_N = .*/limit_N = 1/' \
	"$EXACT_MAP" >"$WORK/npu-small.ini"
start_server --map "$WORK/npu-small.ini" --listen tcp:127.0.0.1:0 --scene "$SCENE" --lockstep \
	--record "$WORK/rec-npu-small.txt"
rc=0
"$POPC" run "$SCENE" -q --set run.duration=1.5 --axis modbus --map "$WORK/npu-small.ini" \
	--connect "$SRV_URI" --free-run --log "$WORK/npu-small.csv" || rc=$?
stop_server
expect_rc npu-small $rc 0
check_last_writes "$WORK/rec-npu-small.txt" 0x0000
awk '$1 == "command" { n++; v = $2 + 0; if (!(v >= -1 && v <= 1) || $2 ~ /inf|nan/) bad = 1 }
	END { exit bad || n < 4 }' "$WORK/rec-npu-small.txt" ||
	fail "npu-small: commands beyond 1 N or not finite: $(tr '\n' '|' <"$WORK/rec-npu-small.txt")"
# (1 N / 1e-300 x 1e-300 reads back as 0.9999999999999999 N)
awk '$1 == "command" && $2 + 0 <= -0.999 { c = 1 } END { exit !c }' "$WORK/rec-npu-small.txt" ||
	fail "npu-small: the clamp never acted: $(tr '\n' '|' <"$WORK/rec-npu-small.txt")"

# the maps renamed by layout (issue 13): the old name is refused (exit 2)
# with the new one named, by path and by installed name; nothing connects
for old in "hilo-percent-torque:hilo-int32" "cia402:cia402-lohi"; do
	for m in "$DRIVES/${old%%:*}.ini" "${old%%:*}"; do
		rc=0
		(cd "$WORK" && "$POPC" run "$SCENE" -q --axis modbus --map "$m" --connect tcp:127.0.0.1:1 \
			2>"$WORK/renamed.err") || rc=$?
		expect_rc "renamed $m" $rc 2
		grep -q "cannot open the register map: .*the shipped map ${old%%:*}.ini was renamed to ${old#*:}.ini" \
			"$WORK/renamed.err" || fail "renamed $m: $(cat "$WORK/renamed.err")"
	done
done

# a map with an error: exit 2, the message names file:line and key
sed 's/^type = int32/type = int24/' "$DRIVES/generic.ini" >"$WORK/bad.ini"
rc=0
"$POPC" run "$SCENE" -q --axis modbus --map "$WORK/bad.ini" --connect tcp:127.0.0.1:1 \
	2>"$WORK/bad.err" || rc=$?
expect_rc bad-map $rc 2
grep -q "$WORK/bad.ini:[0-9]*: position.type = int24: expected one of" "$WORK/bad.err" ||
	fail "bad map message: $(cat "$WORK/bad.err")"
# soft limits are required in every map (safety is always on), min < max, and
# timeout_ms x max_failures is bounded: exit 2 with file, line and key(s)
map_error() { # NAME SED_SCRIPT MESSAGE_PATTERN
	sed "$2" "$DRIVES/generic.ini" >"$WORK/$1.ini"
	local rc=0
	"$POPC" run "$SCENE" -q --axis modbus --map "$WORK/$1.ini" --connect tcp:127.0.0.1:1 \
		2>"$WORK/$1.err" || rc=$?
	expect_rc "$1" $rc 2
	grep -q "$WORK/$1.ini$3" "$WORK/$1.err" || fail "$1 message: $(cat "$WORK/$1.err")"
}
map_error no-soft-min '/^soft_min_m/d' ': missing position.soft_min_m: the position soft limits .* are required'
map_error no-soft-max '/^soft_max_m/d' ': missing position.soft_max_m: the position soft limits .* are required'
map_error soft-order 's/^soft_max_m = .*/soft_max_m = -0.06/' \
	':[0-9]*: position.soft_max_m = -0.06: soft_max_m must be above soft_min_m = -0.05 (line [0-9]*)'
map_error silence 's/^timeout_ms = .*/timeout_ms = 1000/' \
	':[0-9]*: drive.timeout_ms = 1000 (line [0-9]*) x drive.max_failures = 3 (line [0-9]*) = 3000 ms'
# a map that cannot be opened or read (a directory) is bad input too: exit 2
for m in "$WORK/no-such-map.ini" "$WORK"; do
	rc=0
	"$POPC" run "$SCENE" -q --axis modbus --map "$m" --connect tcp:127.0.0.1:1 2>"$WORK/unread.err" || rc=$?
	expect_rc "map $m" $rc 2
	grep -q "$m: cannot \(open\|read\) the register map" "$WORK/unread.err" ||
		fail "map $m: $(cat "$WORK/unread.err")"
done
rc=0
"$POPC" run "$SCENE" -q --axis modbus --map "$DRIVES/generic.ini" --connect serial:x \
	2>"$WORK/uri.err" || rc=$?
expect_rc bad-uri $rc 2
grep -q "connect URI 'serial:x': unknown transport" "$WORK/uri.err" || fail "bad URI message"
# malformed hosts and ports are usage errors naming what is wrong, before
# anything connects (issue 28: these were tried and failed with "Connection
# refused", exit 4); port 0 is a server's (any free port), not a drive's
for uri in "tcp:127.0.0.1:+1|port must be decimal digits, 1-65535" \
	"tcp:host name:1|host 'host name': a host is an IPv4 address" \
	"tcp:999.999.999.999:1|host '999.999.999.999': an IPv4 address is four numbers 0-255" \
	"tcp:127.0.0.1:0|port 0 is for a server (any free port)"; do
	rc=0
	"$POPC" run "$SCENE" -q --axis modbus --map "$DRIVES/generic.ini" --connect "${uri%%|*}" \
		--log "$WORK/uri.csv" 2>"$WORK/uri.err" || rc=$?
	expect_rc "bad URI ${uri%%|*}" $rc 2
	grep -qF "connect URI '${uri%%|*}': ${uri#*|}" "$WORK/uri.err" ||
		fail "bad URI ${uri%%|*}: $(cat "$WORK/uri.err")"
	[ ! -e "$WORK/uri.csv" ] || fail "bad URI ${uri%%|*}: a log was written"
done
# nobody listens: a connection failure before start is a communication loss
rc=0
"$POPC" run "$SCENE" -q --axis modbus --map "$DRIVES/generic.ini" --connect tcp:127.0.0.1:1 \
	--log "$WORK/refused.csv" 2>"$WORK/refused.err" || rc=$?
expect_rc refused $rc 4
check_log "$WORK/refused.csv" '^# stop = axis start failed: .*cannot connect'
# popc-servo-sim: usage errors
rc=0
"$SIM" --map "$DRIVES/generic.ini" --listen tcp:127.0.0.1:0 2>/dev/null || rc=$?
expect_rc sim-usage $rc 2
# fault options take exactly their numbers: a value too many is refused, not
# ignored (bounded: a server that accepted one would listen until killed);
# numbers as everywhere (popc/util/parse.h: no hex), and none so large that
# first + count or MS in ns overflows (UBSan saw N + COUNT overflow a long)
for opt in "--drop 5,1,2" "--drop 0" "--drop 5,0" "--drop -1" "--delay 5" "--delay 5,80,1,1" \
	"--delay 5,80,2," "--exception 5,0" "--notify-at 1x" "--close-after 0x3" \
	"--notify-at 2.5" "--drop 9223372036854775807,2" "--drop 5,1000000000000001" \
	"--delay 5,86400001" "--fault-at 1e16" \
	"--drop c0" "--drop c5+" "--drop c+1" "--fault-at c5+-1" "--drop c5++1" "--notify-at c" \
	"--delay c5+1" "--drop c1000000000000001" "--drop c5+1000000000000001"; do
	rc=0
	# shellcheck disable=SC2086
	timeout 10 "$SIM" --map "$DRIVES/generic.ini" --listen tcp:127.0.0.1:0 --scene "$SCENE" $opt \
		>/dev/null 2>"$WORK/simopt.err" || rc=$?
	expect_rc "sim $opt" $rc 2
	grep -q "bad value '${opt#* }' for ${opt%% *}" "$WORK/simopt.err" ||
		fail "sim $opt: $(cat "$WORK/simopt.err")"
done
finish
