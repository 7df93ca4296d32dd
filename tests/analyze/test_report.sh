# popc-analyze report: gnuplot really draws PNG and PDF figures, the overlay,
# the tables and the index; scripts stay beside the figures and rerun there.
# Each figure names the paper figure it reproduces; force axes are shared; the
# zooms of Figs. 5 and 8 contain the events the 'events' verb finds; --figure N
# makes exactly its files; E_port is drawn when a log has the column.
. "$2"
command -v gnuplot >/dev/null 2>&1 || { echo "gnuplot not installed: skip"; exit 77; }
for v in none ref-energy improved; do run_scene paper.ini "$W/$v.csv" --variant "$v"; done

png_ok() { # valid PNG signature and a plausible size (a drawn 4-panel figure is > 20 kB)
	[ "$(od -An -tx1 -N8 "$1" | tr -d ' \n')" = "89504e470d0a1a0a" ] && [ "$(wc -c <"$1")" -gt 20000 ]
}
pdf_ok() {
	[ "$(head -c 5 "$1")" = "%PDF-" ] && [ "$(wc -c <"$1")" -gt 10000 ] && tail -c 1024 "$1" | grep -q '%%EOF'
}

R=$W/report
expect_rc 0 "$A" report -o "$R" "$W/none.csv" "$W/ref-energy.csv" "$W/improved.csv" || finish
# every figure of the default report; ref-energy has both events (Figs. 5, 8)
for n in none ref-energy improved variants ref-energy-fig4 ref-energy-fig5 ref-energy-fig6 \
	ref-energy-fig8 ref-energy-fig11 improved-fig4 improved-fig6 none-fig11; do
	png_ok "$R/$n.png" && ok "$n.png" || fail "$n.png missing or not a PNG"
	pdf_ok "$R/$n.pdf" && ok "$n.pdf" || fail "$n.pdf missing or not a PDF"
	[ -s "$R/$n.gp" ] || fail "$n.gp missing"
done
# each script names its paper figure (a comment line and the title)
names_fig() { # FILE N: "# paper_figure = N" and "paper Fig. N" in the title
	grep -q "^# paper_figure = $2 " "$R/$1.gp" && grep -q "title \"paper Fig. $2[:.]" "$R/$1.gp"
}
for pair in ref-energy:3 improved:16 ref-energy-fig4:4 ref-energy-fig5:5 ref-energy-fig6:6 \
	ref-energy-fig8:8 ref-energy-fig11:11; do
	names_fig "${pair%:*}" "${pair#*:}" && ok "${pair%:*}.gp names paper Fig. ${pair#*:}" ||
		fail "${pair%:*}.gp does not name paper Fig. ${pair#*:}"
done
grep -q '^# paper_figure = 0 ' "$R/none.gp" && grep -q 'in the form of paper Fig. 3' "$R/none.gp" &&
	ok "none: no paper figure, said so" || fail "none.gp's paper figure"
# the log and the parameter box
grep -q "log $W/ref-energy.csv (variant ref-energy)" "$R/ref-energy.gp" &&
	grep -q 'set label 99 "variant ref-energy\\nK_e = 1000 N/m, delta = 1e-05 m\\nT = 0.001 s, pc_bound = 5 N\\nignore_mode = ' \
		"$R/ref-energy.gp" && ok "log and parameter box" || fail "log or parameter box in ref-energy.gp"
# index.html says which figure reproduces which paper figure
grep -q '<td class="l"><code>LOG-fig5.png</code></td><td class="l">Fig. 5</td>' "$R/index.html" &&
	grep -q 'paper Fig. 16: contact response' "$R/index.html" && grep -q 'src="ref-energy-fig8.png"' "$R/index.html" &&
	ok "index: report figure to paper figure" || fail "index mapping"
# one f_pc scale and one f_c scale in every figure and the overlay: 1.1 x the
# largest |f_pc| of the three logs (compare.csv's pc_max; ref-energy at its 5 N
# bound: 5.5)
want=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "pc_max") k = i; next }
	$k > m { m = $k } END { printf "  set yrange [%.6g:%.6g]", -1.1 * m, 1.1 * m }' "$R/compare.csv")
scales=$(grep -h 'shared f_pc scale' "$R"/*.gp | sed 's/ *#.*//' | sort -u)
[ "$(grep -l 'shared f_pc scale' "$R"/*.gp | wc -l)" -ge 4 ] && [ "$scales" = "$want" ] &&
	grep -q 'shared f_pc scale' "$R/improved.gp" && grep -q 'shared f_pc scale' "$R/variants.gp" &&
	ok "f_pc scale shared: $scales" || fail "f_pc scales: $scales (want $want)"
[ "$(grep -h 'shared f_c scale' "$R"/*.gp | sort -u | wc -l)" -eq 1 ] && grep -q 'shared f_c scale' "$R/improved.gp" &&
	ok "f_c scale shared" || fail "f_c scales: $(grep -h 'shared f_c scale' "$R"/*.gp | sort -u)"
# The zooms contain the events the 'events' verb finds: the event's row is in
# the window's data, with ticks either side, and inside the plotted x range.
"$A" events --format csv "$W/ref-energy.csv" >"$W/ev.csv" || fail "events verb"
for fig in 5 8; do
	t=$(awk -F, -v c="fig${fig}_s" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == c) k = i; next } { print $k }' "$W/ev.csv")
	awk -v t="$t" '!/^#/ && NF { n++; if ($1 == t) at = n } END { exit !(at > 10 && n - at >= 10) }' \
		"$R/ref-energy-fig$fig.dat" &&
		grep -q "set xrange \[" "$R/ref-energy-fig$fig.gp" &&
		awk -v t="$t" '/set xrange/ { gsub(/[][]/, " "); split($3, r, ":"); exit !(r[1] < t && t < r[2]) }' \
			"$R/ref-energy-fig$fig.gp" && grep -q "here t = $(printf '%.4f' "$t") s" "$R/ref-energy-fig$fig.gp" &&
		ok "Fig. $fig zoom contains the event at t = $t s" || fail "Fig. $fig zoom misses t = $t"
done
# Fig. 4's line is the events' settle time
settle=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "settle_s") k = i; next } { print $k }' "$W/ev.csv")
grep -q "from t = $(printf '%.4g' "$settle") s" "$R/ref-energy-fig4.gp" && ok "Fig. 4 settle at $settle s" ||
	fail "Fig. 4 settle line ($settle s)"
for f in compare.csv compare.md index.md index.html; do [ -s "$R/$f" ] || fail "$f missing"; done
grep -q 'src="ref-energy.png"' "$R/index.html" && grep -q 'href="ref-energy.pdf"' "$R/index.html" &&
	grep -q '(variants.png)' "$R/index.md" && ok "index links the figures" || fail "index links"
[ "$(wc -l <"$R/compare.csv")" -eq 4 ] && ok "compare.csv rows" || fail "compare.csv"
# the chatter interval is shaded on ref-energy's PC panel, not on improved's
grep -q 'set object 1 rect' "$R/ref-energy.gp" && ! grep -q 'set object 1 rect' "$R/improved.gp" &&
	ok "chatter shaded" || fail "chatter shading"

# A script reruns by hand in the report directory (users restyle them).
rm "$R/none.png" "$R/none.pdf"
(cd "$R" && gnuplot none.gp) 2>"$W/gp.err" && png_ok "$R/none.png" && ok "none.gp reruns" ||
	fail "rerun none.gp: $(cat "$W/gp.err")"

# Decimation: 50 buckets keep the min and max, so the +-5 N chatter band
# survives in 2 x 50 x 2 rows at most (f_pc's min in column 6, its max in 16:
# test_report_figures.sh checks every bucket).
expect_rc 0 "$A" report --no-draw --points 50 -o "$W/small" "$W/ref-energy.csv" || finish
rows=$(grep -vc '^#' "$W/small/ref-energy.dat")
awk '!/^#/ { if ($16 > mx) mx = $16; if ($6 < mn) mn = $6 } END { exit !(mx == 5 && mn == -5) }' \
	"$W/small/ref-energy.dat" && [ "$rows" -le 200 ] && ok "decimated to $rows rows, +-5 N kept" ||
	fail "decimation: $rows rows"
[ ! -e "$W/small/ref-energy.png" ] && ok "--no-draw draws nothing" || fail "--no-draw drew"

# gnuplot failing is reported (exit 1), not ignored.
expect_rc 1 "$A" report --gnuplot /nonexistent/gnuplot -o "$W/nogp" "$W/none.csv" &&
	grep -q "cannot run '/nonexistent/gnuplot'" "$W/err" && ok "missing gnuplot: exit 1" ||
	fail "missing gnuplot: $(cat "$W/err")"
# A "gnuplot" that exits 0 and draws nothing, into the directory of the report
# above: the figures of that earlier run must not pass for this run's.
expect_rc 1 "$A" report --gnuplot true -o "$R" "$W/none.csv" &&
	grep -q "none.gp ran but none.png or its PDF is missing" "$W/err" && [ ! -e "$R/none.png" ] &&
	ok "stale figures are no proof of drawing: exit 1" || fail "stale figures: $(cat "$W/err")"
# A log's header is text anyone can write; its variant goes into the scripts.
# A quote or a backquote in it must not end the string or run a command.
{
	echo '# format = 1'
	echo '# source = sim'
	echo "# variant = x\" ; system(\"touch $W/pwned1\") ; print \"\`touch $W/pwned2\`"
	grep -v '^#' "$W/none.csv" | head -n 1001
} >"$W/evil.csv"
expect_rc 0 "$A" report -o "$W/evil" "$W/evil.csv" && [ ! -e "$W/pwned1" ] && [ ! -e "$W/pwned2" ] &&
	png_ok "$W/evil/evil.png" && ok "a quote or backquote in the header's variant runs nothing" ||
	fail "header injection: $(ls "$W"/pwned* 2>&1) $(cat "$W/err")"
# --figure N makes exactly its files (and the index), nothing else
only_files() { # DIR WANTED...: the directory holds exactly these
	d=$1; shift
	[ "$(ls "$d" | sort | tr '\n' ' ')" = "$(printf '%s\n' "$@" | sort | tr '\n' ' ')" ]
}
expect_rc 0 "$A" report --figure 4 -o "$W/f4" "$W/ref-energy.csv" &&
	only_files "$W/f4" index.html index.md ref-energy.dat ref-energy-fig4.gp ref-energy-fig4.png ref-energy-fig4.pdf &&
	ok "--figure 4: its files only" || fail "--figure 4: $(ls "$W/f4" | tr '\n' ' ')"
expect_rc 0 "$A" report --figure 5 -o "$W/f5" "$W/ref-energy.csv" &&
	only_files "$W/f5" index.html index.md ref-energy-fig5.dat ref-energy-fig5.gp ref-energy-fig5.png ref-energy-fig5.pdf &&
	ok "--figure 5: its files only" || fail "--figure 5: $(ls "$W/f5" | tr '\n' ' ')"
expect_rc 0 "$A" report --figure 14 -o "$W/f14" "$W/improved.csv" &&
	only_files "$W/f14" index.html index.md improved.dat improved.gp improved.png improved.pdf &&
	grep -q "^# paper_figure = 14 " "$W/f14/improved.gp" && grep -q "the paper's variant ignore; this log's improved" "$W/f14/improved.gp" &&
	ok "--figure 14 on improved: the contact response titled Fig. 14, the variants named" ||
	fail "--figure 14: $(ls "$W/f14" | tr '\n' ' ')"
# --zoom T: the window holds T's tick; none has no PC force event, its zoom still works
expect_rc 0 "$A" report --figure 4 --zoom 2.5 -o "$W/z" "$W/none.csv" &&
	awk '!/^#/ && $1 == 2.5 { f = 1 } END { exit !f }' "$W/z/none-zoom.dat" && png_ok "$W/z/none-zoom.png" &&
	ok "--zoom 2.5: the window holds t = 2.5" || fail "--zoom: $(cat "$W/err")"
# a figure asked for that no log has: a log without a PC force has no Fig. 8 event
grep -v '^#' "$W/none.csv" | cut -d, -f1-5 >"$W/nopc.csv"
expect_rc 1 "$A" report --figure 8 -o "$W/f8none" "$W/nopc.csv" && grep -q -- "--figure 8: no such event in any log" "$W/err" &&
	ok "--figure 8 with no event: exit 1, said" || fail "--figure 8 none: $(cat "$W/err")"
# bad N: exit 2 naming the allowed values, before any file is written
for bad in 9 2 abc 3.5 ""; do
	expect_rc 2 "$A" report --figure "$bad" -o "$W/bad" "$W/none.csv" &&
		grep -q "the paper figures a report draws are 3, 4, 5, 6 (or 7), 8, 10, 11, 14, 16" "$W/err" && [ ! -e "$W/bad" ] &&
		ok "--figure '$bad': exit 2, allowed values named" || fail "--figure '$bad': $(cat "$W/err")"
done
expect_rc 2 "$A" report --zoom soon -o "$W/bad" "$W/none.csv" && [ ! -e "$W/bad" ] && ok "--zoom soon: exit 2" ||
	fail "--zoom soon"
# E_port (the true port energy) beside W when the log has that column (popc's
# simulated logs do): its cells replaced by a made-up 0.9 E_ref, read by name
# and drawn in the energy panel (.dat: E_ref is column 9, E_port 11); the same
# log without the column draws no E_port
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
	!h { for (i = 1; i <= NF; i++) { if ($i == "E_port") p = i; if ($i == "E_ref") e = i }; print; h = 1; next }
	{ $p = $e * 0.9; print }' "$W/ref-energy.csv" >"$W/eport.csv"
awk -F, 'BEGIN { OFS = "," } /^#/ { print; next }
	!h { for (i = 1; i <= NF; i++) if ($i == "E_port") p = i; h = 1 }
	{ s = ""; for (i = 1; i <= NF; i++) if (i != p) s = s (s == "" ? "" : ",") $i; print s }' \
	"$W/ref-energy.csv" >"$W/noport.csv"
expect_rc 0 "$A" report --figure 3 -o "$W/ep" "$W/eport.csv" &&
	grep -q 'using 1:21 with lines .* title "E_port (true)"' "$W/ep/eport.gp" &&
	awk '!/^#/ && $11 != "NaN" { n++; if ($11 > m11) m11 = $11; if ($9 > m10) m10 = $9 }
		END { d = m11 - 0.9 * m10; exit !(n > 1000 && m10 > 0 && d * d <= 1e-10 * m10 * m10) }' "$W/ep/eport.dat" &&
	grep -q 'E_port (true)' "$R/ref-energy.gp" && png_ok "$W/ep/eport.png" &&
	ok "E_port drawn from a log that has it" || fail "E_port: $(cat "$W/err")"
expect_rc 0 "$A" report --figure 3 -o "$W/np" "$W/noport.csv" &&
	! grep -q 'E_port (true)' "$W/np/noport.gp" &&
	ok "no E_port drawn from a log without it" || fail "no E_port: $(cat "$W/err")"
expect_rc 2 "$A" report "$W/none.csv" && ok "missing -o: exit 2"
expect_rc 0 "$A" report --help && ok "--help"
finish
