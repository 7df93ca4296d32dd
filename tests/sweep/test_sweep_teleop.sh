#!/usr/bin/env bash
# popc sweep over teleoperation scenes (issue 26; docs/SWEEPS.md,
# "Teleoperation scenes"): delays, stiffness and teleop.tdpa vary like any key;
# the summary has the tele_* columns (the run summary's two-port figures)
# before wall_time_s in a teleoperation sweep only; a sweep mixing one-port
# and teleoperation runs is refused before any work, as is --list.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/teleop-wall.ini
T=$(mktemp -d /tmp/popc-sweep-teleop-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
# cell FILE RUN NAME: the cell of column NAME in run RUN's row
cell() { awk -F, -v run="$2" -v name="$3" \
  'NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next } $1 == run { print $(col[name]) }' "$1"; }
TELE=tele_violations,tele_margin_min_m,tele_margin_min_s,tele_active_m,tele_active_s,tele_clamped_m,tele_clamped_s,tele_f_c_max,tele_v_c_max,tele_drift_end,tele_xs_late_pp,tele_oscillating

# round trip = forward + backward delay; backward 0 here: 0 and 50 ms
expect_exit 1 "teleop sweep over delay x tdpa (the diverged run fails the sweep)" \
	"$POPC" sweep "$SCENE" --vary forward.delay_ticks=0,50 --vary teleop.tdpa=off,on \
	--vary environment.stiffness=20000 --set backward.delay_ticks=0 --no-log -q -j 2 -o "$T/s"
S=$T/s/summary.csv
check "  the header ends in the tele_* columns, then wall_time_s" \
	grep -q ",limit_cycle,$TELE,wall_time_s\$" <(head -1 "$S")
check "  4 rows" test "$(tail -n +2 "$S" | wc -l)" -eq 4
check "  50 ms, PCs off: diverged (exit 6), oscillating" \
	test "$(cell "$S" 0002 exit_status),$(cell "$S" 0002 tele_oscillating)" = "6,1"
check "  50 ms, PCs off: no late peak to peak (the run stopped)" test -z "$(cell "$S" 0002 tele_xs_late_pp)"
check "  50 ms, PCs on: completed and settled" \
	test "$(cell "$S" 0003 exit_status),$(cell "$S" 0003 tele_oscillating)" = "0,0"
check "  PCs on: the two-port condition held at every tick, no PC clamped" \
	test "$(cell "$S" 0001 tele_violations)$(cell "$S" 0003 tele_violations),$(cell "$S" 0003 tele_clamped_m)$(cell "$S" 0003 tele_clamped_s)" = "00,00"
check "  PCs on at 50 ms: both PCs acted" \
	awk -v m="$(cell "$S" 0003 tele_active_m)" -v s="$(cell "$S" 0003 tele_active_s)" 'BEGIN { exit !(m > 0 && s > 0) }'
check "  PCs off at 0 ms: the condition breaks (the sampled contact is not lossless)" \
	awk -v v="$(cell "$S" 0000 tele_violations)" -v mm="$(cell "$S" 0000 tele_margin_min_m)" \
	'BEGIN { exit !(v > 0 && mm < 0) }'
check "  every tele_* cell a finite number or empty" \
	awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i ~ /^tele_/) t[i] = 1; next }
	  { for (i in t) if ($i != "" && $i !~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/) exit 1 }' "$S"
check "  summary.jsonl: the verdict a number" grep -q '"tele_oscillating":1' "$T/s/summary.jsonl"
expect_exit 1 "  the same command again (a resume) reads its plan back" \
	"$POPC" sweep "$SCENE" --vary forward.delay_ticks=0,50 --vary teleop.tdpa=off,on \
	--vary environment.stiffness=20000 --set backward.delay_ticks=0 --no-log -q -j 2 -o "$T/s"
check "  ... with the same columns" grep -q ",$TELE,wall_time_s\$" <(head -1 "$S")
expect_exit 0 "  sweep stats takes a tele_* metric" "$POPC" sweep stats "$T/s" --by teleop.tdpa \
	--metrics tele_f_c_max,tele_oscillating --format csv
check "  ... one row per group and metric" test "$(grep -c '^on,tele_' "$T/out")" -eq 2

# ---- every one-port sweep keeps its columns
expect_exit 0 "a one-port sweep" "$POPC" sweep "$SRC/data/scenes/paper.ini" \
	--vary environment.stiffness=1000 --set run.duration=0.2 --no-log -q -o "$T/p"
check "  has no tele_* column" test "$(head -1 "$T/p/summary.csv" | grep -c tele_)" -eq 0
check "  ends in limit_cycle,wall_time_s" grep -q ',limit_cycle,wall_time_s$' <(head -1 "$T/p/summary.csv")

# ---- a mix is refused before any work
expect_exit 2 "--vary teleop.architecture=off,position-force is refused" "$POPC" sweep "$SCENE" \
	--vary teleop.architecture=off,position-force --no-log -q -o "$T/mix"
check "  naming the key and both values" err_has "teleop.architecture=off,position-force: 'off' and 'position-force'"
check "  nothing made" test ! -e "$T/mix"
expect_exit 2 "a teleoperation sweep with --list is refused" "$POPC" sweep "$SCENE" \
	--vary forward.delay_ticks=0,50 --list -o "$T/list"
check "  saying why" err_has "--list: a teleoperation sweep"
check "  nothing made" test ! -e "$T/list"
check_summary
