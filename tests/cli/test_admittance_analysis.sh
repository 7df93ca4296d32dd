#!/usr/bin/env bash
# Admittance logs downstream (docs/ADMITTANCE.md, "Downstream"; docs/ANALYSIS.md,
# "Admittance logs"):
# - the run summary (CSV, JSON) has the parallel PC's columns v_pc_active,
#   v_pc_rms, v_pc_max, v_pc_rms_late only for an admittance run;
# - popc-analyze chatter reads v_pc, with thresholds from the quantization:
#   the PC RMS threshold is one count's velocity r / (K T) (0.001 m/s on
#   admittance-wall.ini), in m/s; a log edited to switch v_pc by +-2 counts'
#   velocity every tick for 1 s is flagged there, by +-0.5 not;
# - compare's PC columns of an admittance log are v_pc's, equal to the run
#   summary's;
# - replay of an admittance log runs the parallel PC variants over its force
#   counts: its own variant gives its rows bit for bit, another the same v_ve
#   and its own W and v_pc; a series PC variant is refused (exit 2), and a
#   parallel PC variant on an impedance log;
# - a sweep's pc_active, pc_rms, pc_max, pc_rms_late of an admittance run are
#   its run summary's v_pc_* (m/s), not the series PC's 0;
# - report of an admittance log draws its own figure (f_meas, v_ve and v,
#   v_pc, W against time; gnuplot really drawing, when installed).
# Argument: the popc-analyze program.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
ANALYZE=${1:?popc-analyze}
T=$(mktemp -d /tmp/popc-adm-analysis-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
WALL=$SRC/data/scenes/admittance-wall.ini
# a column of a one-row CSV by name
col() { awk -F, -v name="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
	c { print $c }' "$1"; }

# ---- the run summary
expect_exit 0 "admittance-wall, parallel-pc" "$POPC" run "$WALL" --log "$T/aw.csv" \
	--summary "$T/aw.sum.csv" -q
check "  the summary has the v_pc columns, before the scene's" \
	grep -q ',rendered_stiffness,v_pc_active,v_pc_rms,v_pc_max,v_pc_rms_late,scene,' "$T/aw.sum.csv"
check "  v_pc_active is the PC's share (4.4 %)" \
	awk -v a="$(col "$T/aw.sum.csv" v_pc_active)" 'BEGIN { exit !(a > 0.04 && a < 0.05) }'
expect_exit 0 "the same run, JSON summary" "$POPC" run "$WALL" --log "$T/aw2.csv" \
	--summary "$T/aw.sum.json" --summary-format json -q
check "  the JSON has v_pc_rms_late as a number" grep -qE '"v_pc_rms_late":[0-9]' "$T/aw.sum.json"
expect_exit 0 "an impedance run" "$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=0.5 \
	--log "$T/pp.csv" --summary "$T/pp.sum.csv" -q
check "  its summary has no v_pc column" sh -c "! grep -q v_pc '$T/pp.sum.csv'"
cp "$T/pp.sum.csv" "$T/pp.before"
expect_exit 2 "an admittance row onto an impedance summary" "$POPC" run "$WALL" --set run.duration=0.1 \
	--log "$T/x.csv" --summary "$T/pp.sum.csv" -q
check "  names why" err_has "holds impedance runs' rows"
check "  the summary unchanged" cmp -s "$T/pp.before" "$T/pp.sum.csv"
expect_exit 2 "an impedance row onto an admittance summary" "$POPC" run "$SRC/data/scenes/paper.ini" \
	--set run.duration=0.1 --log "$T/y.csv" --summary "$T/aw.sum.csv" -q
check "  names why" err_has "holds admittance runs' rows"
expect_exit 0 "an admittance row onto an admittance summary" "$POPC" run "$WALL" --set run.duration=0.1 \
	--log "$T/z.csv" --summary "$T/aw.sum.csv" -q
check "  two rows of the same cells" awk -F, 'NR == 1 { n = NF } END { exit !(NR == 3 && NF == n) }' "$T/aw.sum.csv"

# ---- chatter: v_pc, thresholds from one count
expect_exit 0 "chatter on the admittance log" "$ANALYZE" chatter "$T/aw.csv"
check "  the PC RMS threshold is r / (K T) = 0.001 m/s" grep -q 'max PC RMS [0-9.e-]* m/s (threshold 0.001)' "$T/out"
# rows of 3 <= t < 4 s: v_pc = +-A, v = +-1e-4 and the count +1 every other tick
edit() { awk -F, -v a="$1" 'BEGIN { OFS = "," } /^#/ || /^t,/ { print; next }
	{ if ($1 >= 3 && $1 < 4) { k++; s = (k % 2) ? 1 : -1; $3 = $3 + (k % 2);
	  $2 = sprintf("%.17g", $3 * 1e-5); $4 = s * 1e-4; $15 = s * a } print }' "$T/aw.csv"; }
edit 0.002 >"$T/chat.csv"
expect_exit 1 "v_pc switching by 2 counts' velocity: chatter" "$ANALYZE" chatter "$T/chat.csv"
check "  the interval [3, 4) s, in m/s" grep -q 'chatter 1.000 s in 1 interval: \[3.000, 4.000) s (PC RMS up to 0.002 m/s)' "$T/out"
edit 0.0005 >"$T/calm.csv"
expect_exit 0 "by half a count's velocity: no chatter" "$ANALYZE" chatter "$T/calm.csv"

# ---- compare: the PC columns are v_pc's
expect_exit 0 "compare the admittance log, CSV" "$ANALYZE" compare "$T/aw.csv" --format csv
check "  pc_rms_late is the summary's v_pc_rms_late" awk -F, \
	-v want="$(col "$T/aw.sum.csv" v_pc_rms_late)" \
	'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "pc_rms_late") c = i; next }
	 { d = $c - want; exit !(c && want > 0 && d * d <= 1e-24 * want * want) }' "$T/out"

# ---- replay: the parallel PC variants over the recorded force counts
rows() { grep -v '^#' "$1"; }
# a column of a log by name
lcol() { awk -F, -v name="$2" '/^#/ { next } !c { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
	{ print $c }' "$1"; }
expect_exit 0 "replay the admittance log with its own variant and none" "$ANALYZE" replay "$T/aw.csv" \
	--variant parallel-pc --variant none --variant parallel-hold -o "$T/rp"
check "  its own variant: every row bit for bit" cmp -s <(rows "$T/aw.csv") <(rows "$T/rp/aw.parallel-pc.csv")
check "  the replay log names its source" grep -q '^# source = replay$' "$T/rp/aw.parallel-pc.csv"
check "  none: the same v_ve (the VE follows the force alone)" \
	cmp -s <(lcol "$T/aw.csv" v_ve) <(lcol "$T/rp/aw.none.csv" v_ve)
check "  none: v_pc 0 on every row and v = v_ve" awk -F, '/^#/ { next } !c { for (i = 1; i <= NF; i++) {
	if ($i == "v_pc") p = i; if ($i == "v_ve") e = i; if ($i == "v") v = i } c = 1; next }
	{ n++; if ($p != 0 || $v != $e) bad++ } END { exit !(n > 5000 && !bad) }' "$T/rp/aw.none.csv"
differ() { ! cmp -s <(lcol "$1" "$3") <(lcol "$2" "$3"); }
check "  none: its W differs from the PC's" differ "$T/aw.csv" "$T/rp/aw.none.csv" W
check "  parallel-hold: its v_pc differs from parallel-pc's" differ "$T/aw.csv" "$T/rp/aw.parallel-hold.csv" v_pc
check "  parallel-hold's log passes energy --check (W from its v_pc)" \
	"$ANALYZE" energy --check "$T/rp/aw.parallel-hold.csv"
check "  parallel-hold's header names its variant" \
	grep -q '^# variant = parallel-hold$' "$T/rp/aw.parallel-hold.csv"
expect_exit 2 "replay of an admittance log with a series PC variant" "$ANALYZE" replay "$T/aw.csv" \
	--variant ref-energy -o "$T/rp2"
check "  names why" err_has "is an admittance log (device.causality = admittance, header line"
check "  nothing written" test ! -e "$T/rp2/aw.ref-energy.csv"
expect_exit 2 "replay of an impedance log with a parallel PC variant" "$ANALYZE" replay "$T/pp.csv" \
	--variant parallel-hold -o "$T/rp2"
check "  names why" err_has "is an impedance log: --variant 'parallel-hold' is an admittance (parallel PC) variant"
# row 100's f_count (column 11) 1e300: no count (its cast was undefined behaviour)
awk -F, 'BEGIN { OFS = "," } /^#/ || /^t,/ { print; next } { if (++n == 100) $11 = "1e300"; print }' \
	"$T/aw.csv" >"$T/big.csv"
expect_exit 2 "replay of a log with f_count 1e300" "$ANALYZE" replay "$T/big.csv" --variant parallel-pc -o "$T/rp3"
line=$(awk '/^#/ || /^t,/ { next } ++n == 100 { print NR; exit }' "$T/big.csv")
check "  names the line and column" err_has "big.csv:$line: column 11 (f_count): 1.0000000000000001e+300 is not a whole force count within +-2^52"
expect_exit 2 "energy --check of it" "$ANALYZE" energy --check "$T/big.csv"
check "  the same" err_has "big.csv:$line: column 11 (f_count): 1.0000000000000001e+300 is not a whole"

# ---- a sweep's pc_* cells: the parallel PC's
expect_exit 0 "a sweep of admittance-wall, 1 s, parallel-pc and none" "$POPC" sweep "$WALL" \
	--set run.duration=1 --vary admittance.variant=parallel-pc,none -o "$T/sw" -q
expect_exit 0 "the parallel-pc run alone" "$POPC" run "$WALL" --set run.duration=1 --log "$T/sw1.csv" \
	--summary "$T/sw1.sum.csv" -q
# the cell NAME of the sweep row whose variant is V
swcol() { awk -F, -v name="$1" -v v="$2" 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == name) c = i;
	if ($i == "admittance.variant") a = i } next } $a == v { print $c }' "$T/sw/summary.csv"; }
for m in active rms max rms_late; do
	check "  pc_$m of the parallel-pc row is the run's v_pc_$m" \
		test "$(swcol pc_$m parallel-pc)" = "$(col "$T/sw1.sum.csv" v_pc_$m)"
done
check "  and not 0" awk -v a="$(swcol pc_active parallel-pc)" 'BEGIN { exit !(a > 0.01) }'
check "  none's pc_rms is 0.0" test "$(swcol pc_rms none)" = 0.0

# ---- refusals
# ---- report: the admittance figure
expect_exit 0 "report of the admittance log, --no-draw" "$ANALYZE" report "$T/aw.csv" -o "$T/rep0" --no-draw
check "  the script plots f_meas, v_ve, v, v_pc and W" grep -q 'title "f_meas".*' "$T/rep0/aw-admittance.gp"
check "  its data: t and five columns' min and max" awk '/^#/ { next } { exit !(NF == 11) }' \
	"$T/rep0/aw-admittance.dat"
check "  index.html lists its figure" grep -q 'aw-admittance.gp' "$T/rep0/index.html"
check "  the data's largest v_pc (column 9) is the run's v_pc_max" awk -v want="$(col "$T/aw.sum.csv" v_pc_max)" \
	'/^#/ { next } { if ($9 > m) m = $9 } END { exit !(m == want + 0) }' \
	"$T/rep0/aw-admittance.dat"
if command -v gnuplot >/dev/null 2>&1; then
	expect_exit 0 "report of the admittance log, drawn" "$ANALYZE" report "$T/aw.csv" -o "$T/rep"
	check "  a PNG of the four panels (> 20 kB)" sh -c "head -c 8 '$T/rep/aw-admittance.png' | od -An -tx1 |
		grep -q '89 50 4e 47 0d 0a 1a 0a' && [ \$(wc -c < '$T/rep/aw-admittance.png') -gt 20000 ]"
	check "  and its PDF" test -s "$T/rep/aw-admittance.pdf"
	check "  index.html shows it" grep -q '<img src="aw-admittance.png"' "$T/rep/index.html"
else
	echo "# gnuplot not installed: the drawn figure is not checked"
fi
check_summary
