#!/usr/bin/env bash
# Builds popc twice from scratch (optimized, and with AddressSanitizer +
# UndefinedBehaviorSanitizer halting on the first report: meson test's
# 'sanitize' setup, meson.build) and runs every test suite in both. Prints
# "N passed, N failed" over both builds; exits non-zero if anything failed.
set -uo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh || { echo "0 passed, 1 failed"; exit 1; }
jobs=$(nproc 2>/dev/null || echo 2)
status=0
run_build() { # dir, test setup, meson options...
  local dir=$1 setup=$2; shift 2
  rm -rf "$dir"
  meson setup "$dir" "$@" >"$dir.setup.log" 2>&1 || { cat "$dir.setup.log"; return 1; }
  ninja -C "$dir" >"$dir.build.log" 2>&1 || { tail -50 "$dir.build.log"; return 1; }
  meson test -C "$dir" ${setup:+--setup "$setup"} --num-processes "$jobs" --print-errorlogs \
    --timeout-multiplier "${TIMEOUT_MULTIPLIER:-3}"
}
run_build build-release "" --buildtype=release -Db_ndebug=false || status=1
run_build build-sanitize sanitize --buildtype=debug -Db_sanitize=address,undefined -Db_lundef=false || status=1
# meson test names its log after the setup
python3 - build-release/meson-logs/testlog.json build-sanitize/meson-logs/testlog-sanitize.json <<'PY' || status=1
import json, os, sys
passed = failed = skipped = 0
for path in sys.argv[1:]:
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
