#!/usr/bin/env bash
# The numba reference of the tick (bench/tick_jit.py, issue 23) computes what
# `popc run` computes: on the paper's scene over 3 s (the ramp's end splits
# period 688), its W, E_ref and E_port at the last tick equal the last row of
# popc's log bit for bit, and its summary sums (the PC's energy, E_dev, the
# minima and maxima) equal the run summary's cells. No time is asserted.
#
# Without numba (Debian: python3-numba) the same Python runs plain (--plain)
# and is checked the same way; the test then exits 77: the JIT itself did
# not run.
#
#   test_tick_jit.sh JIT_CONSTANTS   (meson passes bench/jit_constants)
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
JC=${1:?usage: test_tick_jit.sh JIT_CONSTANTS}
T=$(mktemp -d /tmp/popc-tickjit-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

scene=$SRC/data/scenes/paper.ini
sets=(--set run.duration=3)
# Debian's numba is the system python3's (a pyenv's python3 first in PATH
# does not see it), as readers.sh finds pandas
PY= plain=()
for p in python3 /usr/bin/python3; do
  "$p" -c 'import numba' 2>/dev/null && { PY=$p; break; }
done
if [ -z "$PY" ]; then
  for p in python3 /usr/bin/python3; do
    "$p" -c 'import numpy' 2>/dev/null && { PY=$p; break; }
  done
  [ -n "$PY" ] || { echo "skip: no python3 imports numba or numpy (Debian: python3-numba)"; exit 77; }
  echo "numba is missing (Debian: python3-numba): checking the reference in plain Python"
  plain=(--plain)
fi

expect_exit 0 "popc run paper.ini over 3 s, log and summary" \
  "$POPC" run "$scene" "${sets[@]}" --log "$T/log.csv" --summary "$T/sum.csv" -q
expect_exit 0 "the reference over the same scene" \
  "$PY" "$SRC/bench/tick_jit.py" "$JC" "$scene" "${sets[@]}" "${plain[@]}"
cp "$T/out" "$T/ref.txt"
check "  it ran 3001 ticks" grep -qx "ticks 3001" "$T/ref.txt"

# name=value pairs of the log's last row and of the summary's row, and the
# reference's, compared as the 64 bits of each double (float.hex)
python3 - "$T/log.csv" "$T/sum.csv" "$T/ref.txt" > "$T/cmp.txt" <<'EOF'
import csv, sys
rows = [l for l in open(sys.argv[1]) if not l.startswith("#")]
head, last = rows[0].strip().split(","), rows[-1].strip().split(",")
log = dict(zip(head, last))
with open(sys.argv[2]) as f:
    summ = next(csv.DictReader(f))
ref = dict(l.split() for l in open(sys.argv[3]) if l.strip())
pairs = [("W", log["W"]), ("E_ref", log["E_ref"]), ("E_port", log["E_port"]),
         ("device_energy_end", summ["device_energy_end"]), ("pc_energy", summ["pc_energy"]),
         ("port_energy_min", summ["port_energy_min"]), ("po_error_end", summ["po_error_end"]),
         ("po_error_max", summ["po_error_max"]), ("device_energy_min", summ["device_energy_min"]),
         ("w_minus_eref_min", summ["w_minus_eref_min"]),
         ("w_minus_eref_end", summ["w_minus_eref_end"])]
for name, cell in pairs:
    mine = float.fromhex(ref[name])
    print(name, "equal" if float(cell).hex() == mine.hex() else "DIFFER",
          cell, repr(mine))
EOF
cat "$T/cmp.txt"
for name in W E_ref E_port device_energy_end pc_energy port_energy_min po_error_end po_error_max \
  device_energy_min w_minus_eref_min w_minus_eref_end; do
  check "  $name bit for bit" grep -q "^$name equal " "$T/cmp.txt"
done
# the reference is the JIT's only where it ran under numba
if [ ${#plain[@]} -gt 0 ]; then
  check_summary || exit 1
  echo "skip: numba is missing (Debian: python3-numba); the plain reference agreed"
  exit 77
fi
check "  it ran under numba" grep -qx "jit numba" "$T/ref.txt"
check_summary
