#!/usr/bin/env bash
# popc map's first failure against a dense grid (issue 23, docs/MAPS.md):
# the paper's plant, none, ref-energy and improved, K from 1e2 to 1e6 N/m on
# the map's own 467-point log grid, criterion passive. popc sweep makes
# every point; popc map makes its scan (every 16th point) and bisections.
# - The PC variants' lines fold: above their first failure they are passive
#   again over a band (ref-energy: first failure 415 N/m, passive points up
#   to 2098 N/m). The map's k_bad is the grid's first failure, within the
#   scan's step (16 grid steps, a factor 1.37), and the map says the band.
# - Its band top is a true transition of the grid (acceptable, then not).
# - The map makes at most 10 % of the grid's runs (counted: rows).
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/paper.ini
T=$(mktemp -d /tmp/popc-map-grid-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
VARIANTS=none,ref-energy,improved
SCAN=16
# data rows of every rows file of a directory
rows() { cat "$1"/rows/*.csv | grep -v '^run,' | grep -v '^#' | wc -l; }
# boundary.csv's cell NAME for variant V
cell() { awk -F, -v v="$2" -v name="$3" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
  $1 == v { print $(col[name]) }' "$1"; }
# the grid's verdicts of variant V as a string, one letter per K in order
# (o passive: exit 0 and E_port never below -1e-6 J; X not: below, or
# diverged, exit 6; ? no verdict), and K of each index
verdicts() { awk -F, -v v="$2" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
  $(col["controller.variant"]) == v { e = $(col["exit_status"]); p = $(col["port_energy_min"]);
    s = s (e == 0 && p != "" && p + 0 >= -1e-6 ? "o" : e == 0 || e == 6 ? "X" : "?") }
  END { print s }' "$1"; }
k_at() { awk -F, -v v="$2" -v i="$3" 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next }
  $(col["controller.variant"]) == v && n++ == i { print $(col["environment.stiffness"]) }' "$1"; }
# index (0-based) of the point of variant V whose K text is K
index_of() { awk -F, -v v="$2" -v k="$3" 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next }
  $(col["controller.variant"]) == v { if ($(col["environment.stiffness"]) == k) print n; n++ }' "$1"; }

# (the sweep exits 1: the stiff walls of none diverge, exit 6, a verdict here)
expect_exit 1 "the dense grid: popc sweep over 3 variants x 467 K" "$POPC" sweep "$SCENE" \
  --vary controller.variant=$VARIANTS --vary environment.stiffness=1e2:1e6:467:log -o "$T/g" -j 2 -q
expect_exit 0 "the map of the same lines" "$POPC" map "$SCENE" --variant $VARIANTS -o "$T/m" -j 2 -q
grid_runs=$(rows "$T/g"); map_runs=$(rows "$T/m")
check "  the grid made 1401 runs" test "$grid_runs" -eq 1401
check "  the map made $map_runs: at most 10 % of the grid's" test $((map_runs * 10)) -le "$grid_runs"
for v in none ref-energy improved; do
  s=$(verdicts "$T/g/summary.csv" $v)
  first=$(awk -v s="$s" 'BEGIN { print index(s, "X") - 1 }')
  bad=$(cell "$T/m/boundary.csv" $v k_bad_N_per_m)
  mi=$(index_of "$T/g/summary.csv" $v "$bad")
  check "  $v: every grid point has a verdict" bash -c "[[ '$s' != *'?'* ]]"
  check "  $v: the map's first failure $bad N/m (index $mi) is the grid's, $(k_at "$T/g/summary.csv" $v "$first") N/m (index $first), within the scan's $SCAN steps" \
    test -n "$mi" -a "$mi" -ge "$first" -a "$mi" -le $((first + SCAN))
  check "  $v: the map's K_bad is unacceptable on the grid, its K_ok acceptable" \
    test "${s:$mi:1}" = X -a "${s:$((mi - 1)):1}" = o
  passive_above=$(awk -v s="$s" -v f="$first" 'BEGIN { print substr(s, f + 1) ~ /o/ }')
  outcome=$(cell "$T/m/boundary.csv" $v outcome)
  if [ "$v" = none ]; then
    check "  none: monotonic on the grid, a bracket in the map" test "$passive_above" = 0 -a "$outcome" = bracket
  else
    check "  $v: the grid folds (passive above its first failure)" test "$passive_above" = 1
    check "  $v: the map says so: not-monotonic" test "$outcome" = not-monotonic
    top=$(index_of "$T/g/summary.csv" $v "$(cell "$T/m/boundary.csv" $v k_last_ok_N_per_m)")
    check "  $v: its band top (index $top) is acceptable on the grid and the next point is not" \
      test -n "$top" -a "${s:$top:1}" = o -a "${s:$((top + 1)):1}" = X
  fi
done
check_summary
