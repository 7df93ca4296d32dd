#!/bin/sh
# The figures of the delay study (docs/TELEOPERATION.md, "The delay study";
# README, "Teleoperation over delay"), drawn by gnuplot from popc's output:
#
#   teleop-delay.png  data/scenes/teleop-wall.ini (a 20 kN/m wall at the slave)
#                     at round trips 0, 50, 200 and 700 ms (forward and backward
#                     delay_ticks 0, 25, 100, 350 at 1 kHz), PCs off and on: the
#                     master's and the slave's positions (encoder x, xs) and
#                     forces (the master's command f_c, the slave's sensor fs),
#                     from each run's log (popc run --log)
#   teleop-map.png    the largest stable wall stiffness against round-trip
#                     delay, PCs off and on, from popc map's boundary.csv
#                     (docs/MAPS.md, "Teleoperation": forward delay 0 to 700
#                     ticks, backward 0, K from 1 to 1e6 N/m, criterion stable)
#
#   tools/teleop-figures.sh [POPC [OUTDIR]]
#
# POPC defaults to build/src/popc, OUTDIR to docs/figures (paths from the source
# root). Needs gnuplot with pngcairo (else png). The runs are deterministic: the
# same build draws the same curves. Prints one line per run and per map line
# (the figures' numbers); tests/cli/test_teleop_figures.sh runs it.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
popc=${1:-$root/build/src/popc}
out=${2:-$root/docs/figures}
scene=$root/data/scenes/teleop-wall.ini
tmp=$(mktemp -d "${TMPDIR:-/tmp}/teleop-figures.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
mkdir -p "$out"

# ---- the runs: 4 round trips x PCs off, on
for d in 0 25 100 350; do
	for pc in off on; do
		# exit 6 (diverged) is a result here: the log ends where it stopped
		rc=0
		"$popc" run "$scene" --set forward.delay_ticks=$d --set backward.delay_ticks=$d \
			--set teleop.tdpa=$pc --log "$tmp/$d-$pc.csv" -q 2>/dev/null || rc=$?
		if [ "$rc" -ne 0 ] && [ "$rc" -ne 6 ]; then
			echo "teleop-figures: popc run (delay $d, PCs $pc) failed, exit $rc" >&2
			exit 1
		fi
		# t, x_m, x_s (mm), f_c, f_s (N): every 5th tick (5 ms) and the last
		awk -F, '/^#/ { next }
			!h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
			{ line = sprintf("%s %.6g %.6g %.6g %.6g", $c["t"], 1e3 * $c["x"], 1e3 * $c["xs"],
				$c["f_c"], $c["fs"]) }
			n++ % 5 == 0 { print line; line = "" }
			END { if (line != "") print line }' "$tmp/$d-$pc.csv" >"$tmp/$d-$pc.dat"
		# the panel's title: how the run ended, its largest |f_c|
		awk -v rt=$((2 * d)) -v pc=$pc -v rc=$rc '
			{ a = $4 < 0 ? -$4 : $4; if (a > m) m = a; t = $1 }
			END { printf "%d ms, PCs %s: %s, max |f_c| %.3g N\n", rt, pc,
				rc == 6 ? sprintf("diverged at t = %.3g s", t) : "completed", m }' \
			"$tmp/$d-$pc.dat" | tee "$tmp/$d-$pc.title"
	done
done

# ---- the map: forward delay 0..700 ticks (round trip, backward 0), PCs off, on
"$popc" map "$scene" --variant off,on --vary forward.delay_ticks=0,10,25,50,100,200,350,500,700 \
	--set backward.delay_ticks=0 --stiffness 1:1e6 -o "$tmp/map" -q >/dev/null
# delay (ms), K_ok, K_bad of the first failure, the band's top (or K_ok), per variant
for pc in off on; do
	awk -F, -v pc=$pc 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
		$1 == pc { top = $(c["k_last_ok_N_per_m"]) != "" ? $(c["k_last_ok_N_per_m"]) : $(c["k_ok_N_per_m"]);
			print $2, $(c["k_ok_N_per_m"]), $(c["k_bad_N_per_m"]), top, $(c["outcome"]) }' \
		"$tmp/map/boundary.csv" >"$tmp/map-$pc.dat"
	awk -v pc=$pc '{ printf "map: PCs %s, round trip %s ms: %s, first failure %s N/m, stable up to %s N/m\n",
		pc, $1, $5, $3, $4 }' "$tmp/map-$pc.dat"
done

term="pngcairo size 1400,1500 font 'Sans,10'"
gnuplot -e "set terminal" 2>&1 | grep -q pngcairo || term="png size 1400,1500"
{
	echo "set terminal $term"
	echo "set output '$out/teleop-delay.png'"
	echo "set multiplot layout 4,2 title 'data/scenes/teleop-wall.ini: a 20 kN/m wall at the slave (x = 0), position-force over a delayed channel; master x (blue), slave xs (red) in mm, left; master command f_c (green), slave sensor fs (black) in N, right' noenhanced"
	echo "set grid"
	echo "set xrange [0:5]"
	echo "set xlabel 't (s)'"
	echo "set ylabel 'position (mm)'"
	echo "set y2label 'force (N)'"
	echo "set ytics nomirror"
	echo "set y2tics"
	echo "set key top left horizontal"
	for d in 0 25 100 350; do
		for pc in off on; do
			echo "set title '$(cat "$tmp/$d-$pc.title")' noenhanced"
			echo "plot '$tmp/$d-$pc.dat' using 1:2 with lines lc rgb '#1f77b4' title 'x_m', \\"
			echo "  '' using 1:3 with lines lc rgb '#d62728' title 'x_s', \\"
			echo "  '' using 1:4 axes x1y2 with lines lc rgb '#2ca02c' title 'f_c', \\"
			echo "  '' using 1:5 axes x1y2 with lines lc rgb 'black' dt 2 title 'f_s'"
		done
	done
	echo "unset multiplot"
	echo "set terminal ${term%size*}size 1100,700 font 'Sans,11'"
	echo "set output '$out/teleop-map.png'"
	echo "unset y2tics"
	echo "unset y2label"
	echo "set ytics mirror"
	echo "set title 'Largest stable wall stiffness against round-trip delay (popc map, criterion stable: completed and settled; teleop-wall.ini, backward delay 0)' noenhanced"
	echo "set logscale y"
	echo "set format y '10^{%T}'"
	echo "set xrange [-20:720]"
	echo "set yrange [1:1e6]"
	echo "set xlabel 'round-trip delay (ms): forward.delay_ticks at 1 kHz' noenhanced"
	echo "set ylabel 'wall stiffness K (N/m)'"
	echo "set key bottom left"
	echo "set grid"
	echo "plot '$tmp/map-off.dat' using 1:2:2:3 with yerrorlines lc rgb '#d62728' lw 2 title 'PCs off: first failure [K_{ok}, K_{bad}]', \\"
	echo "  '$tmp/map-on.dat' using 1:2:2:3 with yerrorlines lc rgb '#1f77b4' lw 2 dt 2 title 'PCs on: first failure (a soft wall creeps: not settled)', \\"
	echo "  '$tmp/map-on.dat' using 1:4 with linespoints lc rgb '#1f77b4' lw 2 pt 7 title 'PCs on: stable up to (the band top)', \\"
	echo "  20000 with lines lc rgb 'black' dt 3 title 'the study wall, 20 kN/m'"
	echo "unset output"
} >"$tmp/fig.gp"
gnuplot "$tmp/fig.gp"
echo "teleop-figures: wrote $out/teleop-delay.png and $out/teleop-map.png"
