#!/usr/bin/env bash
# popc map on a teleoperation scene (issue 26; docs/MAPS.md, "Teleoperation:
# stiffness against delay"): the largest stable wall stiffness against the
# round-trip delay, PCs off and on (--variant names teleop.tdpa). "stable":
# the run completed (so bounded: no divergence stop) and settled (its slave
# within 1 mm peak to peak over the last second: tele_oscillating = 0).
# Against a dense popc sweep of the same lines on the map's own 583-point grid
# (10 to 1e6 N/m), forward delays 0, 25 and 100 ticks (backward 0: round trips
# 0, 25 and 100 ms at 1 kHz):
# - the map's first failure is the grid's, within the scan's 16 steps, and
#   is a true transition of the grid (K_ok stable, K_bad not);
# - a not-monotonic line's band top is a true transition of the grid;
# - with a delay the PCs off fail far below the PCs on's band top;
# - criteria that do not judge a teleoperation run are refused, exit 2.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/teleop-wall.ini
T=$(mktemp -d /tmp/popc-map-teleop-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
SCAN=16
DELAYS=0,25,100
# boundary.csv's cell NAME for variant V, delay D
cell() { awk -F, -v v="$2" -v d="$3" -v name="$4" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
  $1 == v && $2 == d { print $(col[name]) }' "$1"; }
# the grid's verdicts of line (V, D), one letter per K in order (o stable:
# exit 0 and tele_oscillating 0; X not: oscillating, or diverged, exit 6; ?
# no verdict)
verdicts() { awk -F, -v v="$2" -v d="$3" 'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
  $(col["teleop.tdpa"]) == v && $(col["forward.delay_ticks"]) == d { e = $(col["exit_status"]);
    o = $(col["tele_oscillating"]); s = s (e == 0 && o == "0" ? "o" : (e == 0 && o == "1") || e == 6 ? "X" : "?") }
  END { print s }' "$1"; }
# index (0-based) on line (V, D) of the point whose K text is K
index_of() { awk -F, -v v="$2" -v d="$3" -v k="$4" 'NR == 1 { for (c = 1; c <= NF; c++) col[$c] = c; next }
  $(col["teleop.tdpa"]) == v && $(col["forward.delay_ticks"]) == d {
    if ($(col["environment.stiffness"]) == k) print n; n++ }' "$1"; }

# (the sweep exits 1: the diverged runs, exit 6, are verdicts here)
expect_exit 1 "the dense grid: popc sweep over PCs x 3 delays x 583 K" "$POPC" sweep "$SCENE" \
  --vary teleop.tdpa=off,on --vary forward.delay_ticks=$DELAYS \
  --vary environment.stiffness=1e1:1e6:583:log --set backward.delay_ticks=0 --no-log -o "$T/g" -j 2 -q
expect_exit 0 "the map of the same lines" "$POPC" map "$SCENE" --variant off,on \
  --vary forward.delay_ticks=$DELAYS --set backward.delay_ticks=0 --stiffness 1e1:1e6 -o "$T/m" -j 2 -q
B=$T/m/boundary.csv
check "  boundary.csv names the variant axis teleop.tdpa and the criterion stable" \
  grep -q '^teleop.tdpa,forward.delay_ticks,criterion,outcome,' "$B"
check "  every line judged by stable" test "$(grep -c ',stable,' "$B")" -eq 6
check "  no Colgate-Schenkel line on a teleoperation line" \
  test -z "$(cell "$B" on 25 k_colgate_schenkel_N_per_m)"
check "  the figure drawn" test -s "$T/m/map.png"
for v in off on; do
  for d in 0 25 100; do
    s=$(verdicts "$T/g/summary.csv" $v $d)
    first=$(awk -v s="$s" 'BEGIN { print index(s, "X") - 1 }')
    bad=$(cell "$B" $v $d k_bad_N_per_m)
    mi=$(index_of "$T/g/summary.csv" $v $d "$bad")
    check "  $v $d: 583 grid points, each with a verdict" bash -c "[[ ${#s} -eq 583 && '$s' != *'?'* ]]"
    check "  $v $d: the map's first failure $bad N/m (index $mi) is the grid's (index $first) within the scan's $SCAN steps" \
      test -n "$mi" -a "$first" -ge 0 -a "$mi" -ge "$first" -a "$mi" -le $((first + SCAN))
    check "  $v $d: K_bad is unstable on the grid, K_ok stable" \
      test "${s:$mi:1}" = X -a "${s:$((mi - 1)):1}" = o
    if [ "$(cell "$B" $v $d outcome)" = not-monotonic ]; then
      top=$(index_of "$T/g/summary.csv" $v $d "$(cell "$B" $v $d k_last_ok_N_per_m)")
      check "  $v $d: its band top (index $top) is stable on the grid, the next point not" \
        test -n "$top" -a "${s:$top:1}" = o -a "${s:$((top + 1)):1}" = X
    fi
  done
done
# with a delay, the PCs off fail below the walls the PCs on hold
for d in 25 100; do
  off=$(cell "$B" off $d k_bad_N_per_m)
  on=$(cell "$B" on $d k_last_ok_N_per_m); [ -n "$on" ] || on=$(cell "$B" on $d k_ok_N_per_m)
  check "  $d ticks: PCs off fail at $off N/m, PCs on stable up to $on N/m (x100 or more)" \
    awk -v a="$off" -v b="$on" 'BEGIN { exit !(a > 0 && b >= 100 * a) }'
done

# ---- criteria that do not judge a teleoperation run
expect_exit 2 "--criterion passive on a teleoperation scene is refused" "$POPC" map "$SCENE" \
  --variant on --criterion passive -o "$T/x1" -q
check "  naming the scene's criteria" err_has "its criteria are stable and diverged"
expect_exit 2 "--criterion stable on a one-port scene is refused" "$POPC" map \
  "$SRC/data/scenes/paper.ini" --variant none --criterion stable -o "$T/x2" -q
check "  saying why" err_has "is not a teleoperation scene"
expect_exit 2 "--set teleop.tdpa is refused (the map varies it: --variant)" "$POPC" map "$SCENE" \
  --variant on --set teleop.tdpa=off -o "$T/x3" -q
check "  nothing made" test ! -e "$T/x1" -a ! -e "$T/x2" -a ! -e "$T/x3"
check_summary
