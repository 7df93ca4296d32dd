#!/usr/bin/env bash
# Teleoperation through the programs (docs/TELEOPERATION.md): the shipped
# scene runs with its two-port columns and its channel seeds in the header,
# the same seed gives the same log, popc-analyze energy --check recomputes
# both ports bit for bit and checks the two-port condition (exit 1 on a
# changed cell, and on a run without the PCs whose condition breaks), bad
# teleop input is exit 2 naming the key before any work, and a one-port
# scene writes no teleop key. Argument: the popc-analyze program.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
ANALYZE=${1:?popc-analyze}
T=$(mktemp -d /tmp/popc-teleop-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

WALL=$SRC/data/scenes/teleop-wall.ini
COLUMNS="t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port,xs,xs_true,xs_cmd,fs_count,fs,vs_rx,vs_pc,vs_c,Ws,Em_in,Em_out,Em_rx,Es_in,Es_out,Es_rx,fwd_age,bwd_age"

expect_exit 0 "teleop-wall (200 ms round trip, PCs on)" "$POPC" run "$WALL" --log "$T/on.csv"
check "  the two-port columns" grep -qx "$COLUMNS" "$T/on.csv"
check "  both channels' seeds in the header" sh -c "grep -A6 -x '# \[forward\]' '$T/on.csv' | grep -qx '# seed = 1' && grep -A6 -x '# \[backward\]' '$T/on.csv' | grep -qx '# seed = 2'"
check "  no NaN or inf in a cell" sh -c "! grep -v '^#' '$T/on.csv' | grep -qiE 'nan|inf'"
expect_exit 0 "  energy --check: both ports bit for bit, the condition at every row" \
	"$ANALYZE" energy --check "$T/on.csv"
check "  no row differing, the condition never broken" grep -q "online=teleop .*rows differing 0  two-port condition broken on 0 rows" "$T/out"

# a lossy, jittered channel: the same seed, the same log
set_lossy=(--set forward.jitter_ticks=20 --set forward.loss=0.3 --set backward.loss=0.2 --set forward.in_order=off)
expect_exit 0 "a lossy jittered channel" "$POPC" run "$WALL" "${set_lossy[@]}" --log "$T/lossy.csv"
expect_exit 0 "  again" "$POPC" run "$WALL" "${set_lossy[@]}" --log "$T/lossy2.csv"
check "  the same log (its provenance lines aside)" cmp -s <(sans_provenance "$T/lossy.csv") \
	<(sans_provenance "$T/lossy2.csv")
check "  packets were lost (flags 16, 32)" sh -c "grep -v '^#' '$T/lossy.csv' | awk -F, 'NR > 1 && int(\$11 / 16) % 2 {f = 1} END {exit !f}'"
expect_exit 0 "  energy --check" "$ANALYZE" energy --check "$T/lossy.csv"
expect_exit 0 "another forward seed" "$POPC" run "$WALL" "${set_lossy[@]}" --set forward.seed=7 --log "$T/seed7.csv"
check "  another log" bash -c "! cmp -s <(grep -v '^#' '$T/lossy.csv') <(grep -v '^#' '$T/seed7.csv')"

# an Em_out cell changed in its last digit: --check finds it (exit 1)
awk -F, 'BEGIN{OFS=","} /^#/ || /^t,/ {print; next} {n++} n == 3000 {d = substr($23, length($23)); $23 = substr($23, 1, length($23) - 1) (d == "1" ? "2" : "1")} {print}' \
	"$T/on.csv" >"$T/changed.csv"
check "  (the copy differs)" sh -c "! cmp -s '$T/on.csv' '$T/changed.csv'"
expect_exit 1 "energy --check on a changed Em_out" "$ANALYZE" energy --check "$T/changed.csv"
check "  one row differing" grep -q "rows differing 1 " "$T/out"

# without the PCs the 200 ms round trip breaks the condition (and diverges)
expect_exit 6 "teleop.tdpa = off" "$POPC" run "$WALL" --set teleop.tdpa=off --log "$T/off.csv"
check "  the stop line" grep -q "^# stop = closed loop diverged" "$T/off.csv"
expect_exit 1 "  energy --check: the condition broken" "$ANALYZE" energy --check "$T/off.csv"
check "  rows recomputed bit for bit all the same" grep -q "rows differing 0  two-port condition broken on [1-9]" "$T/out"

# bad input: exit 2 before any work, naming the key and what is allowed
bad_case() { # DESC TEXT ASSIGNMENT...
	local what=$1 text=$2; shift 2
	local sets=()
	for a in "$@"; do sets+=(--set "$a"); done
	rm -f "$T/bad.csv"
	expect_exit 2 "$what" "$POPC" run "$WALL" "${sets[@]}" --log "$T/bad.csv"
	check "  says: $text" err_has "$text"
	check "  no log written" test ! -e "$T/bad.csv"
}
bad_case "a delay beyond the channel" "forward.delay_ticks" forward.delay_ticks=100001
bad_case "a loss of 1" "backward.loss" backward.loss=1
bad_case "an unknown architecture" "allowed one of off|position-force|position-position" teleop.architecture=force-force
bad_case "delay plus jitter beyond the channel" "forward.delay_ticks + forward.jitter_ticks" \
	forward.delay_ticks=90000 forward.jitter_ticks=20000
bad_case "run.delay_ticks in a teleop scene" "run.delay_ticks = 0" run.delay_ticks=2
bad_case "an admittance master" "device.causality = impedance" device.causality=admittance

# the variant line names what ran (the PCs, the drift law), not controller.variant
check "the variant line of a run with the PCs on" grep -qx '# variant = tdpa' "$T/on.csv"
check "  and with them off" grep -qx '# variant = none' "$T/off.csv"
sed 's/^# variant = tdpa$/# variant = none/' "$T/on.csv" >"$T/lie.csv"
expect_exit 2 "energy on a log whose variant line contradicts teleop.tdpa" "$ANALYZE" energy "$T/lie.csv"
check "  names the line and the keys" err_has "variant = none, but teleop.tdpa = on and teleop.drift = off run 'tdpa'"

# drift compensation (teleop.drift): its columns and keys, energy --check
# recomputing v_dc bit for bit, the condition at every row, on a lossy channel too
for law in artigas2010 coelho2018; do
	expect_exit 0 "teleop.drift = $law" "$POPC" run "$WALL" --set teleop.drift=$law --log "$T/$law.csv"
	check "  the columns, xm_rx and vs_dc last" grep -qx "$COLUMNS,xm_rx,vs_dc" "$T/$law.csv"
	check "  the variant line" grep -qx "# variant = tdpa-$law" "$T/$law.csv"
	check "  its keys in the header" sh -c "grep -qx '# drift = $law' '$T/$law.csv' && grep -qx '# drift_max_velocity = 0.5' '$T/$law.csv'"
	check "  no NaN or inf in a cell" sh -c "! grep -v '^#' '$T/$law.csv' | grep -qiE 'nan|inf'"
	expect_exit 0 "  energy --check" "$ANALYZE" energy --check "$T/$law.csv"
	check "  no row differing, the condition never broken" grep -q "rows differing 0  two-port condition broken on 0 rows" "$T/out"
	expect_exit 0 "  on the lossy channel" "$POPC" run "$WALL" "${set_lossy[@]}" --set teleop.drift=$law --log "$T/$law-lossy.csv"
	expect_exit 0 "  energy --check" "$ANALYZE" energy --check "$T/$law-lossy.csv"
	check "  no row differing, the condition never broken" grep -q "rows differing 0  two-port condition broken on 0 rows" "$T/out"
done
check "the drift law acted (a vs_dc cell not 0)" sh -c "grep -v '^#' '$T/coelho2018.csv' | awk -F, 'NR > 1 && \$31 != 0 {f = 1} END {exit !f}'"
# a vs_dc cell changed: --check finds it
awk -F, 'BEGIN{OFS=","} /^#/ || /^t,/ {print; next} {n++} $31 != 0 && !done {$31 = $31 * 2; done = 1} {print}' \
	"$T/coelho2018.csv" >"$T/dc.csv"
check "  (the copy differs)" sh -c "! cmp -s '$T/coelho2018.csv' '$T/dc.csv'"
expect_exit 1 "energy --check on a changed vs_dc" "$ANALYZE" energy --check "$T/dc.csv"
check "  one row differing" grep -q "rows differing 1 " "$T/out"

# the passivity excess: written when used, and --check counts it
expect_exit 0 "teleop.excess = 0.001" "$POPC" run "$WALL" --set teleop.excess=0.001 --log "$T/excess.csv"
check "  in the header" grep -qx '# excess = 0.001' "$T/excess.csv"
expect_exit 0 "  energy --check" "$ANALYZE" energy --check "$T/excess.csv"
check "  no row differing, the condition never broken" grep -q "rows differing 0  two-port condition broken on 0 rows" "$T/out"
check "a run without drift or excess writes neither key" sh -c "! grep -qE '^# (drift|excess)' '$T/on.csv'"

bad_case "an unknown drift law" "allowed one of off|artigas2010|coelho2018" teleop.drift=ryu2004
bad_case "a drift bound of 0" "teleop.drift_max_velocity" teleop.drift_max_velocity=0
bad_case "a negative excess" "teleop.excess" teleop.excess=-1
rm -f "$T/bad.csv"
expect_exit 2 "a drift law in a one-port scene" "$POPC" run "$SRC/data/scenes/paper.ini" --set teleop.drift=coelho2018 --log "$T/bad.csv"
check "  says what it needs" err_has "teleop.drift = coelho2018 needs teleop.architecture = position-force"
check "  no log written" test ! -e "$T/bad.csv"

# a one-port scene: no teleop key in its resolved scene
expect_exit 0 "popc scene show of the paper scene" "$POPC" scene show "$SRC/data/scenes/paper.ini"
check "  no [teleop], [slave], [forward], [backward]" sh -c "! grep -qE '^\[(teleop|slave|forward|backward)\]' '$T/out'"
check "  popc scene keys lists forward.delay_ticks" sh -c "'$POPC' scene keys | grep -q 'forward.delay_ticks'"
check_summary
