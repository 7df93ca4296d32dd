# popc-analyze report's figures stay readable from 1 s to 1 h of log (issue
# 27), checked on their structure, not their pixels:
# - NAME.dat is each bucket's envelope: every bucket's min and max of each
#   column exactly as the raw log's over the bucket's ticks, every tick in one
#   bucket; the whole-log panels draw the band between them;
# - the contact response's panels are lettered (a)-(d) as the paper's,
#   positions are in mm (and counts), the whole-log position panel shows the
#   approach (no y range set), a PC force too small for the shared axis gets
#   its own scale beside it;
# - variants.png: the Okabe-Ito palette, the widest band drawn first;
# - Fig. 7: one label per point, each tick -3..+3 named once;
# - -q prints nothing, gnuplot's messages show only on failure or with -v.
. "$2"
command -v gnuplot >/dev/null 2>&1 || { echo "gnuplot not installed: skip"; exit 77; }
for v in none ref-energy improved; do run_scene paper.ini "$W/$v.csv" --variant "$v"; done

# The envelope, bucket by bucket, against the raw log: --points 50 on 5001
# ticks makes buckets of 64 ticks (two rows each, the last maybe one).
R=$W/env
expect_rc 0 "$A" report --no-draw --points 50 -o "$R" "$W/ref-energy.csv" || finish
# .dat columns: t, then the minima of x x_true v f_e f_pc f_c W E_ref W-E_ref
# E_port (columns 2..11), then their maxima (12..21)
awk -v dat="$R/ref-energy.dat" '
	BEGIN {
		# the log columns each .dat column (from 0) is made of
		split("x x_true v f_e f_pc f_c W E_ref", want, " ")
		nb = 0
		while ((getline line < dat) > 0) {
			if (line ~ /^#/) continue
			nr = split(line, c, " ")
			if (nr != 21) { print "row of " nr " cells: " line; bad = 1; exit 1 }
			key = ""
			for (i = 2; i <= 21; i++) key = key " " c[i]
			if (nb > 0 && open && key == k[nb]) { t1[nb] = c[1]; open = 0; continue }
			nb++; t0[nb] = c[1]; t1[nb] = c[1]; k[nb] = key; open = 1
			for (i = 2; i <= 21; i++) v[nb, i] = c[i]
		}
		b = 1
	}
	/^#/ { next }
	!h { for (i = 1; i <= NF; i++) col[$i] = i; h = 1; next }
	{
		t = $1 + 0
		while (b <= nb && t > t1[b] + 0) b++
		if (b > nb || t < t0[b] + 0) { print "tick t = " $1 " in no bucket"; bad = 1; exit 1 }
		n[b]++
		for (j = 1; j <= 8; j++) {
			x = $(col[want[j]]) + 0
			if (!((b, j) in mn) || x < mn[b, j]) mn[b, j] = x
			if (!((b, j) in mx) || x > mx[b, j]) mx[b, j] = x
		}
		rows++
	}
	END {
		if (bad) exit 1
		for (i = 1; i <= nb; i++) {
			cover += n[i]
			for (j = 1; j <= 8; j++)
				if (v[i, 1 + j] + 0 != mn[i, j] || v[i, 11 + j] + 0 != mx[i, j]) {
					printf "bucket %d [%s, %s] %s: min %s max %s, the log has %.17g %.17g\n",
						i, t0[i], t1[i], want[j], v[i, 1 + j], v[i, 11 + j], mn[i, j], mx[i, j]
					exit 1
				}
		}
		if (cover != rows || nb < 40 || nb > 100) { print cover " of " rows " ticks in " nb " buckets"; exit 1 }
		print nb " buckets, " rows " ticks"
	}' FS=, "$W/ref-energy.csv" >"$W/envcheck" &&
	ok "NAME.dat: every bucket's min and max of every column exactly the log's ($(cat "$W/envcheck"))" ||
	fail "envelope: $(cat "$W/envcheck")"
# the chatter band is in it: f_pc's min -5 and max +5 (the bound)
awk '!/^#/ { if ($6 < mn) mn = $6; if ($16 > mx) mx = $16 } END { exit !(mn == -5 && mx == 5) }' \
	"$R/ref-energy.dat" && ok "the +-5 N band kept" || fail "the +-5 N band"

# the scripts (test_report.sh draws them; gnuplot is run below)
R=$W/report
expect_rc 0 "$A" report --no-draw -o "$R" "$W/none.csv" "$W/ref-energy.csv" "$W/improved.csv" || finish
# The whole-log panels draw the band: f_pc's min (6) and max (16) filled
grep -q 'using 1:6:16 with filledcurves' "$R/ref-energy.gp" &&
	grep -q 'using 1:7:17 with filledcurves' "$R/ref-energy.gp" &&
	grep -q 'using 1:4:14 with filledcurves' "$R/ref-energy-fig4.gp" &&
	ok "f_pc, f_c and v drawn as min/max envelopes" || fail "no envelope in the scripts"
# Panels lettered as the paper's: (a) position, (b) velocity, (c) energy, (d) PC force
for p in '(a) position' '(b) velocity' '(c) energy' '(d) PC force'; do
	grep -q "set label 98 \"$p" "$R/ref-energy.gp" && ok "panel $p" || fail "no panel '$p' in ref-energy.gp"
done
# positions in mm, no metre ticks such as 0.000950 (and in the zooms "%g":
# ticks a quarter count apart, which fixed decimals print twice)
grep -q 'set ylabel "position x (mm)"' "$R/ref-energy.gp" && grep -q 'column(2)\*1e3' "$R/ref-energy.gp" &&
	grep -A1 'set ylabel "position (mm)"' "$R/ref-energy-fig5.gp" | grep -q 'set format y "%g"' && grep -q 'measured position x (mm)' "$R/ref-energy-fig6.gp" &&
	! grep -q '%.6f\|%.5f' "$R"/*.gp && ok "positions in mm" || fail "positions not in mm"
# the whole-log position panel sets no y range: the approach (x0 = -6.5 mm) shows
awk '/set label 98 "\(a\) position, whole log/ { a = 1 } a && /set yrange/ { exit 1 } a && /^  plot / { p = 1; exit 0 }
	END { exit !p }' \
	"$R/ref-energy.gp" && ok "the approach is not clipped" || fail "the position panel clips the approach"
# improved's PC force (+-0.04 N) on its own scale beside the shared +-5.5 N; ref-energy needs none
grep -q "this log's own f_pc scale" "$R/improved.gp" && grep -q 'shared f_pc scale' "$R/improved.gp" &&
	! grep -q "this log's own f_pc scale" "$R/ref-energy.gp" &&
	grep -q 'improved (right axis)' "$R/variants.gp" && grep -q 'set y2range' "$R/variants.gp" &&
	ok "a small PC force gets its own scale" || fail "small PC force scale"
# variants.gp: every curve's colour is the Okabe-Ito palette's, none yellow;
# in the PC force panel ref-energy (the widest band) is drawn first
# (each curve's items: "NAME.dat" using ..., each with its colour)
awk '{ n = split($0, item, /, /); for (i = 1; i <= n; i++) if (item[i] ~ /\.dat" using/) {
		c++; if (item[i] !~ /lc rgb "#(0072B2|D55E00|009E73)"/ && item[i] !~ /fc rgb "#(0072B2|D55E00|009E73)"/) bad++ } }
	END { exit !(c >= 24 && bad == 0) }' "$R/variants.gp" && ! grep -qi 'F0E442\|yellow' "$R/variants.gp" &&
	ok "palette" || fail "colours: $(grep -o 'lc rgb "[^"]*"' "$R/variants.gp" | sort -u | tr '\n' ' ')"
awk '/set label 98 "\(c\) PC force/ { p = 1 } p && /^  plot / { f = 1; exit !($0 ~ /^  plot "ref-energy.dat"/) } END { exit !f }' "$R/variants.gp" &&
	ok "ref-energy's band drawn first, under the others" || fail "draw order"
# Fig. 7: one label per point, every tick -3..+3 named once
awk '/^  set label [0-9]+ "[-+0-9 ]+" at / {
		s = $0; sub(/.* at /, "", s); sub(/ (left|right) .*/, "", s)
		if (s in at) { print "two labels at " s; exit 1 }
		at[s] = 1
		t = $0; sub(/^[^"]*"/, "", t); sub(/".*/, "", t)
		n = split(t, k, " "); for (i = 1; i <= n; i++) named[k[i]]++
	}
	END { for (i = -3; i <= 3; i++) if (named[sprintf("%+d", i)] != 1) { print "tick " i " named " named[sprintf("%+d", i)] + 0 " times"; exit 1 } }' \
	"$R/ref-energy-fig6.gp" >"$W/labels" && ok "Fig. 7: labels apart, each tick once" || fail "Fig. 7 labels: $(cat "$W/labels")"

# -q: nothing on stdout or stderr; gnuplot's warnings (a gnuplot that warns)
# show only with -v or when it fails
cat >"$W/gp-warns" <<'SH'
#!/bin/sh
echo "warning: a fake gnuplot's warning" >&2
exec gnuplot "$@"
SH
cat >"$W/gp-fails" <<'SH'
#!/bin/sh
echo "line 3: a fake gnuplot's error" >&2
exit 1
SH
chmod +x "$W/gp-warns" "$W/gp-fails"
expect_rc 0 "$A" report -q --gnuplot "$W/gp-warns" --figure 4 --figure 6 -o "$W/q" "$W/none.csv" "$W/improved.csv" &&
	[ ! -s "$W/out" ] && [ ! -s "$W/err" ] && [ -s "$W/q/improved-fig6.png" ] &&
	ok "-q prints nothing" || fail "-q printed: $(cat "$W/out" "$W/err")"
expect_rc 0 "$A" report --gnuplot "$W/gp-warns" --figure 4 -o "$W/w" "$W/none.csv" && [ ! -s "$W/err" ] &&
	grep -q 'index.html' "$W/out" && ok "gnuplot's warnings kept off the terminal" || fail "warnings leaked: $(cat "$W/err")"
expect_rc 0 "$A" report -v --gnuplot "$W/gp-warns" --figure 4 -o "$W/w" "$W/none.csv" &&
	grep -q "none-fig4.gp: warning: a fake gnuplot's warning" "$W/err" && ok "-v shows them" ||
	fail "-v: $(cat "$W/err")"
expect_rc 1 "$A" report -q --gnuplot "$W/gp-fails" --figure 4 -o "$W/f" "$W/none.csv" &&
	grep -q "none-fig4.gp: line 3: a fake gnuplot's error" "$W/err" && grep -q 'exited with status 1' "$W/err" &&
	ok "a failing gnuplot's messages shown, even with -q" || fail "failure: $(cat "$W/err")"
finish
