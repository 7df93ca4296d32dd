#!/usr/bin/env bash
# popc-analyze on teleoperation logs (docs/TELEOPERATION.md, "Analysing a
# log"): chatter per port with each port's own thresholds, named; the teleop
# verb's drift and force tracking (checked against the log's own rows);
# compare's two-port table and its refusal of a mix with one-port logs;
# replay over the recorded channel (the log's own setting: every row bit for
# bit; the PCs off: the condition breaks; another bound: clamped); report's
# teleop figure, listed in index.html. Argument: the popc-analyze program.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
ANALYZE=${1:?popc-analyze}
T=$(mktemp -d /tmp/popc-teleop-ana-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

WALL=$SRC/data/scenes/teleop-wall.ini
rows() { grep -v '^#' "$1"; }
# a cell of a CSV table (header on line 1) by column name, row by log name
cell() { awk -F, -v name="$2" -v lg="$3" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
	$1 == lg { print $c }' "$1"; }
# a column of the last row of a popc log
last() { awk -F, -v name="$2" '/^#/ { next } !c { for (i = 1; i <= NF; i++) if ($i == name) c = i; next }
	{ v = $c } END { print v }' "$1"; }

expect_exit 0 "teleop-wall for 3 s, PCs on" "$POPC" run "$WALL" --set run.duration=3 --log "$T/on.csv" -q
expect_exit 6 "the same without the PCs (diverges)" "$POPC" run "$WALL" --set run.duration=3 \
	--set teleop.tdpa=off --log "$T/off.csv" -q
expect_exit 0 "a one-port log" "$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=1 --log "$T/one.csv" -q

# ---- chatter: per port, thresholds from each port's own quantum
"$ANALYZE" chatter "$T/on.csv" >"$T/out" 2>"$T/err"
st=$?
check "chatter on a teleop log: exit 0 or 1 (checked)" test "$st" -le 1
check "  the master port named, its PC in N" grep -q '^on:master: ' "$T/out"
check "  the slave port named, its PC in m/s" sh -c "grep -A1 '^on:slave: ' '$T/out' | grep -q 'm/s (threshold'"
# master: 5 % of 20 K_e delta = K_e delta = 20000 N/m x 1e-5 m = 0.2 N;
# slave: 5 % of 20 v_1 = r / (K_e T) = 0.01 N / (20000 N/m x 1 ms) = 5e-4 m/s
check "  master threshold K_e delta = 0.2 N" sh -c "grep -A1 '^on:master' '$T/out' | grep -q '(threshold 0.2)'"
check "  slave threshold r / (K_e T) = 0.0005 m/s" sh -c "grep -A1 '^on:slave' '$T/out' | grep -q '(threshold 0.0005)'"
expect_exit "$st" "  csv: the same verdict" "$ANALYZE" chatter --format csv "$T/on.csv"
check "  csv names the port in the log cell" sh -c "! grep -v '^log,' '$T/out' | grep -qv '^on:\(master\|slave\),'"

# ---- teleop: drift and force tracking
expect_exit 0 "teleop verb, text" "$ANALYZE" teleop "$T/on.csv" "$T/off.csv"
check "  drift and force tracking lines" sh -c "grep -q 'drift x - xs: end' '$T/out' && grep -q 'force tracking f_c + fs: RMS' '$T/out'"
check "  both ports" sh -c "grep -q '  master port: PC active' '$T/out' && grep -q '  slave port: PC active' '$T/out'"
expect_exit 0 "teleop verb, csv" "$ANALYZE" teleop --format csv "$T/on.csv" "$T/off.csv"
cp "$T/out" "$T/tele.csv"
check "  drift_end_m is the last row's x - xs" awk -v a="$(cell "$T/tele.csv" drift_end_m on)" \
	-v x="$(last "$T/on.csv" x)" -v xs="$(last "$T/on.csv" xs)" 'BEGIN { exit !(a == x - xs) }'
check "  the PCs off: the delayed force tracking is exactly 0 (f_c = -fs as received)" \
	test "$(cell "$T/tele.csv" track_delayed_max_N off)" = 0
check "  the PCs on: the delayed force tracking's largest is the master PC's (within 1e-9 N)" \
	awk -v a="$(cell "$T/tele.csv" track_delayed_max_N on)" -v b="$(cell "$T/tele.csv" m_pc_max_N on)" \
	'BEGIN { d = a - b; exit !(b > 0 && d < 1e-9 && d > -1e-9) }'
check "  the PCs on: the master PC active, no port clamped" awk -v a="$(cell "$T/tele.csv" m_pc_active on)" \
	-v c="$(cell "$T/tele.csv" m_clamped on)$(cell "$T/tele.csv" s_clamped on)" 'BEGIN { exit !(a > 0 && c == "00") }'
check "  the PCs off: the smallest margin below 0 (the condition broken)" \
	awk -v m="$(cell "$T/tele.csv" m_margin_min_J off)" 'BEGIN { exit !(m < -1) }'
check "  no NaN or inf" sh -c "! grep -qiE 'nan|inf' '$T/tele.csv'"
expect_exit 0 "teleop verb, json" "$ANALYZE" teleop --format json "$T/on.csv" "$T/off.csv"
check "  json: the csv's cells" python3 "$SRC/tests/cli/json_matches_csv.py" "$T/tele.csv" "$T/out" --digits
expect_exit 2 "teleop verb on a one-port log" "$ANALYZE" teleop "$T/one.csv"
check "  says it is not a teleoperation log" err_has "is not a teleoperation log"

# ---- compare: the two-port table; a mix refused
expect_exit 0 "compare two teleop logs" "$ANALYZE" compare --format csv "$T/on.csv" "$T/off.csv"
check "  the teleop verb's table" cmp -s "$T/out" "$T/tele.csv"
expect_exit 0 "compare, markdown" "$ANALYZE" compare --format markdown "$T/on.csv" "$T/off.csv"
check "  a Markdown table of 2 rows" sh -c "[ \$(grep -c '^| ' '$T/out') -eq 3 ]"
expect_exit 2 "compare a teleop log with a one-port log" "$ANALYZE" compare "$T/on.csv" "$T/one.csv"
check "  names both and says why" err_has "on.csv is a teleoperation log (teleop.architecture = position-force) and $T/one.csv a one-port log"
check "  nothing on stdout" test ! -s "$T/out"

# ---- replay over the recorded channel
expect_exit 0 "replay with the PCs on and off" "$ANALYZE" replay "$T/on.csv" --variant all -o "$T/rp"
check "  the log's own setting: every row bit for bit" cmp -s <(rows "$T/on.csv") <(rows "$T/rp/on.tdpa-on.csv")
check "  the header says source = replay" grep -qx '# source = replay' "$T/rp/on.tdpa-on.csv"
check "  the PCs off: another log" bash -c "! cmp -s <(grep -v '^#' '$T/on.csv') <(grep -v '^#' '$T/rp/on.tdpa-off.csv')"
check "  its header says tdpa = off" sh -c "grep -A3 -x '# \[teleop\]' '$T/rp/on.tdpa-off.csv' | grep -qx '# tdpa = off'"
check "  the recorded motion kept (x, xs, fs, vs_rx)" cmp -s \
	<(rows "$T/on.csv" | cut -d, -f1,2,13,17,18) <(rows "$T/rp/on.tdpa-off.csv" | cut -d, -f1,2,13,17,18)
expect_exit 1 "  energy --check: recomputed bit for bit, the condition broken" \
	"$ANALYZE" energy --check "$T/rp/on.tdpa-off.csv"
check "  rows differing 0, condition broken" grep -q "rows differing 0  two-port condition broken on [1-9]" "$T/out"
expect_exit 0 "replay with a slave PC bound of 0.01 m/s" "$ANALYZE" replay "$T/on.csv" --variant tdpa-on \
	--set teleop.slave_pc_bound=0.01 --prefix "$T/b."
check "  the slave PC clamped on some row (flag 8)" sh -c "grep -v '^#' '$T/b.tdpa-on.csv' | awk -F, 'NR > 1 && int(\$11 / 8) % 2 {f = 1} END {exit !f}'"
check "  the header says the bound" grep -qx '# slave_pc_bound = 0.01' "$T/b.tdpa-on.csv"
expect_exit 2 "replay a teleop log with a one-port variant" "$ANALYZE" replay "$T/on.csv" --variant po-pc -o "$T/rp2"
check "  says which variants it replays" err_has "replays tdpa-off, tdpa-on or all"
expect_exit 2 "replay a one-port log with tdpa-on" "$ANALYZE" replay "$T/one.csv" --variant tdpa-on -o "$T/rp2"
check "  says it is a one-port log" err_has "is a one-port log"
check "  input untouched" cmp -s <(rows "$T/on.csv") <(rows "$T/rp/on.tdpa-on.csv")

# ---- report: the teleop figure, listed in the index
expect_exit 0 "report of the teleop logs, --no-draw" "$ANALYZE" report "$T/on.csv" "$T/off.csv" -o "$T/rep0" --no-draw
check "  the script plots positions, forces, energies per port, drift" sh -c \
	"grep -q 'title \"xs (slave)\"' '$T/rep0/on-teleop.gp' && grep -q 'title \"Es_rx' '$T/rep0/on-teleop.gp' && grep -q 'title \"x - xs\"' '$T/rep0/on-teleop.gp'"
check "  its data: t and eleven columns' min and max" awk '/^#/ { next } { exit !(NF == 23) }' \
	"$T/rep0/on-teleop.dat"
check "  index.html lists both logs' figures" sh -c "grep -q 'on-teleop.gp' '$T/rep0/index.html' && grep -q 'off-teleop.gp' '$T/rep0/index.html'"
if command -v gnuplot >/dev/null 2>&1; then
	expect_exit 0 "report of the teleop log, drawn" "$ANALYZE" report "$T/on.csv" -o "$T/rep"
	check "  a PNG of the five panels (> 20 kB)" sh -c "head -c 8 '$T/rep/on-teleop.png' | od -An -tx1 |
		grep -q '89 50 4e 47 0d 0a 1a 0a' && [ \$(wc -c < '$T/rep/on-teleop.png') -gt 20000 ]"
	check "  and its PDF" test -s "$T/rep/on-teleop.pdf"
	check "  index.html shows it" grep -q '<img src="on-teleop.png"' "$T/rep/index.html"
else
	echo "# gnuplot not installed: the drawn figure is not checked"
fi
# what the verbs do not read yet: a position-position log (its slave PC is a
# force), and replay of a drift-compensated log; energy --check reads both
expect_exit 0 "a position-position log" "$POPC" run "$SRC/data/scenes/teleop-pp-wall.ini" \
	--set run.duration=0.5 --log "$T/pp.csv" -q
for verb in chatter teleop compare "replay --variant all -o $T/rpp"; do
	expect_exit 2 "  ${verb%% *} refuses it" "$ANALYZE" $verb "$T/pp.csv"
	check "  naming the architecture" grep -q 'position-position: chatter, teleop' "$T/err"
done
expect_exit 0 "  energy --check reads it" "$ANALYZE" energy --check "$T/pp.csv"
expect_exit 0 "a drift-compensated log with an excess" "$POPC" run "$WALL" --set run.duration=0.5 \
	--set teleop.drift=coelho2018 --set teleop.excess=0.001 --log "$T/dr.csv" -q
expect_exit 2 "  replay refuses it" "$ANALYZE" replay --variant all "$T/dr.csv" -o "$T/rpd"
check "  naming the law" grep -q 'teleop.drift = coelho2018: replay' "$T/err"
expect_exit 0 "  teleop reads it" "$ANALYZE" teleop "$T/dr.csv"
expect_exit 0 "a log with an excess" "$POPC" run "$WALL" --set run.duration=0.5 \
	--set teleop.excess=0.001 --log "$T/ex.csv" -q
expect_exit 0 "  replayed with the PCs on" "$ANALYZE" replay --variant tdpa-on "$T/ex.csv" -o "$T/rpx"
check "  its own setting: every row bit for bit (the excess counted)" cmp -s <(rows "$T/ex.csv") \
	<(rows "$T/rpx/ex.tdpa-on.csv")
check "  the variant line names what ran" grep -q '^# variant = tdpa$' "$T/rpx/ex.tdpa-on.csv"

check_summary
