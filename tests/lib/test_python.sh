#!/usr/bin/env bash
# import popc (python/popc, over the built libpopc.so): the examples
# (examples/python) run and find the bits of popc run and popc-analyze; the
# module's own checks: header dict, structured rows, errors naming the key.
# Arguments: PYTHON LIBPOPC sanitized|plain (the python3 with numpy; the
# built library; whether it was built with ASan, which python3 cannot load
# without preloading the ASan runtime and which then reports python's own
# leaks: skipped there, the release build and the install test run it).
set -u
PY=${1:?python3 with numpy}
[ "${3:-plain}" = sanitized ] && { echo "skipped: a sanitized libpopc is not loaded into python3 (not built with ASan)"; exit 77; }
SRC=${POPC_SOURCE_ROOT:?}
. "$SRC/tests/check.sh"
T=$(mktemp -d /tmp/popc-python-XXXXXX)
trap 'rm -rf "$T"' EXIT
export POPC_LIBRARY=${2:?libpopc.so} PYTHONPATH=$SRC/python POPC_DATA_PATH=$SRC/data
"$PY" -c 'import numpy' 2>/dev/null || { echo "skipped: $PY has no numpy (python3-numpy)"; exit 77; }
for v in none improved windowed-po; do
  "$PY" "$SRC/examples/python/step_controller.py" paper "$v" > "$T/out" 2>&1
  check "step_controller.py paper $v: rows equal popc run's ($(cat "$T/out"))" test $? -eq 0
done
"$POPC" run paper -q --set run.duration=2 --set controller.variant=hold --log "$T/hold.csv"
"$PY" "$SRC/examples/python/read_log.py" "$T/hold.csv" > "$T/out" 2>&1
check "read_log.py: W recomputed equals the log's ($(tr '\n' ';' < "$T/out"))" test $? -eq 0
"$PY" - "$T/hold.csv" > "$T/out" 2>&1 <<'PYEOF'
import sys, numpy, popc
log = popc.read_log(sys.argv[1])
assert log.header["variant"] == "hold" and log.header["run.duration"] == "2", log.header
assert log.rows.dtype.names[:3] == ("t", "x", "count"), log.rows.dtype
assert log.rows["count"].dtype == numpy.int64 and log.rows["flags"].dtype == numpy.uint32
assert len(log.rows) == 2001 and log.stop == "completed"
# the cells are the doubles the log's text gives (Python's float() is exact)
with open(sys.argv[1]) as f:
    lines = [l for l in f if not l.startswith("#")][1:]
fc = numpy.array([float(l.split(",")[7]) for l in lines])
assert numpy.array_equal(fc.view(numpy.uint64), log.rows["f_c"].view(numpy.uint64))
try:
    popc.Scene("paper").set("run.rate", "0")
    raise SystemExit("run.rate=0 accepted")
except popc.Error as e:
    assert e.status == -1 and "run.rate" in str(e), e
try:
    popc.read_log(sys.argv[1] + ".missing")
    raise SystemExit("a missing log read")
except popc.Error as e:
    assert ".missing" in str(e), e
assert popc.api_version()[0] == 1 and popc.version()
print("ok")
PYEOF
check "the module: header dict, structured rows, exact cells, errors naming key and file" grep -qx ok "$T/out" || cat "$T/out"
check_summary
