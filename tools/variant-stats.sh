#!/bin/sh
# Every controller variant on the paper scene over N sub-count start offsets
# (operator.x0 + i delta / N, i = 0 .. N-1) and several durations, as one
# `popc sweep`, then `popc sweep stats` per variant and duration: the median
# and range (min, max) of the late-phase metrics. This is where the README's
# table of variants comes from (docs/TIMELINE.md, "Statistics").
#
# usage: tools/variant-stats.sh [-o DIR] [-n OFFSETS] [-d DURATIONS] [-f FORMAT] [-j JOBS]
#   -o DIR        the sweep directory (default variant-stats)
#   -n OFFSETS    sub-count offsets per variant and duration (default 20)
#   -d LIST       durations, s (default 5,20)
#   -f FORMAT     text, markdown or csv (popc sweep stats --format; default markdown)
#   -j JOBS       parallel runs (default 2)
#   SETS          extra 'k=v k=v' fixed for every run (environment)
#   SCENE         the scene (default data/scenes/paper.ini)
#   POPC          the program (default build/src/popc under the source tree)
# Every run uses controller.ignore_mode=undo. Cost: 7 variants x 20 offsets x
# (5 s + 20 s) is 3.5 million ticks, a few seconds of simulation; the process
# start of each of the 280 runs dominates (about 10 s on two cores). --no-log:
# the sweep keeps the summaries only.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
POPC=${POPC:-$root/build/src/popc}
SCENE=${SCENE:-$root/data/scenes/paper.ini}
SETS=${SETS:-}
dir=variant-stats
n=20
durations=5,20
format=markdown
jobs=2
while getopts o:n:d:f:j: opt; do
	case $opt in
	o) dir=$OPTARG ;;
	n) n=$OPTARG ;;
	d) durations=$OPTARG ;;
	f) format=$OPTARG ;;
	j) jobs=$OPTARG ;;
	*) sed -n '2,20p' "$0" >&2; exit 2 ;;
	esac
done
set --
for kv in $SETS; do set -- "$@" --set "$kv"; done
# the scene's own start position and encoder resolution (after SETS)
resolved=$("$POPC" scene show "$SCENE" --set controller.ignore_mode=undo "$@")
x0=$(echo "$resolved" | awk -F' = ' '/^\[/ { s = $0 } s == "[operator]" && $1 == "x0" { print $2 }')
delta=$(echo "$resolved" | awk -F' = ' '/^\[/ { s = $0 } s == "[encoder]" && $1 == "resolution" { print $2 }')
x0_list=$(awk -v x0="$x0" -v d="$delta" -v n="$n" \
	'BEGIN { for (i = 0; i < n; i++) printf "%s%.12g", i ? "," : "", x0 + i * d / n }')
"$POPC" sweep "$SCENE" --vary controller.variant=none,po-pc,ref-energy,filtered-velocity,ignore,hold,improved \
	--vary run.duration="$durations" --vary operator.x0="$x0_list" \
	--set controller.ignore_mode=undo "$@" --no-log -o "$dir" -j "$jobs" -q
"$POPC" sweep stats "$dir" --by controller.variant,run.duration --format "$format"
