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

# po-pc's contact oscillation decays slowly (time constant 2.2 s early, 3.2 s
# late; sustain 0.48-0.62 over 3.4-5 s logs): not a limit cycle at any length.
# With lc_sustain = 0.5 logs of 3.5-4.25 s were flagged (amplitude still above
# 50 counts there); none's sustained swing measures 0.97.
run_scene paper.ini "$W/po-pc.csv" --variant po-pc --set run.duration=3.8
expect_rc 0 "$A" chatter "$W/po-pc.csv" &&
	grep -q "^po-pc: no chatter; no limit cycle" "$W/out" &&
	ok "po-pc, 3.8 s: its decaying oscillation is no limit cycle" ||
	fail "po-pc 3.8 s: $(cat "$W/out")"

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
		grep -q "^short: chatter not checked (50 ticks, fewer than one window of 100); limit cycle not checked" "$W/out" &&
		! grep -q "no chatter\|no limit cycle" "$W/out" && ok "short log: chatter not checked, exit 2" ||
		fail "short log: $(cat "$W/out" "$W/err")"
fi
expect_rc 2 "$A" chatter --format csv "$W/short.csv" && grep -qx "short,chatter_not_checked,,," "$W/out" &&
	grep -qx "short,limit_cycle_not_checked,,," "$W/out" &&
	ok "short log csv: chatter_not_checked and limit_cycle_not_checked rows" || fail "short csv: $(cat "$W/out")"
expect_rc 2 "$A" chatter -q "$W/short.csv" && ok "short log -q: exit 2"
expect_rc 0 "$A" chatter "$W/window.csv" && grep -q "^window: no chatter" "$W/out" &&
	ok "100 ticks: one window, checked" || fail "100-tick log: $(cat "$W/out" "$W/err")"

# The limit cycle needs half its 2 s window: 1000 ticks of 1 ms. A 0.1 to 1 s
# log has a chatter verdict but none on the limit cycle: "limit cycle not
# checked" (never "no limit cycle"), a note on stderr naming its length and
# the 1000 ticks it needs (kept under -q: the exit status cannot say it), and
# the exit status of its chatter verdict (0 here). Under 0.1 s nothing was
# checked: exit 2 (above). At 1000 ticks the limit cycle is judged.
grep -v '^#' "$W/ref-energy.csv" | head -n 501 >"$W/half.csv"
grep -v '^#' "$W/ref-energy.csv" | head -n 1001 >"$W/second.csv"
lc_note="note: $W/half.csv: limit cycle not checked: the log has 500 ticks (0.5 s at T = 0.001 s), fewer than half a limit-cycle window (1000 ticks, 1 s); it needs at least 1000 ticks (1 s), or a shorter window (--threshold lc_window=S)"
if expect_rc 0 "$A" chatter "$W/half.csv"; then
	grep -qx "half: no chatter; limit cycle not checked (500 ticks, fewer than half a window: 1000)" "$W/out" &&
		grep -q "last 0.5 s: limit-cycle metrics n/a (fewer than 1000 ticks)" "$W/out" &&
		! grep -q "no limit cycle\|amplitude" "$W/out" && grep -qF "$lc_note" "$W/err" &&
		ok "0.5 s log: chatter checked, limit cycle not checked, exit 0" ||
		fail "half log: $(cat "$W/out" "$W/err")"
fi
expect_rc 0 "$A" chatter -q "$W/half.csv" && [ ! -s "$W/out" ] && grep -qF "$lc_note" "$W/err" &&
	ok "0.5 s log -q: exit 0, the note still on stderr" || fail "half -q: $(cat "$W/out" "$W/err")"
expect_rc 0 "$A" chatter --format csv "$W/half.csv" && grep -qx "half,limit_cycle_not_checked,,," "$W/out" &&
	[ "$(wc -l <"$W/out")" -eq 2 ] && ok "0.5 s log csv: limit_cycle_not_checked row" ||
	fail "half csv: $(cat "$W/out")"
# the rule follows the window: --threshold lc_window=1 needs 500 ticks
expect_rc 0 "$A" chatter --threshold lc_window=1 "$W/half.csv" && grep -q "^half: no chatter; no limit cycle" "$W/out" &&
	! grep -q "limit cycle not checked" "$W/err" && ok "lc_window=1: 500 ticks are half a window, checked" ||
	fail "half lc_window=1: $(cat "$W/out" "$W/err")"
# Those 1000 ticks are the approach: at rest until 0.5 s, the wall at 0.75 s,
# three bounces (3 mm, 2 Hz, 12 % in contact): no limit cycle, since the
# window's first quarter holds no turning point (it was flagged, exit 1).
expect_rc 0 "$A" chatter "$W/second.csv" && ! grep -q "not checked" "$W/out" "$W/err" &&
	grep -q "^second: no chatter; no limit cycle$" "$W/out" && grep -q "sustain 0," "$W/out" &&
	ok "1000 ticks: the limit cycle checked; the approach is none" || fail "1000-tick log: $(cat "$W/out" "$W/err")"
# The bounces after the approach, 1 s of them from 0.8 s on (a recording
# started in contact): ref-energy's decay (time constant about 1 s) is no limit
# cycle (it was: a ratio of 0.59 between the quarters of a 1 s log passed the
# 0.5 meant for the 1.5 s of a full window; scaled, 0.35); without PC the same
# stretch keeps its swing and is one.
grep -v '^#' "$W/ref-energy.csv" | awk 'NR == 1 || (NR > 801 && NR <= 1801)' >"$W/bounce.csv"
grep -v '^#' "$W/none.csv" | awk 'NR == 1 || (NR > 801 && NR <= 1801)' >"$W/bounce-none.csv"
expect_rc 0 "$A" chatter "$W/bounce.csv" && grep -q "^bounce: no chatter; no limit cycle$" "$W/out" &&
	ok "ref-energy's bounces, 0.8-1.8 s: no limit cycle" || fail "bounce: $(cat "$W/out" "$W/err")"
expect_rc 1 "$A" chatter "$W/bounce-none.csv" && grep -q "^bounce-none: no chatter; LIMIT CYCLE$" "$W/out" &&
	ok "none, 0.8-1.8 s: limit cycle" || fail "bounce-none: $(cat "$W/out" "$W/err")"
# compare: chatter_s and chatter_intervals empty (not 0) for the short log, its
# PC columns still filled; both filled at 100 ticks. The limit-cycle cells
# (limit_cycle, lc_amplitude, lc_frequency) empty below 1000 ticks, filled at it.
if expect_rc 0 "$A" compare --format csv "$W/short.csv" "$W/window.csv" "$W/half.csv" "$W/second.csv"; then
	awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
		{ lc = $c["limit_cycle"] $c["lc_amplitude"] $c["lc_frequency"] }
		$1 == "short" && ($c["chatter_s"] != "" || $c["chatter_intervals"] != "" || $c["pc_rms"] == "") { exit 1 }
		$1 == "window" && ($c["chatter_s"] != "0.0" || $c["chatter_intervals"] != "0") { exit 1 }
		$1 != "second" && lc != "" { exit 1 }
		$1 == "second" && ($c["limit_cycle"] == "" || $c["lc_amplitude"] == "" || $c["lc_frequency"] == "") { exit 1 }
		{ n++ } END { exit n != 4 }' "$W/out" &&
		grep -q "compare: note: .*short.csv: chatter not checked.*its chatter columns are n/a" "$W/err" &&
		grep -qF "compare: $lc_note; its limit-cycle columns are n/a" "$W/err" &&
		[ "$(grep -c "limit cycle not checked" "$W/err")" -eq 3 ] &&
		ok "compare: a short log's chatter and limit-cycle cells empty, notes" || fail "compare short: $(cat "$W/out" "$W/err")"
fi
expect_rc 0 "$A" compare --format markdown "$W/short.csv" && grep -q "^| short | unknown | 50 |.* | n/a | n/a | n/a | n/a | n/a | [-0-9.e]* | [-0-9.e]* | [-0-9.e]* | [-0-9.e]* | [-0-9.e+]* |$" "$W/out" &&
	ok "compare markdown: n/a" || fail "compare md short: $(cat "$W/out")"
expect_rc 0 "$A" compare "$W/half.csv" && grep -q "^half .*  0    0 n/a        n/a      n/a  *[-0-9.e+]*  *[-0-9.e+]*  *[-0-9.e+]*  *[-0-9.e+]*  *[-0-9.e+]*$" "$W/out" &&
	ok "compare text: limit-cycle cells n/a" || fail "compare text half: $(cat "$W/out")"
# report: the tables as compare's, the HTML cell and the log's paragraph say
# not checked, a note on stderr
if expect_rc 0 "$A" report --no-draw -o "$W/rep-short" "$W/half.csv" "$W/second.csv"; then
	grep -q "^| half | .* | n/a | n/a | n/a | [-0-9.e]* | [-0-9.e]* | [-0-9.e]* | [-0-9.e]* | [-0-9.e+]* |$" "$W/rep-short/compare.md" &&
		grep -q "^half,.*,,,[-0-9.e]*,[-0-9.e]*,[-0-9.e]*,[-0-9.e]*,[-0-9.e+]*$" "$W/rep-short/compare.csv" &&
		grep -q '<td>half</td>\|href="#half">half</a></td><td>unknown</td>.*<td>n/a</td></tr>' "$W/rep-short/index.html" &&
		grep -q 'href="#second">second</a></td><td>unknown</td>.*<td>no</td></tr>' "$W/rep-short/index.html" &&
		grep -q "No chatter flagged. Limit cycle not checked (shorter than half a limit-cycle window)." "$W/rep-short/index.md" &&
		grep -q "No chatter flagged. Limit cycle not checked" "$W/rep-short/index.html" &&
		grep -qF "report: $lc_note; its limit-cycle columns are n/a" "$W/err" &&
		ok "report: limit cycle not checked, n/a" || fail "report half: $(cat "$W/err"; grep half "$W/rep-short/index.html")"
fi

# Thresholds move the decision: an RMS threshold of twice the bound (10 N)
# flags no chatter; the absolute name of before is refused naming the new one.
expect_rc 0 "$A" chatter -q --threshold pc_rms_share=2 "$W/ref-energy.csv" && ok "--threshold pc_rms_share=2"
expect_rc 2 "$A" chatter --threshold pc_rms=10 "$W/ref-energy.csv" &&
	grep -q "threshold 'pc_rms' is relative to the scene now: use pc_rms_share" "$W/err" &&
	ok "--threshold pc_rms: refused, naming pc_rms_share" || fail "pc_rms: $(cat "$W/err")"
# the detector names its parameters (resolution_m, pc_bound_N); popc-analyze
# names them as its user sets them
expect_rc 2 "$A" chatter --threshold resolution=1e-5 "$W/ref-energy.csv" &&
	grep -qF "threshold 'resolution' is relative to the scene now: use --set encoder.resolution=M (the scene's, not a threshold)" "$W/err" &&
	! grep -q "resolution_m" "$W/err" &&
	ok "--threshold resolution: refused, naming --set encoder.resolution" || fail "resolution: $(cat "$W/err")"
expect_rc 2 "$A" chatter --threshold pc_rms=10 "$W/ref-energy.csv" &&
	grep -qF "(a share of controller.pc_bound;" "$W/err" && ! grep -q "pc_bound_N" "$W/err" &&
	ok "--threshold pc_rms: the hint names controller.pc_bound" || fail "pc_rms hint: $(cat "$W/err")"
expect_rc 2 "$A" chatter --threshold bogus=1 "$W/ref-energy.csv" && ok "unknown threshold: exit 2"
expect_rc 2 "$A" chatter --threshold pc_rms_share=-1 "$W/ref-energy.csv" && ok "negative threshold: exit 2"
expect_rc 0 "$A" chatter --help && ok "--help"
finish
