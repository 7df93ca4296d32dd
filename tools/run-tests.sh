#!/usr/bin/env bash
# Builds popc twice from scratch (optimized, and with AddressSanitizer +
# UndefinedBehaviorSanitizer halting on the first report: meson test's
# 'sanitize' setup, meson.build) and runs every test suite in both. A third
# build, with clang, runs the numerics and compares its logs with the first
# build's bitwise (the clang block below). Prints how long each build's
# setup, compile and tests took, then "N passed, N failed, N skipped" over
# the three builds; exits non-zero if anything failed.
#
# Environment: TEST_JOBS (parallel tests per build; default twice the cores:
# the Modbus tests spend most of their time waiting for a timeout or a
# paced period, and no test's verdict depends on how busy the machine is),
# TIMEOUT_MULTIPLIER (meson's, default 3).
set -uo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh || { echo "0 passed, 1 failed"; exit 1; }
cores=$(nproc 2>/dev/null || echo 2)
jobs=${TEST_JOBS:-$((2 * cores))}
status=0
times=()
now() { date +%s.%N; }
# timed DIR T0 T1 T2: DIR's setup and compile took T1 - T0, its tests T2 - T1
timed() {
  times+=("$(awk -v d="$1" -v a="$2" -v b="$3" -v c="$4" \
    'BEGIN { printf "%s: setup and compile %.1f s, tests %.1f s", d, b - a, c - b }')")
}
run_build() { # dir, test setup, meson options...
  local dir=$1 setup=$2; shift 2
  local t0 t1 t2 rc
  t0=$(now)
  rm -rf "$dir"
  meson setup "$dir" "$@" >"$dir.setup.log" 2>&1 || { cat "$dir.setup.log"; return 1; }
  ninja -C "$dir" >"$dir.build.log" 2>&1 || { tail -50 "$dir.build.log"; return 1; }
  t1=$(now)
  meson test -C "$dir" ${setup:+--setup "$setup"} --num-processes "$jobs" --print-errorlogs \
    --timeout-multiplier "${TIMEOUT_MULTIPLIER:-3}"
  rc=$?
  t2=$(now)
  timed "$dir" "$t0" "$t1" "$t2"
  return $rc
}
run_build build-release "" --buildtype=release -Db_ndebug=false --werror || status=1
run_build build-sanitize sanitize --buildtype=debug -Db_sanitize=address,undefined -Db_lundef=false || status=1

# --- clang: the same bits from another compiler (issue 10) -------------------
# build-clang: clang, release, --werror, -march=native where clang takes it
# (FMA on most x86-64 CPUs: where contraction would change every log). Runs
# suite unit (the arithmetic: plant and expm, controller, the paper's figures,
# numfmt, the observer against __float128, hard cases, the parsers' corpus,
# the behaviour digests) and suite bitwise (tests/bitwise: every case's log
# cmp-equal to build-release's popc). The other suites test processes, I/O
# and messages, which do not depend on the compiler; each build of them
# costs minutes. This block: 27 s on 2 cores shared with other work (load 7
# to 13): setup and build 21 s, the 17 tests 6 s (bitwise 0.8 s).
clang_build() {
  local native=() t0 t1 t2 rc
  t0=$(now)
  echo 'int x;' | clang -march=native -fsyntax-only -x c - 2>/dev/null && native=(-Dc_args=-march=native)
  CC=clang meson setup build-clang --buildtype=release -Db_ndebug=false --werror "${native[@]}" \
    -Dbitwise_reference="$PWD/build-release/src/popc" >build-clang.setup.log 2>&1 ||
    { cat build-clang.setup.log; return 1; }
  ninja -C build-clang >build-clang.build.log 2>&1 || { tail -50 build-clang.build.log; return 1; }
  t1=$(now)
  meson test -C build-clang --suite unit --suite bitwise --num-processes "$jobs" --print-errorlogs \
    --timeout-multiplier "${TIMEOUT_MULTIPLIER:-3}"
  rc=$?
  t2=$(now)
  timed build-clang "$t0" "$t1" "$t2"
  return $rc
}
rm -rf build-clang
if tools/install-deps.sh test; then clang_build || status=1
else echo "build-clang: clang could not be installed"; status=1
fi
# --- end of the clang block ---------------------------------------------------

# --- the tick beside a JIT (issue 23; docs/BENCHMARKS.md, "The tick beside a JIT")
# Once, briefly (600 s of the paper scene, one round) on build-release: popc run
# beside the numba reference and the chain, figures printed, never judged.
# Counts as one test that fails only when one of its commands fails.
t0=$(now)
tick_bench=1
[ -x build-release/src/popc ] && bench/tick_vs_jit.sh build-release 600 1 && tick_bench=0
[ "$tick_bench" -eq 0 ] || { echo "bench/tick_vs_jit.sh: a command failed"; status=1; }
times+=("$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "bench/tick_vs_jit.sh: %.1f s", b - a }')")
printf '%s\n' "${times[@]}"

# meson test names its log after the setup
python3 - build-release/meson-logs/testlog.json build-sanitize/meson-logs/testlog-sanitize.json \
  build-clang/meson-logs/testlog.json "tick-bench=$tick_bench" <<'PY' || status=1
import json, os, sys
passed = failed = skipped = 0
for path in sys.argv[1:]:
    if path.startswith("tick-bench="):  # bench/tick_vs_jit.sh's exit status
        if path.endswith("=0"): passed += 1
        else: failed += 1
        continue
    d = path.split("/")[0]
    if not os.path.exists(path):
        print(f"{d}: no test log (the build failed)"); failed += 1; continue
    for line in open(path):
        r = json.loads(line)["result"]
        if r in ("OK", "EXPECTEDFAIL"): passed += 1
        elif r == "SKIP": skipped += 1
        else: failed += 1
print(f"{passed} passed, {failed} failed, {skipped} skipped")
sys.exit(1 if failed else 0)
PY
exit $status
