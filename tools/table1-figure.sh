#!/bin/sh
# The figure of docs/TABLE1.md: what each reading of Table I's Prev_fc does over
# 20 s of the paper's Fig. 14 scene (controller.variant = ignore): W - E_ref and
# the PC force f_pc under controller.ignore_mode = undo (the default) and literal.
#
#   tools/table1-figure.sh [POPC [OUT.png]]
#
# POPC defaults to build/src/popc, OUT.png to docs/figures/table1-readings.png
# (paths from the source root). Needs gnuplot (pngcairo, else png). The runs are
# deterministic: the same build draws the same curves.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
popc=${1:-$root/build/src/popc}
out=${2:-$root/docs/figures/table1-readings.png}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/table1-figure.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM

for mode in undo literal; do
	"$popc" run "$root/data/scenes/fig14.ini" --set run.duration=20 \
		--set controller.ignore_mode=$mode --log "$tmp/$mode.csv" -q
	# t, W - E_ref (J), f_pc (N), by the log's column names
	awk -F, '/^#/ { next }
		!h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
		{ printf "%s %.17g %s\n", $c["t"], $c["W"] - $c["E_ref"], $c["f_pc"] }' \
		"$tmp/$mode.csv" >"$tmp/$mode.dat"
done

# the titles' figures, from the runs themselves (so they follow the code):
# undo's largest PC force and when; literal's first PC force above 0.5 N and
# its largest
stats() {
	awk '{ a = $3 < 0 ? -$3 : $3; if (a > m) { m = a; tm = $1 } if (a > 0.5 && f == "") f = $1 }
		END { printf "%.3g %.4g %s\n", m, tm, f == "" ? "never" : sprintf("%.3g", f) }' "$1"
}
set -- $(stats "$tmp/undo.dat")
undo_max=$1 undo_at=$2
set -- $(stats "$tmp/literal.dat")
lit_max=$1 lit_from=$3
term="pngcairo size 1400,900 font 'Sans,11'"
gnuplot -e "set terminal" 2>&1 | grep -q pngcairo || term="png size 1400,900"
cat >"$tmp/fig.gp" <<GP
set terminal $term
set output '$out'
set multiplot layout 2,2 title "Table I's Prev_fc, two readings: Fig. 14 scene (data/scenes/fig14.ini, variant ignore), 20 s" noenhanced
set grid
set xrange [0:20]
set xlabel 't (s)'
set ylabel 'W - E_{ref} (mJ)'
set yrange [-0.045:0.02]
set title "undo (default): Prev_fc = f_c(k-1); each excursion returns W - E_ref to its value before (Fig. 7)" noenhanced
plot '$tmp/undo.dat' using 1:(\$2*1e3) with lines lc rgb '#1f77b4' notitle
set title "literal: Prev_fc = f_e(k); an ignored reversal moves it by -K_e delta^2 / 2 = -5e-8 J" noenhanced
plot '$tmp/literal.dat' using 1:(\$2*1e3) with lines lc rgb '#d62728' notitle
set ylabel 'f_{pc} (N)'
set yrange [-5.5:5.5]
set title "undo: f_pc, at most $undo_max N (at $undo_at s), then quiet" noenhanced
plot '$tmp/undo.dat' using 1:3 with lines lc rgb '#1f77b4' notitle
set title "literal: f_pc dithers, above 0.5 N from $lit_from s, up to $lit_max N (the bound: 5 N)" noenhanced
plot '$tmp/literal.dat' using 1:3 with lines lc rgb '#d62728' notitle
unset multiplot
GP
gnuplot "$tmp/fig.gp"
echo "table1-figure: wrote $out"
