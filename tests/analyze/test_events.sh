# popc-analyze events: synthetic logs whose event times are known by
# construction, and a real run of the paper scene checked against a separate
# implementation of the definitions (awk) on the same log.
. "$2"

# synth.csv (T = 1 ms, delta = 1e-5 m): rest, a fast approach (3 counts per
# tick at k = 100..199), a calm stretch too short to be the settle one (a fast
# tick at k = 400), then calm from k = 401 (settle 0.401 s with the default
# 0.5 s hold) until one fast tick at k = 1200 (settle_end 1.2 s), calm to the
# end (settle_final 1.201 s).
# Fig. 5 events (PC on at k, +1 then -1, W - E_ref falls at k+1): k = 50
# (before settling: fig5_first 0.05 s) and k = 900 (fig5 0.9 s, falls 1e-6 J).
# Not events: a reversal with the PC off (k = 950), one where W - E_ref rises
# (k = 1000). Fig. 8 events (the PC turns on at k, no count at k+1): k = 300
# (fig8_first) and k = 800 (fig8 0.8 s); the PC still on at k = 801 is no new
# activation.
awk 'BEGIN {
	print "t,x,count,f_pc,W,E_ref"
	c = 0; w = 0
	for (k = 0; k <= 1500; k++) {
		d = 0
		if (k >= 100 && k <= 199) d = 3
		if (k == 400) d = 3
		if (k == 1200) d = 2
		if (k == 50 || k == 900 || k == 950 || k == 1000) d = 1
		if (k == 51 || k == 901 || k == 951 || k == 1001) d = -1
		c += d
		pc = 0
		if (k == 50 || k == 300 || k == 800 || k == 801 || k == 900 || k == 1000) pc = 0.5
		if (k == 51) w = -1e-6
		if (k == 901) w = -2e-6
		if (k == 1001) w = -1.5e-6
		printf "%.3f,%.5f,%d,%g,%g,0\n", k / 1000, c * 1e-5, c, pc, w
	}
}' >"$W/synth.csv"
expect_row='synth,0.401,1.2,1.201,0.9,-1e-06,0.8,0.05,0.3,102,2,2,0.00303,0.00304,1501'
expect_rc 0 "$A" events --format csv "$W/synth.csv" &&
	[ "$(sed -n 2p "$W/out")" = "$expect_row" ] && ok "synthetic log: every event at its known tick" ||
	fail "synthetic log: $(sed -n 2p "$W/out") (want $expect_row)"

# a shorter hold takes the first calm stretch after the approach (k = 200)
expect_rc 0 "$A" events --format csv --settle-hold 0.1 "$W/synth.csv" &&
	[ "$(sed -n 2p "$W/out" | cut -d, -f2,3,5,7)" = "0.2,0.4,0.9,0.3" ] &&
	ok "--settle-hold 0.1: settle 0.2 s, until 0.4 s, fig8 0.3 s inside it" ||
	fail "--settle-hold 0.1: $(sed -n 2p "$W/out")"

# calm throughout: settled at the first row, no event; a last tick that moves
# two counts: settle_final empty
awk 'BEGIN { print "t,count,f_pc,W,E_ref"; for (k = 0; k < 300; k++) printf "%.3f,%d,0,0,0\n", k / 1000, k % 2 }' >"$W/calm.csv"
awk 'BEGIN { print "t,count,f_pc,W,E_ref"; for (k = 0; k < 300; k++) printf "%.3f,%d,0,0,0\n", k / 1000, k == 299 ? 5 : 0 }' >"$W/lastfast.csv"
expect_rc 0 "$A" events --format csv "$W/calm.csv" "$W/lastfast.csv" &&
	[ "$(sed -n 2p "$W/out" | cut -d, -f2-10)" = "0,,0,,,,,,0" ] &&
	[ "$(sed -n 3p "$W/out" | cut -d, -f2-4)" = ",," ] &&
	ok "calm log settles at its first row; a fast last tick: no settle at all" ||
	fail "calm/lastfast: $(cat "$W/out")"

# no PC force: the figure events are not checkable (exit 2, named), the
# settling is still reported
cut -d, -f1,3 "$W/synth.csv" >"$W/nopc.csv"
expect_rc 2 "$A" events --format csv "$W/nopc.csv" &&
	grep -q "nopc.csv: no PC force" "$W/err" && [ "$(sed -n 2p "$W/out" | cut -d, -f2,5)" = "0.401," ] &&
	ok "no PC force: settle only, exit 2" || fail "no PC force: $(cat "$W/out" "$W/err")"
expect_rc 2 "$A" events --settle-hold -1 "$W/synth.csv" && grep -q "settle-hold" "$W/err" &&
	ok "--settle-hold -1 refused" || fail "--settle-hold -1"

# A real run: the same definitions in awk over the log's count, f_pc, W and
# E_ref columns give the same ticks (times kept as the log spells them).
run_scene paper.ini "$W/paper.csv" --set controller.ignore_mode=undo
expect_rc 0 "$A" events --format csv "$W/paper.csv" || finish
# both sides as %.17g, so that popc-analyze's shortest round-trip text and
# awk's own print of the same double compare equal
norm() { awk -F, '{ for (i = 1; i <= NF; i++) printf "%s%s", (i > 1 ? "," : ""), ($i == "" ? "" : sprintf("%.17g", $i)); print "" }'; }
got=$(sed -n 2p "$W/out" | cut -d, -f2-12 | norm)
ref=$(grep -v '^#' "$W/paper.csv" | awk -F, -v hold=0.5 '
NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
{
	t = $col["t"]; c = $col["count"] + 0; pc = ($col["f_pc"] + 0) != 0
	we = $col["W"] - $col["E_ref"]; n++
	d = n > 1 ? c - cp : 0
	calm = d >= -1 && d <= 1
	if (!calm) { nfast++; if (open) { send = t; open = 0 }; inrun = 0 }
	else {
		if (!inrun) { inrun = 1; rs = t; f5r = ""; f8r = "" }
		if (!settled && nfast > 0 && t - rs >= hold) { settled = 1; open = 1; s = rs; f5 = f5r; f8 = f8r }
	}
	if (n > 2 && pc1 && (dp == 1 || dp == -1) && d == -dp && we < wep) {
		n5++; if (f5f == "") f5f = tp
		if (settled) { if (f5 == "" && tp >= s) f5 = tp } else if (inrun && tp >= rs && f5r == "") f5r = tp
	}
	if (n > 1 && pc1 && !pc2 && d == 0) {
		n8++; if (f8f == "") f8f = tp
		if (settled) { if (f8 == "" && tp >= s) f8 = tp } else if (inrun && tp >= rs && f8r == "") f8r = tp
	}
	dp = d; pc2 = pc1; pc1 = pc; cp = c; tp = t; wep = we
}
END { print s "," send "," (inrun ? rs : "") "," f5 "," f8 "," f5f "," f8f "," nfast "," n5 "," n8 }' | norm)
if [ "$(echo "$got" | cut -d, -f1-4,6-)" = "$ref" ]; then
	ok "paper scene: events equal a separate implementation ($ref)"
else
	fail "paper scene: popc-analyze $got, awk $ref"
fi
# and they lie where the definitions put them: in contact, in order
settle=$(echo "$got" | cut -d, -f1); fig5=$(echo "$got" | cut -d, -f4); fig8=$(echo "$got" | cut -d, -f6)
awk -v s="$settle" -v f5="$fig5" -v f8="$fig8" 'BEGIN { exit !(s > 1 && s < 5 && f5 >= s && f8 >= s) }' &&
	ok "paper scene: settle $settle s, Fig. 5 event $fig5 s, Fig. 8 event $fig8 s" ||
	fail "paper scene events out of order: $got"
finish
