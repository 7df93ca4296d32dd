#!/usr/bin/env bash
# popc map on an admittance scene (docs/MAPS.md, "The admittance display"):
# --variant names admittance.variant, and the diverged edge over the VE's
# virtual spring K is the dual of Colgate and Schenkel's condition, the
# stability of the sampled VE behind its zero-order hold (boundary.csv's
# k_colgate_schenkel_N_per_m on an admittance line):
#   m_v = 0:  K < 2 (b_v - B) / T            (the virtual damper b_v in the
#                                              place of the device's b)
#   m_v > 0:  K < (4 m_v - 2 (b_v + B) T) / T^2
# - where it is exact (a massless hand pushing with a force intent, so the
#   sensor reads the intent's force alone), every 2 % bracket holds the line
#   to within 2 % beyond its top: the diverged edge is an upper bound, since
#   near the edge |lambda| - 1 grows as K - K* and a 1 s run reaches the
#   divergence bound only a little above it (measured: at most 1 %);
# - a line whose formula is <= 0 (m_v <= (b_v + B) T / 2) is below-range;
# - with the paper's hand spring and damper (the ramp) the edge lies below the
#   line (the hand closes a second loop through the servo), and with the hand's
#   mass (0.1 kg) a bare damper VE diverges at every K in range.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/zwidth-admittance.ini
T=$(mktemp -d /tmp/popc-map-adm-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
# a cell of boundary.csv by column name, for the row whose first cells are $2.. (comma-joined)
cell() { awk -F, -v key="$2" -v name="$3" -v nk="$4" \
  'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
   { k = $1; for (i = 2; i <= nk; i++) k = k "," $i; if (k == key) print $(col[name]) }' "$1"; }
# holds LO HI K: LO / (1 + 0.02) <= K <= HI, LO > 0 (the edge may lie above K, not below)
holds() { awk -v lo="$1" -v hi="$2" -v k="$3" \
	'BEGIN { exit !(lo + 0 > 0 && lo / 1.02 <= k && k <= hi) }'; }
PURE="--set operator.intent=force --set operator.stiffness=0 --set operator.damping=0"

# ---- a bare virtual damper: K* = 2 (b_v - B) / T
# shellcheck disable=SC2086
expect_exit 0 "map of none over b_v and B (m_v = 0)" "$POPC" map "$SCENE" --variant none \
	--vary admittance.virtual_damping=0.5,1,2 --vary environment.damping=0,0.2 $PURE \
	--stiffness 1e2:1e5 --criterion diverged -o "$T/a" -j 2 -q
check "  the header names the admittance variant axis" \
	grep -q '^admittance.variant,admittance.virtual_damping,environment.damping,criterion,' "$T/a/boundary.csv"
for b in 0.5 1 2; do for B in 0 0.2; do
	key="none,$b,$B,diverged"
	ok=$(cell "$T/a/boundary.csv" "$key" k_ok_N_per_m 4)
	bad=$(cell "$T/a/boundary.csv" "$key" k_bad_N_per_m 4)
	line=$(cell "$T/a/boundary.csv" "$key" k_colgate_schenkel_N_per_m 4)
	want=$(awk -v b=$b -v B=$B 'BEGIN { printf "%.6g", 2 * (b - B) / 1e-3 }')
	check "  b_v=$b B=$B: the line is 2 (b_v - B) / T = $want" awk -v l="$line" -v w="$want" \
		'BEGIN { exit !(l - w < 1e-9 * w && w - l < 1e-9 * w) }'
	check "  b_v=$b B=$B: [$ok, $bad] holds it" holds "$ok" "$bad" "$want"
done; done

# ---- a virtual mass-damper: K* = (4 m_v - 2 b_v T) / T^2, over T
# shellcheck disable=SC2086
expect_exit 0 "map of none over m_v and T (b_v = 1)" "$POPC" map "$SCENE" --variant none \
	--vary admittance.virtual_mass=0.001,0.002,0.005 --vary run.rate=500,1000 $PURE \
	--stiffness 1e2:1e6 --criterion diverged -o "$T/m" -j 2 -q
for m in 0.001 0.002 0.005; do for r in 500 1000; do
	key="none,$m,$r,diverged"
	want=$(awk -v m=$m -v r=$r 'BEGIN { T = 1 / r; printf "%.6g", (4 * m - 2 * T) / (T * T) }')
	out=$(cell "$T/m/boundary.csv" "$key" outcome 4)
	if awk -v w="$want" 'BEGIN { exit !(w <= 0) }'; then
		check "  m_v=$m T=1/$r: K* = $want <= 0, below-range" test "$out" = below-range
		continue
	fi
	ok=$(cell "$T/m/boundary.csv" "$key" k_ok_N_per_m 4)
	bad=$(cell "$T/m/boundary.csv" "$key" k_bad_N_per_m 4)
	check "  m_v=$m T=1/$r: [$ok, $bad] holds K* = $want" holds "$ok" "$bad" "$want"
done; done

# ---- with the hand: below the line; with its mass, nowhere stable
# (no --criterion: on an admittance scene the default is diverged)
expect_exit 0 "map with the paper's hand spring and damper" "$POPC" map "$SCENE" --variant none \
	--vary admittance.virtual_damping=1 --stiffness 1e2:1e5 -o "$T/h" -j 2 -q
ok=$(cell "$T/h/boundary.csv" "none,1,diverged" k_ok_N_per_m 3)
check "  the hand's loop lowers the edge: $ok < 2 b_v / T = 2000" \
	awk -v ok="$ok" 'BEGIN { exit !(ok > 1500 && ok < 1980) }'
expect_exit 0 "map with the hand's mass" "$POPC" map "$SCENE" --variant none \
	--vary admittance.virtual_damping=1 --set operator.mass=0.1 --stiffness 1e2:1e5 \
	--criterion diverged -o "$T/hm" -j 2 -q
check "  a bare damper under the hand's mass: below-range" \
	test "$(cell "$T/hm/boundary.csv" "none,1,diverged" outcome 3)" = below-range

# ---- refusals: an impedance variant on an admittance scene, --set admittance.variant
expect_exit 2 "an impedance variant on an admittance scene" "$POPC" map "$SCENE" --variant ref-energy \
	-o "$T/bad1" -q
expect_exit 2 "--set admittance.variant" "$POPC" map "$SCENE" --variant none \
	--set admittance.variant=parallel-pc -o "$T/bad2" -q
expect_exit 2 "--criterion passive on an admittance scene" "$POPC" map "$SCENE" --variant none \
	--criterion diverged,passive -o "$T/bad3" -q
check "  names the criterion and why" err_has "--criterion passive: $SCENE is an admittance scene"
check "  before any run" test ! -e "$T/bad3/rows"
check_summary
