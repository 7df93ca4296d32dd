# popc-analyze chatter on the paper's scenes (seed Figs. 3, 10, 16 and the
# sampled spring without PC): chatter in the low-velocity phase for
# ref-energy, a limit cycle for none and filtered-velocity, nothing for improved.
. "$2"

run_scene fig3.ini "$W/ref-energy.csv"
run_scene no-pc.ini "$W/none.csv"
run_scene fig10.ini "$W/filtered-velocity.csv"
run_scene fig16.ini "$W/improved.csv"

# ref-energy: exit 1, chatter intervals only, all in the low-velocity phase
# (the contact settles by about 3.7 s; chatter measured from 3.81 s on).
if expect_rc 1 "$A" chatter --format csv "$W/ref-energy.csv"; then
	awk -F, 'NR > 1 && $2 == "limit_cycle" { exit 1 }
		 NR > 1 && $2 == "chatter" { n++; s += $4 - $3; if ($3 < 3.0) exit 1 }
		 END { exit !(n >= 1 && s >= 0.5) }' "$W/out" &&
		ok "ref-energy: chatter after 3 s, >= 0.5 s of it, no limit cycle" ||
		{ fail "ref-energy chatter rows"; cat "$W/out" >&2; }
fi

for v in none filtered-velocity; do
	if expect_rc 1 "$A" chatter --format csv "$W/$v.csv"; then
		awk -F, 'NR > 1 && $2 == "chatter" { exit 1 }
			 NR > 1 && $2 == "limit_cycle" { lc = 1; amp = $5 }
			 END { exit !(lc && amp > 1e-3 && amp < 2.5e-3) }' "$W/out" &&
			ok "$v: limit cycle (amplitude about 1.6 mm), no chatter" ||
			{ fail "$v: expected only a limit cycle"; cat "$W/out" >&2; }
	fi
done

expect_rc 0 "$A" chatter --format csv "$W/improved.csv" &&
	[ "$(wc -l <"$W/out")" -eq 1 ] && ok "improved: nothing flagged" ||
	{ fail "improved: flagged"; cat "$W/out" >&2; }

# Text form, several logs: exit 1 when any is flagged; names the interval.
expect_rc 1 "$A" chatter "$W/improved.csv" "$W/ref-energy.csv" &&
	grep -q "^ref-energy: chatter" "$W/out" && grep -q "^improved: no chatter; no limit cycle" "$W/out" &&
	ok "text output" || fail "text output: $(cat "$W/out")"

# A log shorter than one 100 ms window (50 ticks of 1 ms, taken from the start of
# the ref-energy run) has no verdict: chatter "not checked", exit 2, naming its
# length and the 100 ticks it needs; never "no chatter". At 100 ticks it is
# checked (the first window is full).
grep -v '^#' "$W/ref-energy.csv" | head -n 51 >"$W/short.csv"
grep -v '^#' "$W/ref-energy.csv" | head -n 101 >"$W/window.csv"
if expect_rc 2 "$A" chatter "$W/short.csv"; then
	grep -q "short.csv: chatter not checked: the log has 50 ticks (0.05 s at T = 0.001 s), fewer than one detection window of 100 ticks (0.1 s); it needs at least 100 ticks" "$W/err" &&
		grep -q "^short: chatter not checked (50 ticks, fewer than one window of 100)" "$W/out" &&
		! grep -q "no chatter" "$W/out" && ok "short log: chatter not checked, exit 2" ||
		fail "short log: $(cat "$W/out" "$W/err")"
fi
expect_rc 2 "$A" chatter --format csv "$W/short.csv" && grep -qx "short,chatter_not_checked,,," "$W/out" &&
	ok "short log csv: chatter_not_checked row" || fail "short csv: $(cat "$W/out")"
expect_rc 2 "$A" chatter -q "$W/short.csv" && ok "short log -q: exit 2"
expect_rc 0 "$A" chatter "$W/window.csv" && grep -q "^window: no chatter" "$W/out" &&
	ok "100 ticks: one window, checked" || fail "100-tick log: $(cat "$W/out" "$W/err")"
# compare: chatter_s and chatter_intervals empty (not 0) for the short log, its
# PC columns still filled; both filled at 100 ticks
if expect_rc 0 "$A" compare --format csv "$W/short.csv" "$W/window.csv"; then
	awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
		$1 == "short" && ($c["chatter_s"] != "" || $c["chatter_intervals"] != "" || $c["pc_rms"] == "") { exit 1 }
		$1 == "window" && ($c["chatter_s"] != "0" || $c["chatter_intervals"] != "0") { exit 1 }' "$W/out" &&
		grep -q "compare: note: .*short.csv: chatter not checked.*its chatter columns are n/a" "$W/err" &&
		ok "compare: a short log's chatter cells empty, note" || fail "compare short: $(cat "$W/out" "$W/err")"
fi
expect_rc 0 "$A" compare --format markdown "$W/short.csv" && grep -q "^| short | unknown | 50 |.* | n/a | n/a | 0 |" "$W/out" &&
	ok "compare markdown: n/a" || fail "compare md short: $(cat "$W/out")"

# Thresholds move the decision: a 10 N RMS threshold flags no chatter.
expect_rc 0 "$A" chatter -q --threshold pc_rms=10 "$W/ref-energy.csv" && ok "--threshold pc_rms=10"
expect_rc 2 "$A" chatter --threshold bogus=1 "$W/ref-energy.csv" && ok "unknown threshold: exit 2"
expect_rc 2 "$A" chatter --threshold pc_rms=-1 "$W/ref-energy.csv" && ok "negative threshold: exit 2"
expect_rc 0 "$A" chatter --help && ok "--help"
finish
