#!/usr/bin/env bash
# popc map's device-passive edge against Colgate and Schenkel's passivity
# condition (docs/MAPS.md, "The device port"), on data/scenes/zwidth-spring.ini:
# - where the condition is exact (no virtual damping, a slow motion), the
#   edge's 2 % bracket holds K_CS = 2 b / T on every line of b x T;
# - the VE port alone (criterion passive) is never passive there: it leaks
#   K T / 2 per unit of integral v^2 and has no damping to pay for it;
# - elsewhere the edge is the energy balance of the excitation, not the
#   condition's worst case: for a sine of frequency w,
#     K*(w) = (2 / T) (b (w T)^2 / (2 (1 - cos w T)) + B cos w T),
#   which the brackets hold at 2, 125 and 250 Hz, with and without virtual
#   damping B (at 250 Hz, w T = pi/2: the same edge for every B), to within
#   1 % beyond the bracket: K*(w) is the edge of the sine's steady motion,
#   and the start's transient rings at the contact's natural frequency
#   (sqrt((K + K_HO) / M), 10-12 Hz), whose own K* differs where B > 0
#   (measured: 250 Hz, B = 0.4: [1235.1, 1259.8] against K* = 1233.7;
#   2 Hz, B = 0.4: [1763.7, 1798.9] against 1799.9).
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/zwidth-spring.ini
T=$(mktemp -d /tmp/popc-map-cs-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
# a cell of boundary.csv by column name, for the row whose first cells are $2.. (comma-joined)
cell() { awk -F, -v key="$2" -v name="$3" -v nk="$4" \
  'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
   { k = $1; for (i = 2; i <= nk; i++) k = k "," $i; if (k == key) print $(col[name]) }' "$1"; }
# holds LO HI K [SLACK]: LO / (1 + SLACK) <= K <= HI (1 + SLACK)
holds() { awk -v lo="$1" -v hi="$2" -v k="$3" -v s="${4:-0}" \
	'BEGIN { exit !(lo + 0 > 0 && lo / (1 + s) <= k && k <= hi * (1 + s)) }'; }

# ---- where the condition is exact: b x T, B = 0
expect_exit 0 "map of none over b and T, device-passive and passive" "$POPC" map "$SCENE" \
	--variant none --vary operator.damping=0.2,0.5,1 --vary run.rate=500,1000,2000 \
	--stiffness 1e2:1e5 --criterion device-passive,passive -o "$T/a" -j 2 -q
for b in 0.2 0.5 1; do for r in 500 1000 2000; do
	key="none,$b,$r,device-passive"
	ok=$(cell "$T/a/boundary.csv" "$key" k_ok_N_per_m 4)
	bad=$(cell "$T/a/boundary.csv" "$key" k_bad_N_per_m 4)
	cs=$(cell "$T/a/boundary.csv" "$key" k_colgate_schenkel_N_per_m 4)
	check "  b=$b T=1/$r: a bracket of 2 %" awk -v w="$(cell "$T/a/boundary.csv" "$key" width 4)" \
		'BEGIN { exit !(w > 0 && w <= 0.02) }'
	check "  b=$b T=1/$r: [$ok, $bad] holds K_CS = 2b/T = $cs" holds "$ok" "$bad" "$cs"
	check "  b=$b T=1/$r: the VE port alone is passive nowhere in range" \
		test "$(cell "$T/a/boundary.csv" "none,$b,$r,passive" outcome 4)" = below-range
done; done

# ---- elsewhere: the sine's own energy balance K*(w)
kstar() { awk -v f="$1" -v B="$2" 'BEGIN { b = 0.5; T = 1e-3; th = 2 * 3.141592653589793 * f * T;
	printf "%.6f", (2 / T) * (b * th * th / (2 * (1 - cos(th))) + B * cos(th)) }'; }
for f in 2 125 250; do
	expect_exit 0 "map at $f Hz over B" "$POPC" map "$SCENE" --variant none \
		--vary environment.damping=0,0.1,0.4 --set operator.frequency=$f \
		--set encoder.resolution=1e-9 --stiffness 1e2:1e5 --criterion device-passive \
		-o "$T/f$f" -j 2 -q
	for B in 0 0.1 0.4; do
		key="none,$B,device-passive"
		ok=$(cell "$T/f$f/boundary.csv" "$key" k_ok_N_per_m 3)
		bad=$(cell "$T/f$f/boundary.csv" "$key" k_bad_N_per_m 3)
		ks=$(kstar $f $B)
		check "  $f Hz B=$B: [$ok, $bad] holds K*(w) = $ks (1 % beyond)" \
			holds "$ok" "$bad" "$ks" 0.01
	done
done
# the low-frequency edge lies above the condition's line by 4 B / T: the
# slow sine never excites the virtual damper at the Nyquist rate, where its
# backward difference costs B instead of paying it
cs=$(cell "$T/f2/boundary.csv" "none,0.4,device-passive" k_colgate_schenkel_N_per_m 3)
ok=$(cell "$T/f2/boundary.csv" "none,0.4,device-passive" k_ok_N_per_m 3)
check "  2 Hz B=0.4: edge $ok above K_CS = $cs" awk -v ok="$ok" -v cs="$cs" 'BEGIN { exit !(ok > 8 * cs) }'

check_summary
