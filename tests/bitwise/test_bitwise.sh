#!/usr/bin/env bash
# Bitwise across compilers (docs/BENCHMARKS.md, "Bitwise across compilers"):
# runs every case below with $POPC and with $POPC_REFERENCE, another build's
# popc (tools/run-tests.sh: build-clang against build-release's gcc), and
# compares the two logs of each case with cmp, header included.
#   meson setup build-clang -Dbitwise_reference=$PWD/build-release/src/popc
#   meson test -C build-clang bitwise
# or by hand: POPC=A POPC_REFERENCE=B tests/bitwise/test_bitwise.sh
# The checked-in digests of tests/behaviour pin the logs themselves (on a
# gcc-only machine too); this test compares two builds on the same machine,
# over more cases, and says how many rows differ and where the first is.
set -u
bitwise_here=$(cd "$(dirname "$0")" && pwd)
bitwise_src=$(cd "$bitwise_here/../.." && pwd)
POPC=${POPC:?POPC must name the popc program}
REF=${POPC_REFERENCE:-}
[ -n "$REF" ] || { echo "POPC_REFERENCE unset: no other build to compare with"; exit 77; }
[ -x "$REF" ] || { echo "POPC_REFERENCE=$REF: not a program (build that build first)"; exit 1; }
T=$(mktemp -d /tmp/popc-bitwise-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$bitwise_src/tests/check.sh"

# The cases: one line per log, "NAME SCENE [popc run options...]", SCENE
# relative to data/scenes, TABLE/ standing for this folder. Each run is 5 s
# at 1 kHz (5001 rows; paper-10khz 1 s at 10 kHz) and takes a few ms.
# The sine cases call glibc's sin and cos, whose last bit depends on the
# variant glibc picks for the CPU (its FMA versions changed 3259 of 5001 rows
# of paper-sine here): two builds compared must run on the same machine.
bitwise_cases() {
  local scene variant m
  # every scene of data/scenes with every variant
  for scene in "$bitwise_src"/data/scenes/*.ini; do
    grep -q '^causality *= *admittance' "$scene" && continue # impedance variants only here
    scene=$(basename "$scene" .ini)
    for variant in none po-pc ref-energy filtered-velocity ignore hold improved; do
      echo "$scene-$variant $scene.ini --variant $variant"
    done
  done
  for m in trapezoid rk4 semi-implicit-euler euler; do
    echo "paper-$m paper.ini --set integrator.method=$m"
  done
  echo "paper-trapezoid-1 paper.ini --set integrator.method=trapezoid --set integrator.substeps=1"
  echo "paper-sine paper.ini --set operator.intent=sine --set operator.amplitude=0.02 --set operator.x0=0.005"
  echo "paper-sine-improved paper.ini --variant improved --set operator.intent=sine --set operator.amplitude=0.02 --set operator.x0=0.005"
  echo "paper-force paper.ini --set operator.intent=force --set operator.force=3"
  echo "paper-force-po-pc paper.ini --variant po-pc --set operator.intent=force --set operator.force=3"
  echo "paper-table paper.ini --set operator.intent=table --set operator.table=TABLE/table-position.csv"
  echo "paper-table-force paper.ini --set operator.intent=table --set operator.table=TABLE/table-force.csv --set operator.table_quantity=force"
  echo "paper-spring paper.ini --set environment.kind=spring"
  echo "paper-spring-damped paper.ini --variant po-pc --set environment.kind=spring --set environment.damping=0.3 --set operator.intent=sine"
  echo "paper-spring-rk4 paper.ini --set environment.kind=spring --set integrator.method=rk4"
  echo "paper-device-spring paper.ini --variant improved --set device.damping=0.2 --set device.stiffness=20"
  echo "paper-ignore-literal paper.ini --variant ignore --set controller.ignore_mode=literal"
  echo "paper-foaw paper.ini --variant filtered-velocity --set controller.foaw_window=64 --set controller.foaw_noise=2e-5"
  echo "paper-10khz paper.ini --variant improved --set run.rate=10000 --set run.duration=1"
}

# write_logs POPC DIR: every case's log as DIR/NAME.csv; prints a line for
# each run that did not exit 0 and returns 1 if there was one.
write_logs() {
  local popc=$1 dir=$2 name scene args rc=0
  mkdir -p "$dir"
  while read -r name scene args; do
    # shellcheck disable=SC2086  # the options are words
    "$popc" run "$bitwise_src/data/scenes/$scene" ${args//TABLE/$bitwise_here} \
      --log "$dir/$name.csv" -q || { echo "$name: $popc run exited $?"; rc=1; }
  done < <(bitwise_cases)
  return $rc
}

check "every case runs with $POPC" write_logs "$POPC" "$T/a"
check "every case runs with $REF" write_logs "$REF" "$T/b"
rows() { sed -n '/^t,/,$p' "$1"; } # from the column line on
while read -r name _; do
  # header included, but for its provenance lines (build, date, command line)
  if cmp -s <(sans_provenance "$T/a/$name.csv") <(sans_provenance "$T/b/$name.csv"); then
    ok "$name: bitwise the same from both builds"
  else
    n=$(paste -d'\n' <(rows "$T/a/$name.csv") <(rows "$T/b/$name.csv") |
        awk 'NR % 2 { l = $0; next } l != $0 { n++ } END { print n + 0 }')
    bad "$name: the logs differ in $n rows, first at $(cmp <(sans_provenance "$T/a/$name.csv") <(sans_provenance "$T/b/$name.csv") 2>&1 | sed -n 's/.*differ: //p')"
  fi
done < <(bitwise_cases)
check_summary
