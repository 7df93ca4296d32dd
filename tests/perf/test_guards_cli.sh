#!/usr/bin/env bash
# The plant's and the simulated axis' guards as a user meets them through
# popc run: scenes double precision cannot step are refused naming their keys
# (exit 2), an encoder resolution too fine for the scene's positions is
# refused, a growth factor that overflows is called unstable (exit 6), a
# closed loop that diverges stops at the scene's bound blaming the physics
# with a clean log, and long stable runs are never stopped. Each case is a
# defect that was found; the comment says what it did before.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
PAPER="$SRC/data/scenes/paper.ini"
T=$(mktemp -d /tmp/popc-guards-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

# K/M = 1e9 / 2.3e-308 = inf: the plant's matrices were inf/NaN, the run
# printed "completed", exit 0, with uninitialised encoder counts
expect_exit 2 "K/M not finite is refused" "$POPC" run "$PAPER" -q --set operator.mass=0 \
  --set device.mass=2.3e-308 --set operator.stiffness=1e9
check "  names the keys" err_has "(operator.stiffness + device.stiffness) / (operator.mass + device.mass)"
expect_exit 2 "B/M not finite is refused" "$POPC" run "$PAPER" -q --set operator.mass=0 \
  --set device.mass=2.3e-308 --set operator.stiffness=0 --set operator.damping=1e6
check "  names the keys" err_has "(operator.damping + device.damping) / (operator.mass + device.mass)"
check "  names no parameter of the core" bash -c "! grep -qE 'mass_kg|_Npm|_Nspm|period_s' '$T/err'"

# RK4 x 100 on K = 1e9 N/m, M = 1e-3 kg grows 400^100 per period: the product
# of the matrices overflowed, rho was NaN and the verdict "stable but too
# inaccurate"
expect_exit 6 "an overflowing growth factor is unstable" "$POPC" run "$PAPER" -q \
  --set operator.stiffness=1e9 --set operator.mass=0 --set device.mass=1e-3 --set integrator.method=rk4
check "  says unstable" err_has "is unstable for this plant"
check "  and the stable substep count" err_has "integrator.substeps >= 400"
check "  not 'too inaccurate'" bash -c "! grep -q 'stable but too inaccurate' '$T/err'"

# explicit Euler at 1 substep on a stiff hand (h w = 1000) still stops at once
expect_exit 6 "explicit Euler on a stiff hand is stopped" "$POPC" run "$PAPER" -q \
  --set integrator.method=euler --set integrator.substeps=1 --set operator.stiffness=1e9 \
  --set operator.mass=1e-3 --set device.mass=0
check "  before the first step" err_has "(tick 0)"

# encoder.resolution = 1e-300: stopped at tick 0 as "the plant diverged ...
# the closed loop is unstable"
expect_exit 2 "a resolution too fine for the scene is refused" "$POPC" run "$PAPER" -q \
  --set encoder.resolution=1e-300
check "  names encoder.resolution and 2^53" bash -c "grep -q 'encoder.resolution = 1e-300 m is too fine' '$T/err' && grep -q '2^53 counts' '$T/err'"
check "  no divergence blamed" bash -c "! grep -q diverged '$T/err'"
# a force pushing a free-ish mass to 1e6 m passes 2^53 counts of 1e-15 m at
# 9 m: foreseen before the run (its reach over the hand's spring), its own
# message, not a divergence (it was found at run time, exit 2 after ticks ran)
expect_exit 2 "count overflow has its own message" "$POPC" run "$PAPER" -q \
  --set operator.intent=force --set operator.force=1e6 --set operator.force_rate=1e9 \
  --set operator.stiffness=1 --set environment.stiffness=0 --set encoder.resolution=1e-15
check "  names encoder.resolution" err_has "encoder.resolution = 1e-15 m is too fine for this force intent"
check "  and what to change" err_has "use encoder.resolution >= "
check "  no divergence blamed" bash -c "! grep -q diverged '$T/err'"

# a sampled 1e6 N/m wall without PC is active: the exact plant flew to
# -3.3e4 m, W - E_ref = -6.4e12 J, and the run "completed" with exit 0
# these runs keep the ramp they were measured with (rest at -0.01 m until
# 0.5 s, 0.05 m/s to 0.03 m), not the paper scene's calibrated one
OLD_RAMP="--set operator.x0=-0.01 --set operator.t0=0.5 --set operator.speed=0.05 --set operator.x_end=0.03"
expect_exit 6 "a diverging closed loop stops at the scene's bound" "$POPC" run "$PAPER" -q $OLD_RAMP \
  --set environment.stiffness=1e6 --variant none --log "$T/div.csv"
check "  blames the physics" err_has "the closed loop of this scene diverged (the physics, not the integrator)"
check "  names the bound" err_has "the bound is 1.3 m"
check "  the passivity condition without delay: b > K_e T / 2" err_has "a sampled wall is passive for b > K_e T / 2)"
# with a loop delay the condition is b > K_e T (1/2 + d) (docs/ANALYSIS.md,
# "Loop delay moves the passivity boundary"), not K_e T / 2 (issue 27)
expect_exit 6 "a diverging closed loop with run.delay_ticks = 2" "$POPC" run "$PAPER" -q $OLD_RAMP \
  --set environment.stiffness=1e6 --set run.delay_ticks=2 --variant none
check "  the passivity condition with the delay" err_has "a sampled wall is passive for b > K_e T (1/2 + d), d = run.delay_ticks = 2)"
check "  the log ends with the stop line" bash -c "tail -n 1 '$T/div.csv' | grep -q '^# stop = closed loop diverged: '"
# x_true is column 4 (t,x,count,x_true,...): nothing logged past 1.3 m
check "  the log's columns are as assumed" bash -c "grep -v '^#' '$T/div.csv' | head -n 1 | grep -q '^t,x,count,x_true,'"
check "  nothing past the bound logged" awk -F, '!/^#/ && $1 != "t" { x = $4 < 0 ? -$4 : $4; if (x > 1.3) bad = 1 } END { exit bad }' "$T/div.csv"
check "  nor any non-finite number" bash -c "! grep -v '^#' '$T/div.csv' | grep -qiE 'nan|inf'"

# an undamped stiff light hand (K/M = 1e15 1/s^2, w T = 3.2e4 at 1 kHz) with
# the wall out of reach is a bounded motion; the exact step's det(Phi) was
# 1 + 2.3e-4 (unbalanced scaling and squaring), the free motion grew every
# period and the run stopped at t = 213 s as "the physics" diverging
expect_exit 0 "the exact step keeps a stiff light hand bounded" "$POPC" run "$PAPER" -q $OLD_RAMP \
  --set operator.mass=0 --set device.mass=1e-6 --set operator.stiffness=1e9 \
  --set operator.damping=0 --set environment.position=1 --variant none --set run.duration=1000 \
  --set encoder.resolution=1e-12 --log "$T/stiff.csv"
# the hand follows x_d within V / w = 1.6e-9 m: x in [x0, x_end] to 1e-8 m
check "  x stays within the ramp's positions" awk -F, '!/^#/ && $1 != "t" { if ($4 < -0.01000001 || $4 > 0.03000001) bad = 1 } END { exit bad }' "$T/stiff.csv"

# explicit Euler x 100 on the paper scene is stable and accurate (0.12
# counts): it was stopped at t = 27.6 s of a 600 s run (x 8 at 10.5 s)
expect_exit 0 "a long accurate Euler run completes" "$POPC" run "$PAPER" $OLD_RAMP --set run.duration=600 \
  --set integrator.method=euler --set integrator.substeps=100
check "  with its error below one count" err_has "max position error against exact: 1.22e-06 m"

check_summary
