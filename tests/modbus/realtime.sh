#!/bin/bash
# A real-time run over TCP loopback at 1 kHz for 10 s completes and reports
# its period and latency statistics (issue 4). popc-servo-sim runs in real
# time (the plant follows the wall clock). How punctual the periods are is
# this machine's business, not popc's, and is not asserted; what is asserted
# is what popc must get right whatever the scheduler does:
# - the run completes, every tick logged with dt and rtt, 10001 samples;
# - the statistics popc reports are those of the periods it logged: the max
#   and the count exact, the mean to its printed digits, p50 and p99 within
#   the histogram's 1/128 of the log's own order statistics;
# - the pacing is on an absolute grid: popc never samples before its
#   deadline and skips the grid points it has missed, so over n periods with
#   S skipped the logged periods add up to at least (n + S) T and to less
#   than (n + S + 1) T plus the last period (an exact consequence of
#   wait_deadline in src/axes/modbus/modbus_axis.c, not a margin).
# The margins that are timing: the drive's watchdog and popc's response
# timeout. Measured here with the sanitized build, two CPU-bound processes
# and the rest of the suite beside it: periods up to 16.9 ms (p99.9 11.7 ms),
# and a period of 100.8 ms seen in CI, where generic.ini's 100 ms watchdog
# stopped the run. The server runs with a 1000 ms watchdog (ten times the
# worst period seen) and popc with the tests' 500 ms timeout (lib.sh).
# The scene is the paper's operator on a 1 N/m spring, with no PO/PC: the
# commands are never zero (up to 3 units of 0.01 N), and the closed loop
# stays passive for any period much shorter than 2 B_HO / K_e = 1 s. (The
# paper scene's 1000 N/m wall sits on the Colgate-Schenkel boundary at 1 ms:
# with late periods under load it gained energy and left generic.ini's soft
# limits, a verdict on the scheduler again.)
#   realtime.sh SERVO_SIM
. "$(dirname "$0")/lib.sh"

MAP=$(test_map "$DRIVES/generic.ini")
RT_SCENE=(--set environment.kind=spring --set environment.stiffness=1 --variant none)
start_server --map "$MAP" --listen tcp:127.0.0.1:0 --scene "$SCENE" --watchdog-ms 1000 \
	--record "$WORK/rec.txt"
rc=0
"$POPC" run "$SCENE" --set run.duration=10 "${RT_SCENE[@]}" --axis modbus --map "$MAP" \
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
		# the value of each word is the next word, less a trailing comma; copied, not
		# edited in place: assigning $(NF + 1) adds a field, and with i <= NF
		# the loop never ended under gawk
		for (i = 1; i < NF; i++) { val = $(i + 1); sub(/,$/, "", val); v[$i] = val + 0 }
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

# the reported period statistics against the logged periods
awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
	n++ > 0 { printf "%.17g\n", $c["dt"] }' "$WORK/rt.csv" | sort -g >"$WORK/dt.sorted"
mean_ms=$(grep '^  period dt: ' "$WORK/rt.err" | sed -n 's/.* mean \([0-9.e+-]*\) ms,.*/\1/p')
skipped=$(grep '^  period dt: ' "$WORK/rt.err" | sed -n 's/.*(skipped periods \([0-9]*\)).*/\1/p')
dt_last=$(awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
	{ v = $c["dt"] } END { print v }' "$WORK/rt.csv")
awk -F, -v mean_ms="$mean_ms" -v skipped="$skipped" -v d_last="$dt_last" -v T=0.001 '
	FNR == NR { d[++n] = $1 + 0; sum += $1; next }
	FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
	FNR == 2 {
		e = 1 / 128 + 1e-9
		# the quantile is the upper edge of the bucket of sample ceil(q n),
		# within 1/128 above it; a rank either side is allowed for the rounding
		split("0.5 0.99", qs, " "); split("dt_p50_s dt_p99_s", names, " ")
		for (j = 1; j <= 2; j++) {
			k = int(qs[j] * n + 0.999999); got = $c[names[j]]
			lo = d[k > 1 ? k - 1 : 1]; hi = d[k < n ? k + 1 : n] * (1 + e)
			if (!(got >= lo * (1 - 1e-8) && got <= hi)) {
				printf "%s %.9g s is not the log'"'"'s %.9g s (sample %d of %d)\n", names[j], got, d[k], k, n; bad = 1 }
		}
		if (!($c["dt_max_s"] >= d[n] * (1 - 1e-8) && $c["dt_max_s"] <= d[n] * (1 + 1e-8))) {
			printf "dt_max_s %.9g s is not the log'"'"'s %.9g s\n", $c["dt_max_s"], d[n]; bad = 1 }
		if (!(n == 10000 && skipped != "" && mean_ms != "")) { print "no period statistics"; bad = 1; exit }
		if (!(mean_ms * 1e-3 * n >= sum * (1 - 2e-5) && mean_ms * 1e-3 * n <= sum * (1 + 2e-5))) {
			printf "mean %s ms x %d periods is not the log'"'"'s sum %.9g s\n", mean_ms, n, sum; bad = 1 }
		lo = (n + skipped) * T - 1e-6; hi = (n + skipped + 1) * T + d_last + 1e-6
		if (!(sum >= lo && sum < hi)) {
			printf "the periods add up to %.9g s, outside [(n + S) T, (n + S + 1) T + last) = [%.9g, %.9g) s for n = %d, S = %d\n", sum, lo, hi, n, skipped; bad = 1 }
	}
	END { exit bad }' "$WORK/dt.sorted" "$WORK/sum.csv" || fail "the period statistics are not those of the logged periods"
finish
