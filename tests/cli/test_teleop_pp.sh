#!/usr/bin/env bash
# Position-position teleoperation through the programs (docs/TELEOPERATION.md,
# "Position-position"): the shipped scene runs with the teleop columns,
# popc-analyze energy --check recomputes the slave's coupling and both ports
# bit for bit and checks the two-port condition (exit 1 on a changed cell,
# and on a run without the PCs), the coupling keys are written only for this
# architecture, and bad coupling input is exit 2 naming the key before any
# work. Argument: the popc-analyze program.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
ANALYZE=${1:?popc-analyze}
T=$(mktemp -d /tmp/popc-teleop-pp-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

PP=$SRC/data/scenes/teleop-pp-wall.ini
COLUMNS="t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port,xs,xs_true,xs_cmd,fs_count,fs,vs_rx,vs_pc,vs_c,Ws,Em_in,Em_out,Em_rx,Es_in,Es_out,Es_rx,fwd_age,bwd_age"

expect_exit 0 "teleop-pp-wall (200 ms round trip, PCs on)" "$POPC" run "$PP" --log "$T/on.csv"
check "  the teleop columns" grep -qx "$COLUMNS" "$T/on.csv"
check "  the architecture and coupling in the header" sh -c "grep -qx '# architecture = position-position' '$T/on.csv' && grep -qx '# coupling_stiffness = 3000' '$T/on.csv' && grep -qx '# coupling_damping = 3' '$T/on.csv'"
check "  no NaN or inf in a cell" sh -c "! grep -v '^#' '$T/on.csv' | grep -qiE 'nan|inf'"
expect_exit 0 "  energy --check: the coupling and both ports bit for bit, the condition" \
	"$ANALYZE" energy --check "$T/on.csv"
check "  no row differing, the condition never broken" grep -q "online=teleop .*rows differing 0  two-port condition broken on 0 rows" "$T/out"

# a changed cell in its last digit: vs_c (the slave's force command, column
# 20), xs_cmd (the master position the slave's coupling held, column 15)
change() { # COLUMN ROW IN OUT
	awk -F, -v col="$1" -v row="$2" 'BEGIN{OFS=","} /^#/ || /^t,/ {print; next} {n++} n == row {d = substr($col, length($col)); $col = substr($col, 1, length($col) - 1) (d == "1" ? "2" : "1")} {print}' "$3" >"$4"
}
change 20 3000 "$T/on.csv" "$T/vs_c.csv"
check "  (the copy differs)" sh -c "! cmp -s '$T/on.csv' '$T/vs_c.csv'"
expect_exit 1 "energy --check on a changed vs_c" "$ANALYZE" energy --check "$T/vs_c.csv"
check "  one row differing" grep -q "rows differing 1 " "$T/out"
change 15 2500 "$T/on.csv" "$T/xs_cmd.csv"
check "  (the copy differs)" sh -c "! cmp -s '$T/on.csv' '$T/xs_cmd.csv'"
expect_exit 1 "energy --check on a changed xs_cmd" "$ANALYZE" energy --check "$T/xs_cmd.csv"

# without the PCs the 200 ms round trip breaks the condition and diverges
expect_exit 6 "teleop.tdpa = off" "$POPC" run "$PP" --set teleop.tdpa=off --log "$T/off.csv"
check "  the stop line" grep -q "^# stop = closed loop diverged" "$T/off.csv"
expect_exit 1 "  energy --check: the condition broken" "$ANALYZE" energy --check "$T/off.csv"
check "  rows recomputed bit for bit all the same" grep -q "rows differing 0  two-port condition broken on [1-9]" "$T/out"

# bad input: exit 2 before any work, naming the key and what is allowed
bad_case() { # DESC TEXT ASSIGNMENT...
	local what=$1 text=$2; shift 2
	local sets=()
	for a in "$@"; do sets+=(--set "$a"); done
	rm -f "$T/bad.csv"
	expect_exit 2 "$what" "$POPC" run "$PP" "${sets[@]}" --log "$T/bad.csv"
	check "  says: $text" err_has "$text"
	check "  no log written" test ! -e "$T/bad.csv"
}
bad_case "a negative coupling stiffness" "teleop.coupling_stiffness" teleop.coupling_stiffness=-1
bad_case "a slave PC force bound of 0" "teleop.slave_pc_force_bound" teleop.slave_pc_force_bound=0
bad_case "no coupling at all" "needs teleop.coupling_stiffness > 0 N/m or teleop.coupling_damping > 0" \
	teleop.coupling_stiffness=0 teleop.coupling_damping=0
bad_case "a drift law (it corrects a velocity command)" \
	"teleop.drift = coelho2018 needs teleop.architecture = position-force" teleop.drift=coelho2018
bad_case "a Modbus slave (a drive takes a position or a velocity)" \
	"teleop.architecture = position-position needs axis.kind = sim" axis.kind=modbus \
	axis.map=servo-position.ini axis.connect=tcp:127.0.0.1:1502

# the coupling keys only for position-position
expect_exit 0 "popc scene show of teleop-wall (position-force)" "$POPC" scene show "$SRC/data/scenes/teleop-wall.ini"
check "  no coupling key" sh -c "! grep -qE '^(coupling_|slave_pc_force_bound)' '$T/out'"
expect_exit 0 "popc scene show of teleop-pp-wall" "$POPC" scene show "$PP"
check "  its coupling keys" sh -c "grep -qx 'coupling_stiffness = 3000' '$T/out' && grep -qx 'slave_pc_force_bound = 100' '$T/out'"
check "  popc scene keys lists teleop.coupling_stiffness" sh -c "'$POPC' scene keys | grep -q 'teleop.coupling_stiffness'"
check_summary
