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
# the data path: POPC_DATA_PATH by default (the module passes it, libpopc
# reads no environment), or the data_path given (API 1.2)
import os
data = os.environ["POPC_DATA_PATH"]
assert popc.Scene("paper").period_s == popc.Scene("paper", data_path=data).period_s
try:
    popc.Scene("paper", data_path="/nonexistent")
    raise SystemExit("paper found in /nonexistent")
except popc.Error as e:
    assert "/nonexistent" in str(e), e
print("ok")
PYEOF
check "the module: header dict, structured rows, exact cells, errors naming key and file" grep -qx ok "$T/out" || cat "$T/out"
# Scene.from_log (API 1.3): the log's scene runs to the log, byte for byte;
# a recorded CSV without popc's header is refused, naming the file
printf 't,x\n0,0\n' > "$T/recorded.csv"
"$PY" - "$T/hold.csv" "$T/again.csv" "$T/recorded.csv" > "$T/out" 2>&1 <<'PYEOF'
import sys, popc
s = popc.Scene.from_log(sys.argv[1])
assert s.tick_count == 2001, s.tick_count
popc.run(s, sys.argv[2])
try:
    popc.Scene.from_log(sys.argv[3])
    raise SystemExit("a recorded log gave a scene")
except popc.Error as e:
    assert e.status == -1 and "recorded.csv" in str(e) and "not a popc log" in str(e), e
print("ok")
PYEOF
check "Scene.from_log: the log's scene ($(tr '\n' ';' < "$T/out"))" grep -qx ok "$T/out"
# popc run's provenance lines (its build, date, command line) are its own
prov='^# (popc_build|date|command) = '
check "  run again, it writes the log byte for byte, popc run's provenance lines aside" \
  cmp -s <(grep -Ev "$prov" "$T/hold.csv") <(grep -Ev "$prov" "$T/again.csv")
# the admittance port against the admittance device, from Python: every
# column of popc run's admittance log, bit for bit (API 1.1)
"$POPC" run admittance-wall -q --set run.duration=1 --set admittance.variant=parallel-improved --log "$T/adm.csv"
"$PY" - "$T/adm.csv" > "$T/out" 2>&1 <<'PYEOF'
import sys, numpy, popc
s = popc.Scene("admittance-wall", **{"run.duration": "1", "admittance.variant": "parallel-improved"})
log = popc.read_log(sys.argv[1])
port, sim = popc.AdmittancePort(s), popc.AdmittanceSim(s)
assert len(log.rows.dtype.names) == 15, log.rows.dtype.names
cols = {c: [] for c in log.rows.dtype.names}
smp = sim.sample
for k in range(s.tick_count):
    t, a = port.step(smp.count, smp.force_count)
    for c, v in (("t", t.t_s), ("x", t.x_m), ("count", t.count), ("v", t.v_mps), ("f_e", t.f_e_N), ("f_pc", t.f_pc_N), ("f_c", t.f_c_N),
                 ("W", t.W_J), ("E_ref", t.E_ref_J), ("flags", t.flags), ("f_count", a.f_count),
                 ("f_meas", a.f_meas_N), ("x_cmd", smp.x_cmd_m), ("v_ve", a.v_ve_mps),
                 ("v_pc", a.v_pc_mps)):
        cols[c].append(v)
    if k + 1 < s.tick_count:
        smp = sim.exchange(a.v_c_mps)
for c in log.rows.dtype.names:
    mine = numpy.array(cols[c], dtype=log.rows[c].dtype)
    assert len(cols[c]) == len(log.rows) and numpy.array_equal(
        mine.view(numpy.uint8), numpy.ascontiguousarray(log.rows[c]).view(numpy.uint8)), c
try:
    popc.AdmittancePort(popc.Scene("paper"))
    raise SystemExit("an admittance port of an impedance scene made")
except popc.Error as e:
    assert "device.causality" in str(e), e
print("ok", sum(1 for v in cols["v_pc"] if v != 0.0))
PYEOF
check "the admittance port and device from Python: popc run's admittance log, every column bit for bit (ok, PC active on N ticks: $(cat "$T/out"))" grep -q "^ok [1-9]" "$T/out" || cat "$T/out"
check_summary
