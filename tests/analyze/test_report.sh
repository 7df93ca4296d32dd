# popc-analyze report: gnuplot really draws PNG and PDF figures, the overlay,
# the tables and the index; scripts stay beside the figures and rerun there.
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
for n in none ref-energy improved variants; do
	png_ok "$R/$n.png" && ok "$n.png" || fail "$n.png missing or not a PNG"
	pdf_ok "$R/$n.pdf" && ok "$n.pdf" || fail "$n.pdf missing or not a PDF"
	[ -s "$R/$n.gp" ] || fail "$n.gp missing"
done
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
# survives in 2 x 50 x 2 rows at most.
expect_rc 0 "$A" report --no-draw --points 50 -o "$W/small" "$W/ref-energy.csv" || finish
rows=$(grep -vc '^#' "$W/small/ref-energy.dat")
awk '!/^#/ { if ($6 > mx) mx = $6; if ($6 < mn) mn = $6 } END { exit !(mx == 5 && mn == -5) }' \
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
expect_rc 2 "$A" report "$W/none.csv" && ok "missing -o: exit 2"
expect_rc 0 "$A" report --help && ok "--help"
finish
