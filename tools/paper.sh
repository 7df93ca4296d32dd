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
mkdir -p "$out"
for v in none po-pc ref-energy filtered-velocity ignore hold improved; do
  build/src/popc run data/scenes/paper.ini --variant "$v" --log "$out/$v.csv" --summary "$out/summary.csv" -q
done
echo "logs: $out/*.csv, run summaries: $out/summary.csv"
if [ -x build/analysis/popc-analyze ]; then
  build/analysis/popc-analyze report "$out"/*.csv -o "$out/report"
  build/analysis/popc-analyze compare "$out"/*.csv --format markdown | tee "$out/compare.md"
  echo "report: $out/report/index.html"
fi
