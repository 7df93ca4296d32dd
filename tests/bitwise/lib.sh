# shellcheck shell=bash
# The cases of tests/bitwise, sourced by test_bitwise.sh. bitwise_cases prints
# one line per log: "KIND NAME SCENE [popc run options...]", SCENE relative to
# data/scenes, TABLE/ standing for this folder. KIND is
#   exact  the rows come from + - * / and sqrt, each rounded once to double,
#          and libm functions with exact results (floor, ceil, ldexp, fabs,
#          fmax, llround, nearbyint); the other libm calls on the way (expm's
#          ceil(log2()) scaling, the stability guard's log, log1p, exp) move
#          no row unless a result sits within an ulp of a power of two or of
#          the guard's margin. So the same bits with any compiler that honours
#          these flags on any IEEE-754 double machine: the digests are checked
#          in (expected.sha256), and a gcc-only machine checks them too;
#   libm   the sine intent calls glibc's sin and cos, whose last bit depends
#          on the variant glibc picks for the CPU (its FMA versions of sin
#          and cos change 3259 of 5001 rows of paper-sine): compared between
#          two builds on the same machine only.
# The caller sets bitwise_src (the source root) and bitwise_here (this folder).
# Each run is 5 s at 1 kHz (5001 rows; paper-10khz 1 s at 10 kHz), a few ms.
bitwise_cases() {
  local scene variant m
  # every scene with every variant (the scenes differ only in their variant,
  # but a scene a user runs is a scene the test runs)
  for scene in paper fig3 fig10 fig14 fig16 no-pc; do
    for variant in none po-pc ref-energy filtered-velocity ignore hold improved; do
      echo "exact $scene-$variant $scene.ini --variant $variant"
    done
  done
  for m in trapezoid rk4 semi-implicit-euler euler; do
    echo "exact paper-$m paper.ini --set integrator.method=$m"
  done
  echo "exact paper-trapezoid-1 paper.ini --set integrator.method=trapezoid --set integrator.substeps=1"
  echo "libm paper-sine paper.ini --set operator.intent=sine --set operator.amplitude=0.02 --set operator.x0=0.005"
  echo "libm paper-sine-improved paper.ini --variant improved --set operator.intent=sine --set operator.amplitude=0.02 --set operator.x0=0.005"
  echo "exact paper-force paper.ini --set operator.intent=force --set operator.force=3"
  echo "exact paper-force-po-pc paper.ini --variant po-pc --set operator.intent=force --set operator.force=3"
  echo "exact paper-table paper.ini --set operator.intent=table --set operator.table=TABLE/table-position.csv"
  echo "exact paper-table-force paper.ini --set operator.intent=table --set operator.table=TABLE/table-force.csv --set operator.table_quantity=force"
  echo "exact paper-spring paper.ini --set environment.kind=spring"
  echo "libm paper-spring-damped paper.ini --variant po-pc --set environment.kind=spring --set environment.damping=0.3 --set operator.intent=sine"
  echo "exact paper-spring-rk4 paper.ini --set environment.kind=spring --set integrator.method=rk4"
  echo "exact paper-device-spring paper.ini --variant improved --set device.damping=0.2 --set device.stiffness=20"
  echo "exact paper-ignore-undo paper.ini --variant ignore --set controller.ignore_mode=undo"
  echo "exact paper-foaw paper.ini --variant filtered-velocity --set controller.foaw_window=64 --set controller.foaw_noise=2e-5"
  echo "exact paper-10khz paper.ini --variant improved --set run.rate=10000 --set run.duration=1"
}

# write_logs POPC DIR: every case's log as DIR/NAME.csv; prints a line for
# each run that did not exit 0 and returns 1 if there was one.
write_logs() {
  local popc=$1 dir=$2 name scene args rc=0
  mkdir -p "$dir"
  while read -r _ name scene args; do
    # shellcheck disable=SC2086  # the options are words
    "$popc" run "$bitwise_src/data/scenes/$scene" ${args//TABLE/$bitwise_here} \
      --log "$dir/$name.csv" -q || { echo "$name: $popc run exited $?"; rc=1; }
  done < <(bitwise_cases)
  return $rc
}

# rows_digest LOG: SHA-256 of the log from its column line on (rows and the
# stop line); the header holds the version and absolute table paths.
rows_digest() { sed -n '/^t,/,$p' "$1" | sha256sum | cut -d' ' -f1; }
