#!/bin/sh
# The figures of docs/MAPS.md:
# - docs/figures/map-paper.png: the passive map of the seven variants on the
#   paper's plant (the VE port's energy, E_port);
# - docs/figures/map-zwidth-spring.png: the device-passive map of the seven
#   variants over the device's damping b on data/scenes/zwidth-spring.ini,
#   beside Colgate and Schenkel's line 2 b / T.
# Usage: tools/map-figure.sh [POPC] [DIR]
set -eu
POPC=${1:-build/src/popc}
DIR=${2:-/tmp/popc-map-paper}
VARIANTS=none,po-pc,ref-energy,filtered-velocity,ignore,hold,improved
"$POPC" map data/scenes/paper.ini --variant $VARIANTS \
  --vary environment.damping=0.01:1:16:log --set run.duration=2 \
  --stiffness 1e2:1e6 --tol 0.02 --criterion passive -o "$DIR" -j 2 -q
cp "$DIR/map.png" docs/figures/map-paper.png
"$POPC" map data/scenes/zwidth-spring.ini --variant $VARIANTS \
  --vary operator.damping=0.05:2:12:log \
  --stiffness 1e2:1e6 --tol 0.02 --criterion device-passive -o "$DIR-spring" -j 2 -q
cp "$DIR-spring/map.png" docs/figures/map-zwidth-spring.png
