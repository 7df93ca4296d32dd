#!/usr/bin/env bash
# Builds popc twice from scratch (optimized, and with AddressSanitizer +
# UndefinedBehaviorSanitizer halting on the first report) and runs every test
# suite in both. Prints how long each build's setup, compile and tests took,
# then "N passed, N failed, N skipped" over both builds; exits non-zero if
# anything failed.
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
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
status=0
builds=()
times=()
now() { date +%s.%N; }
run_build() { # dir, meson options...
  local dir=$1; shift
  builds+=("$dir")
  local t0 t1 t2
  t0=$(now)
  rm -rf "$dir"
  meson setup "$dir" "$@" >"$dir.setup.log" 2>&1 || { cat "$dir.setup.log"; return 1; }
  ninja -C "$dir" >"$dir.build.log" 2>&1 || { tail -50 "$dir.build.log"; return 1; }
  t1=$(now)
  meson test -C "$dir" --num-processes "$jobs" --print-errorlogs --timeout-multiplier "${TIMEOUT_MULTIPLIER:-3}"
  local rc=$?
  t2=$(now)
  times+=("$(awk -v d="$dir" -v a="$t0" -v b="$t1" -v c="$t2" \
    'BEGIN { printf "%s: setup and compile %.1f s, tests %.1f s", d, b - a, c - b }')")
  return $rc
}
run_build build-release --buildtype=release -Db_ndebug=false || status=1
run_build build-sanitize --buildtype=debug -Db_sanitize=address,undefined -Db_lundef=false || status=1
printf '%s\n' "${times[@]}"
python3 - "${builds[@]}" <<'PY' || status=1
import json, os, sys
passed = failed = skipped = 0
for d in sys.argv[1:]:
    path = os.path.join(d, "meson-logs", "testlog.json")
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
