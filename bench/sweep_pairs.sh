#!/bin/sh
# The sweep's own cost as paired differences, docs/BENCHMARKS.md section 6.
#
#   bench/sweep_pairs.sh SCENE SPEEDS PAIRS REFERENCE POPC...
#
# Each pair is one `POPC sweep SCENE -j 1 --no-log` of SPEEDS operator speeds
# times 5 controller variants on contact runs (bench/sweep_cost.sh says why
# those) and, right after it, one run of REFERENCE (bench/sweep_reference) on
# the same runs; every POPC given makes its own pair, one after the other, and
# the whole round is repeated PAIRS times. Prints, for each POPC, the first
# quartile, median and third quartile of its paired differences (ms of CPU,
# perf stat's task-clock of the whole process tree): "POPC q1 MS med MS q3 MS".
#
# Where bench/sweep_cost.sh takes the best of each program over its repeats,
# this takes each sweep against the reference run beside it, so that a slow
# spell of the machine shifts both sides of a pair alike; its median is the
# figure to quote on a machine whose noise between batches is as large as the
# difference sought.
set -eu
[ $# -ge 5 ] || { echo "usage: $0 SCENE SPEEDS PAIRS REFERENCE POPC..." >&2; exit 2; }
scene=$1 speeds=$2 pairs=$3 reference=$4
shift 4
# shellcheck source=bench/sweep_common.sh
. "$(dirname "$0")/sweep_common.sh"
r=0
while [ $r -lt "$pairs" ]; do
	r=$((r + 1))
	n=0
	for popc in "$@"; do
		n=$((n + 1))
		rm -rf "$out/sweep"
		# shellcheck disable=SC2086
		s=$(cpu "$popc" sweep "$scene" $vary $contact -o "$out/sweep" --no-log -j 1 -q)
		# shellcheck disable=SC2086
		b=$(cpu "$reference" "$scene" $contact $vary)
		echo "$n $s $b"
	done
done > "$out/pairs"
n=0
for popc in "$@"; do
	n=$((n + 1))
	awk -v n="$n" '$1 == n {print $2 - $3}' "$out/pairs" | sort -n |
		awk -v p="$popc" '{d[NR] = $1}
			END {printf "%s q1 %.3f med %.3f q3 %.3f\n", p, d[int(NR / 4) + 1],
			     d[int(NR / 2) + 1], d[int(3 * NR / 4) + 1]}'
done
