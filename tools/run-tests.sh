#!/usr/bin/env bash
# Builds popc twice from scratch (optimized, and with AddressSanitizer +
# UndefinedBehaviorSanitizer halting on the first report) and runs every test
# suite in both. Prints "N passed, N failed" over both builds; exits non-zero
# if anything failed.
set -uo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh || { echo "0 passed, 1 failed"; exit 1; }
jobs=$(nproc 2>/dev/null || echo 2)
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
status=0
run_build() { # dir, meson options...
  local dir=$1; shift
  rm -rf "$dir"
  meson setup "$dir" "$@" >"$dir.setup.log" 2>&1 || { cat "$dir.setup.log"; return 1; }
  ninja -C "$dir" >"$dir.build.log" 2>&1 || { tail -50 "$dir.build.log"; return 1; }
  meson test -C "$dir" --num-processes "$jobs" --print-errorlogs --timeout-multiplier "${TIMEOUT_MULTIPLIER:-3}"
}
run_build build-release --buildtype=release -Db_ndebug=false || status=1
run_build build-sanitize --buildtype=debug -Db_sanitize=address,undefined -Db_lundef=false || status=1
python3 - build-release build-sanitize <<'PY' || status=1
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
