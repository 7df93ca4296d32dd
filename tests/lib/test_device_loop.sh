#!/usr/bin/env bash
# examples/device_loop (a device's servo callback on the public API) writes
# the rows `popc run` writes for the same scene, bit for bit (the rows are
# compared, the header lines aside; they are equal too), for every variant
# and for every shipped scene the example can run (a simulated axis without
# run.delay_ticks); bad input is exit 2 naming the key.
# Arguments: DEVICE_LOOP
set -u
DL=${1:?device_loop}
SRC=${POPC_SOURCE_ROOT:?}
. "$SRC/tests/check.sh"
T=$(mktemp -d /tmp/popc-device-loop-XXXXXX)
trap 'rm -rf "$T"' EXIT
export POPC_DATA_PATH=$SRC/data
rows() { grep -v '^#' "$1"; }
printf '%s\n' none po-pc ref-energy filtered-velocity ignore hold improved \
  pc-off-reversals energy-bounding windowed-po > "$T/variants"
while read -r v; do
  "$DL" paper "$T/dl-$v.csv" controller.variant="$v" run.duration=2
  check "device_loop paper, $v: exit 0" test $? -eq 0
  "$POPC" run paper -q --set controller.variant="$v" --set run.duration=2 --log "$T/run-$v.csv"
  check "  popc run paper, $v: exit 0" test $? -eq 0
  check "  the rows equal popc run's, bit for bit ($(rows "$T/run-$v.csv" | wc -l) lines)" \
    cmp -s <(rows "$T/dl-$v.csv") <(rows "$T/run-$v.csv")
done < "$T/variants"
for f in "$SRC"/data/scenes/*.ini; do
  name=$(basename "$f" .ini)
  # the example closes the loop on the simulated device with no delay ring
  grep -q -E '^\s*(kind\s*=\s*modbus|delay_ticks\s*=\s*[1-9])' "$f" && continue
  # an admittance scene: the impedance port and device refuse it, naming the
  # key, and nothing is written (the admittance calls: test lib-admittance)
  if grep -q -E '^\s*causality\s*=\s*admittance' "$f"; then
    expect_exit 2 "device_loop on admittance scene $name" "$DL" "$f" "$T/dl-$name.csv" run.duration=1
    check "  says device.causality" err_has 'device.causality'
    check "  wrote no log" test ! -e "$T/dl-$name.csv"
    continue
  fi
  "$DL" "$f" "$T/dl-$name.csv" run.duration=1 2>"$T/err" && "$POPC" run "$f" -q --set run.duration=1 --log "$T/run-$name.csv" 2>>"$T/err"
  check "scene $name: device_loop's rows equal popc run's" cmp -s <(rows "$T/dl-$name.csv") <(rows "$T/run-$name.csv") || cat "$T/err"
done
# bad input: the key and its range, exit 2, nothing written
expect_exit 2 "device_loop with run.rate=0" "$DL" paper "$T/bad.csv" run.rate=0
check "  says which key and its range" err_has 'run.rate' 
check "  wrote no log" test ! -e "$T/bad.csv"
check_summary
