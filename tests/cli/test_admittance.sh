#!/usr/bin/env bash
# Admittance causality through the programs (docs/ADMITTANCE.md): the shipped
# scenes run, their logs have the admittance columns (an impedance log does
# not), popc-analyze energy --check finds the logged W bit for bit and a
# changed cell, bad admittance input is exit 2 naming the key before any
# work, and popc bench loop times the two causalities side by side.
# Argument: the popc-analyze program.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
ANALYZE=${1:?popc-analyze}
T=$(mktemp -d /tmp/popc-admittance-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

ADM=$SRC/data/scenes/admittance.ini
WALL=$SRC/data/scenes/admittance-wall.ini
ADM_COLUMNS="t,x,count,v,f_e,f_pc,f_c,W,E_ref,flags,f_count,f_meas,x_cmd,v_ve,v_pc"

for v in none parallel-pc parallel-ignore parallel-hold parallel-improved; do
	expect_exit 0 "admittance-wall, $v" "$POPC" run "$WALL" --set admittance.variant=$v \
		--set admittance.force_noise=0.02 --log "$T/$v.csv"
	check "  the admittance columns" grep -qx "$ADM_COLUMNS" "$T/$v.csv"
	check "  the header names the admittance variant" grep -qx "# variant = $v" "$T/$v.csv"
	check "  the summary's parallel PC line" err_has "parallel PC active"
	check "  no NaN or inf in a cell" sh -c "! grep -v '^#' '$T/$v.csv' | grep -qiE 'nan|inf'"
	expect_exit 0 "  energy --check: the logged W bit for bit" "$ANALYZE" energy --check "$T/$v.csv"
	check "  online=$v, no row differing" grep -q "online=$v .*rows differing 0" "$T/out"
done
check "the noise seed is in the log header" grep -qx "# force_noise_seed = 1" "$T/parallel-pc.csv"
expect_exit 0 "another seed" "$POPC" run "$WALL" --set admittance.force_noise=0.02 \
	--set admittance.force_noise_seed=2 --log "$T/seed2.csv"
check "  other force readings" bash -c "! cmp -s <(grep -v '^#' '$T/parallel-pc.csv') <(grep -v '^#' '$T/seed2.csv')"
expect_exit 0 "the same seed again" "$POPC" run "$WALL" --set admittance.force_noise=0.02 --log "$T/again.csv"
check "  the same log (its provenance lines aside)" cmp -s <(sans_provenance "$T/parallel-pc.csv") \
	<(sans_provenance "$T/again.csv")

# a W cell changed in its last digit: --check finds it (exit 1)
awk -F, 'BEGIN{OFS=","} /^#/ || /^t,/ {print; next} {n++} n == 3000 && $8 != "0.0" {$8 = $8 "1"} {print}' \
	"$T/parallel-pc.csv" >"$T/changed.csv"
check "  (the copy differs)" sh -c "! cmp -s '$T/parallel-pc.csv' '$T/changed.csv'"
expect_exit 1 "energy --check on a changed W" "$ANALYZE" energy --check "$T/changed.csv"
check "  one row differing" grep -q "rows differing 1" "$T/out"

expect_exit 0 "admittance.ini (free motion into the wall)" "$POPC" run "$ADM" --log "$T/adm.csv"
check "  the VE met the wall: f_e > 0 somewhere" sh -c "grep -v '^#' '$T/adm.csv' | awk -F, 'NR > 1 && \$5 > 0 {f = 1} END {exit !f}'"
expect_exit 0 "the same scene in impedance causality" "$POPC" run "$ADM" --set device.causality=impedance \
	--log "$T/imp.csv"
check "  an impedance log's columns" grep -qx "t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port" "$T/imp.csv"
check "  no [admittance] section, no causality key" sh -c "! grep -v '^# command = ' '$T/imp.csv' | grep -qE '^# \[admittance\]|causality'"

# bad input: exit 2 before any work, naming the key and what is allowed
bad_case() { # DESC TEXT ASSIGNMENT...
	local what=$1 text=$2; shift 2
	local sets=()
	for a in "$@"; do sets+=(--set "$a"); done
	rm -f "$T/bad.csv"
	expect_exit 2 "$what" "$POPC" run "$ADM" "${sets[@]}" --log "$T/bad.csv"
	check "  says: $text" err_has "$text"
	check "  no log written" test ! -e "$T/bad.csv"
}
bad_case "force resolution 0" "admittance.force_resolution = 0: out of range; allowed (0, 1000] N" \
	admittance.force_resolution=0
bad_case "virtual mass 0 without damping" "admittance.virtual_mass = 0 kg needs admittance.virtual_damping > 0" \
	admittance.virtual_mass=0 admittance.virtual_damping=0
bad_case "a negative virtual mass" "admittance.virtual_mass = -1: out of range; allowed [0, 1000] kg" \
	admittance.virtual_mass=-1
bad_case "a PC bound of 0" "admittance.pc_velocity_bound = 0: out of range; allowed (0, 1000] m/s" \
	admittance.pc_velocity_bound=0
bad_case "an unknown variant" "admittance.variant = 'improved': unknown value; allowed one of none|parallel-pc|" \
	admittance.variant=improved
bad_case "a position servo without K_p" "admittance.servo = position needs admittance.servo_stiffness > 0" \
	admittance.servo_stiffness=0
bad_case "a loop delay" "device.causality = admittance needs run.delay_ticks = 0" run.delay_ticks=1
bad_case "friction" "device.causality = admittance needs device.coulomb = 0" device.coulomb=0.2
printf '[device]\ncausality = admittance\n[admittance]\nforce_resolution = 0\n' >"$T/bad.ini"
expect_exit 2 "the same from a scene file" "$POPC" run "$T/bad.ini" -q
check "  names file, line and key" err_has "$T/bad.ini:4: admittance.force_resolution = 0: out of range"

expect_exit 0 "popc bench loop on an admittance scene" "$POPC" bench loop --scene "$WALL" \
	--min-time 0.01 --repeat 1 --format csv
check "  admittance against impedance, a ratio" grep -qE '^loop_ns_per_tick,[0-9.e+-]+,[0-9.e+-]+,[0-9.e+-]+$' "$T/out"
check_summary
