#!/bin/bash
# A real-time run over TCP loopback at 1 kHz for 10 s completes and reports
# its period and latency statistics (issue 4). popc-servo-sim runs in real
# time (the plant follows the wall clock). Timings are not asserted (a shared
# CI machine decides them); the statistics must be present and consistent:
# p50 <= p99 <= p99.9 <= max, 10001 samples, every tick logged with dt, rtt.
#   realtime.sh SERVO_SIM
. "$(dirname "$0")/lib.sh"

start_server --map "$DRIVES/generic.ini" --listen tcp:127.0.0.1:0 --scene "$SCENE" \
	--record "$WORK/rec.txt"
rc=0
"$POPC" run "$SCENE" --set run.duration=10 --axis modbus --map "$DRIVES/generic.ini" \
	--connect "$SRV_URI" --rt --log "$WORK/rt.csv" --summary "$WORK/sum.csv" 2>"$WORK/rt.err" || rc=$?
stop_server
expect_rc realtime $rc 0
check_log "$WORK/rt.csv" '^# stop = completed$'
[ "$(rows "$WORK/rt.csv")" -eq 10001 ] || fail "not every tick logged"
check_last_writes "$WORK/rec.txt" 0x0000
cat "$WORK/rt.err"

# "period dt: target 1 ms, mean M ms, p50 A ms, p99 B ms, p99.9 C ms, max D ms; overruns N ..."
for what in 'period dt' 'latency rtt'; do
	line=$(grep "^  $what: " "$WORK/rt.err") || { fail "no '$what' statistics"; continue; }
	echo "$line" | awk '{
		for (i = 1; i <= NF; i++) { k = $i; sub(/,$/, "", $(i + 1)); v[k] = $(i + 1) + 0 }
		ok = v["p50"] > 0 && v["p50"] <= v["p99"] && v["p99"] <= v["p99.9"] && v["p99.9"] <= v["max"] &&
		     v["mean"] > 0 && v["mean"] <= v["max"]
		exit !ok }' || fail "inconsistent statistics: $line"
done
grep -q 'over 10001 samples' "$WORK/rt.err" || fail "exchange count"
grep -Eq 'overruns [0-9]+ \(skipped periods [0-9]+\)' "$WORK/rt.err" || fail "overrun count missing"
grep -q 'real-time: ' "$WORK/rt.err" || fail "no note on real-time scheduling"
# the --summary row carries the axis' percentiles after the run's columns
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
	NR == 2 { ok = c["dt_p50_s"] && c["rtt_p999_s"] && c["overruns"] && NF == length(c) &&
		  $c["dt_p50_s"] > 0 && $c["dt_p50_s"] <= $c["dt_max_s"] && $c["ticks"] == 10001 }
	END { exit !(NR == 2 && ok) }' "$WORK/sum.csv" || fail "summary CSV lacks the period columns: $(cat "$WORK/sum.csv")"
# dt and rtt in every row after tick 0, positive
awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
	n++ > 0 && !($c["dt"] > 0 && $c["rtt"] > 0) { bad = 1 }
	END { exit bad || !c["dt"] || !c["rtt"] || n != 10001 }' "$WORK/rt.csv" ||
	fail "dt or rtt missing in the log"
finish
