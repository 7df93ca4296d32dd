#!/usr/bin/env bash
# Quick start, command 1: installs what is missing of the paper set (tools/
# install-deps.sh paper: the compiler, meson, the libraries and gnuplot; no
# service), builds popc in build/, runs the paper's experiment (seed Figs. 3,
# 6, 10, 14, 16) on the simulated plant for every controller variant, and
# draws the report. Output in out/paper/.
#
# Quiet when every step works (the comparison table and where things are);
# when a step fails, its whole output and which step it was, exit 1. A build/
# that a failed `meson setup` left without build.ninja is set up again.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 1
log=$(mktemp "${TMPDIR:-/tmp}/popc-paper.XXXXXX") || exit 1
trap 'rm -f "$log"' EXIT

fail() { echo "popc: paper.sh: $*" >&2; exit 1; }
# step WHAT COMMAND...: runs COMMAND with its output kept aside; on failure
# prints that output and names the step
step() {
  local what=$1; shift
  "$@" </dev/null >"$log" 2>&1 && return 0
  local rc=$?
  cat "$log" >&2
  fail "$what failed (exit $rc): $*"
}

tools/install-deps.sh paper || fail "installing the packages of the paper set failed (tools/install-deps.sh paper)"

# build.ninja is the last thing meson setup writes: without it build/ is
# what a failed setup left, and ninja could only say "loading 'build.ninja'"
if [ ! -f build/build.ninja ]; then
  [ -e build ] && echo "popc: paper.sh: build/ has no build.ninja (an earlier meson setup failed); setting it up again" >&2
  rm -rf build
  if ! meson setup build --buildtype=release </dev/null >"$log" 2>&1; then
    cat "$log" >&2
    fail "meson setup build failed; the full log is build/meson-logs/meson-log.txt (the next run sets build/ up again)"
  fi
fi
step "building popc (ninja -C build)" ninja -C build

out=out/paper
rm -rf "$out"
mkdir -p "$out/logs" || fail "cannot create $out/logs"
for v in none po-pc ref-energy filtered-velocity ignore hold improved; do
  step "the paper run of variant $v" \
    build/src/popc run data/scenes/paper.ini --variant "$v" --log "$out/logs/$v.csv" --summary "$out/summary.csv" -q
done
step "drawing the report" build/analysis/popc-analyze report "$out"/logs/*.csv -o "$out/report"
compare_md() { build/analysis/popc-analyze compare "$out"/logs/*.csv --format markdown >"$out/compare.md"; }
step "the comparison table (popc-analyze compare)" compare_md
cat "$out/compare.md"
echo "logs: $out/logs/, run summaries: $out/summary.csv, report: $out/report/index.html"
