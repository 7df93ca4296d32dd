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

# Thresholds move the decision: a 10 N RMS threshold flags no chatter.
expect_rc 0 "$A" chatter -q --threshold pc_rms=10 "$W/ref-energy.csv" && ok "--threshold pc_rms=10"
expect_rc 2 "$A" chatter --threshold bogus=1 "$W/ref-energy.csv" && ok "unknown threshold: exit 2"
expect_rc 2 "$A" chatter --threshold pc_rms=-1 "$W/ref-energy.csv" && ok "negative threshold: exit 2"
expect_rc 0 "$A" chatter --help && ok "--help"
finish
