#!/bin/sh
# The sweep's own cost, docs/BENCHMARKS.md section 6.
#
#   bench/sweep_cost.sh SCENE SPEEDS REPEATS REFERENCE POPC...
#
# CPU (perf stat's task-clock, ms, of the whole process tree: a sweep's
# workers included) of `POPC sweep SCENE -j 1 --no-log` over SPEEDS operator
# speeds times 5 controller variants, for each POPC given (e.g. a build
# before a change and one after), and of REFERENCE (bench/sweep_reference:
# the same runs in one process, nothing else) on the same runs. Each on three
# kinds of runs:
#   full     the scene as it is (the paper scene: 5001 ticks)
#   contact  21 ticks from inside the wall (x0 = 5 mm, t0 = 0): summaries with
#            every metric set, as full runs have, at a hundredth of the work
#   2tick    2 ticks (run.duration = 0.001): summaries of zeros
# Whole processes alternate (every program, then the next repeat); prints the
# best of REPEATS for each program and kind: "PROGRAM KIND MS".
#
# The sweep's own cost is CPU(sweep, contact) - CPU(reference, contact): the
# runs' ticks cancel, what the sweep does per run and once stays (start-up
# and dynamic loading cancel too: both programs are linked alike). The runs'
# own CPU is CPU(reference, full) - CPU(reference, contact).
set -eu
[ $# -ge 5 ] || { echo "usage: $0 SCENE SPEEDS REPEATS REFERENCE POPC..." >&2; exit 2; }
scene=$1 speeds=$2 repeats=$3 reference=$4
shift 4
# shellcheck source=bench/sweep_common.sh
. "$(dirname "$0")/sweep_common.sh"
sets() {
	case $1 in
	full) echo "" ;;
	contact) echo "$contact" ;;
	2tick) echo "--set run.duration=0.001" ;;
	esac
}
r=0
while [ $r -lt "$repeats" ]; do
	r=$((r + 1))
	for kind in full contact 2tick; do
		n=0
		for popc in "$@"; do
			n=$((n + 1))
			rm -rf "$out/sweep"
			# shellcheck disable=SC2046,SC2086
			echo "popc$n:$popc $kind $(cpu "$popc" sweep "$scene" $vary $(sets $kind) \
				-o "$out/sweep" --no-log -j 1 -q)"
		done
		# shellcheck disable=SC2046,SC2086
		echo "reference $kind $(cpu "$reference" "$scene" $(sets $kind) $vary)"
	done
done | awk '{k = $1 " " $2; if (!(k in b) || $3 + 0 < b[k]) b[k] = $3 + 0}
	END {for (k in b) print k, b[k]}' | sort
