#!/bin/sh
# docs/figures/map-paper.png: the passive map of the seven variants on the
# paper's plant (docs/MAPS.md). Usage: tools/map-figure.sh [POPC] [DIR]
set -eu
POPC=${1:-build/src/popc}
DIR=${2:-/tmp/popc-map-paper}
"$POPC" map data/scenes/paper.ini \
  --variant none,po-pc,ref-energy,filtered-velocity,ignore,hold,improved \
  --vary environment.damping=0.01:1:16:log --set run.duration=2 \
  --stiffness 1e2:1e6 --tol 0.02 --criterion passive -o "$DIR" -j 2 -q
cp "$DIR/map.png" docs/figures/map-paper.png
