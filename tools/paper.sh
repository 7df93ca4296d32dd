#!/usr/bin/env bash
# Quick start, command 1: installs what is missing, builds popc, runs the
# paper's experiment (seed Figs. 3, 6, 10, 14, 16) on the simulated plant for
# every controller variant, and draws the report. Output in out/paper/.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
[ -d build ] || meson setup build --buildtype=release >/dev/null
ninja -C build >/dev/null
out=out/paper
rm -rf "$out"
mkdir -p "$out/logs"
for v in none po-pc ref-energy filtered-velocity ignore hold improved; do
  build/src/popc run data/scenes/paper.ini --variant "$v" --log "$out/logs/$v.csv" --summary "$out/summary.csv" -q
done
build/analysis/popc-analyze report "$out"/logs/*.csv -o "$out/report"
build/analysis/popc-analyze compare "$out"/logs/*.csv --format markdown | tee "$out/compare.md"
echo "logs: $out/logs/, run summaries: $out/summary.csv, report: $out/report/index.html"
