#!/usr/bin/env bash
# An encoder count overflow is foreseen before anything runs where the scene
# bounds its positions (a position table's largest |value|; a force, intent or
# table, over the hand's and the device's springs): exit 2 naming the keys and
# the resolution that works, no log. A force with no spring to hold it has no
# bound: the run stops when its count would overflow as a numeric failure
# (exit 6) with a clean log. popc of 46f30c1 exited 2 (bad input) after
# hundreds of ticks in all four cases.
set -u
POPC=${POPC:?POPC must name the popc program}
case $POPC in /*) ;; *) POPC=$PWD/$POPC ;; esac
SRC=${POPC_SOURCE_ROOT:?}
A=${1:?popc-analyze as argument 1}
T=$(mktemp -d /tmp/popc-reach-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
SCENE=$SRC/data/scenes/paper.ini
# away from the wall (at 0): nothing stops the hand's table of -900 m
printf 't,x_d\n0,-0.01\n0.5,-0.01\n1.0,-900\n2,-900\n' > "$T/far.csv"
printf 't,f\n0,0\n0.5,0\n1.0,-1e5\n2,-1e5\n' > "$T/push.csv"

expect_exit 2 "a position table to -900 m at 1e-14 m" "$POPC" run "$SCENE" --set operator.intent=table \
	--set "operator.table=$T/far.csv" --set encoder.resolution=1e-14 --log "$T/a.csv"
check "  names the resolution, the table's reach and what works" err_has "encoder.resolution = 1e-14 m is too fine for this table intent: positions up to 9001 m (10 x the largest of the table's |x_d| (900 m), |operator.x0|, |environment.position|, + 1 m) would exceed 2^53 counts; use encoder.resolution >= 1e-12 m"
check "  nothing ran: no log" test ! -e "$T/a.csv"
expect_exit 0 "  the same table at 1e-12 m runs" "$POPC" run "$SCENE" --set operator.intent=table \
	--set "operator.table=$T/far.csv" --set encoder.resolution=1e-12 -q --set run.duration=1.5
expect_exit 2 "a force table of -1e5 N on K_HO = 50 N/m at 1e-13 m" "$POPC" run "$SCENE" --set operator.intent=table \
	--set operator.table_quantity=force --set "operator.table=$T/push.csv" --set encoder.resolution=1e-13 --log "$T/b.csv"
check "  names the springs" err_has "(operator.stiffness |operator.x0| + the table's largest |force|) / (operator.stiffness + device.stiffness) = 2000.01 m"
check "  nothing ran: no log" test ! -e "$T/b.csv"
expect_exit 2 "a force intent of -1e6 N on K_HO = 10 N/m at 1e-12 m" "$POPC" run "$SCENE" --set operator.intent=force \
	--set operator.force=-1e6 --set operator.force_rate=1e9 --set operator.stiffness=10 --set encoder.resolution=1e-12 --log "$T/c.csv"
check "  names the keys" err_has "too fine for this force intent: positions up to 1e+06 m (10 x (operator.stiffness |operator.x0| + |operator.force|) / (operator.stiffness + device.stiffness) = 100000 m"
check "  nothing ran: no log" test ! -e "$T/c.csv"
expect_exit 2 "popc scene show refuses the far table too" "$POPC" scene show "$SCENE" --set operator.intent=table \
	--set "operator.table=$T/far.csv" --set encoder.resolution=1e-14
check "  names it" err_has "too fine for this table intent"

# no spring: no bound; the run ends as a numeric failure, the log clean
expect_exit 6 "a force of 1e6 N on a free mass at 1e-12 m" "$POPC" run "$SCENE" --set operator.intent=force \
	--set operator.force=1e6 --set operator.force_rate=1e9 --set operator.stiffness=0 --set operator.damping=0 \
	--set encoder.resolution=1e-12 --log "$T/d.csv"
check "  says why" err_has "encoder count overflow at t = "
check "  the log ends with its stop line" bash -c "tail -n 1 '$T/d.csv' | grep -q '^# stop = closed loop diverged: encoder count overflow'"
check "  no non-finite number in the log" bash -c "! grep -v '^#' '$T/d.csv' | grep -qiE 'nan|inf'"
expect_exit 0 "  popc-analyze energy --check reads it" "$A" energy --check "$T/d.csv"
check_summary
