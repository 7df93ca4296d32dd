#!/usr/bin/env bash
# popc's tick beside a JIT doing the same work (issue 23; docs/BENCHMARKS.md,
# "The tick beside a JIT"): whole processes, alternated, CPU time.
#
#   bench/tick_vs_jit.sh BUILD_DIR [DURATION_S [ROUNDS]]   (defaults 3600 and 3)
#
# Each round runs, one after the other:
#   popc run paper.ini --set run.duration=D -q                 (asks for nothing)
#   popc run paper.ini --set run.duration=D -q --summary FILE  (the summary: the
#                                       metrics, E_port and E_dev, the work the
#                                       reference does)
#   bench/tick_jit.py: the numba reference of the same ticks (its loop's
#                                       CPU time; its compilation, on two ticks
#                                       first, is printed apart, not counted)
# then once `popc bench loop --format csv` for the tick's dependency chain
# (src/cli/bench_floor.c, the flat probe of the minimal arithmetic).
# Prints each round's figures, the fastest of each and their ratios. The
# figures are the machine's: nothing is judged, and the script fails only
# when a command fails. Without numba (Debian: python3-numba) the reference
# is left out and said so.
set -euo pipefail
BUILD=${1:?usage: bench/tick_vs_jit.sh BUILD_DIR [DURATION_S [ROUNDS]]}
D=${2:-3600}
ROUNDS=${3:-3}
SRC=$(cd "$(dirname "$0")/.." && pwd)
POPC=$BUILD/src/popc
JC=$BUILD/bench/jit_constants
SCENE=$SRC/data/scenes/paper.ini
T=$(mktemp -d /tmp/popc-tickjit-XXXXXX)
trap 'rm -rf "$T"' EXIT

PY=
for p in python3 /usr/bin/python3; do
  "$p" -c 'import numba' 2>/dev/null && { PY=$p; break; }
done

# cpu_of CMD...: the command's user + system CPU seconds (bash's time)
cpu_of() {
  local TIMEFORMAT='%3U %3S' out
  out=$( { time "$@" >/dev/null; } 2>&1 ) || { echo "failed: $*" >&2; echo "$out" >&2; return 1; }
  echo "$out" | tail -1 | awk '{printf "%.3f", $1 + $2}'
}

ticks=$(awk -v d="$D" 'BEGIN { printf "%d", d * 1000 + 1 }') # paper.ini: 1 kHz
echo "tick_vs_jit: paper.ini, run.duration = $D s ($ticks ticks), $ROUNDS rounds, CPU time"
echo "load: $(uptime | sed 's/.*load average/load average/')"
best_q=inf best_s=inf best_j=inf
for r in $(seq 1 "$ROUNDS"); do
  q=$(cpu_of "$POPC" run "$SCENE" --set run.duration="$D" -q)
  rm -f "$T/sum.csv"
  s=$(cpu_of "$POPC" run "$SCENE" --set run.duration="$D" -q --summary "$T/sum.csv")
  j=nan
  if [ -n "$PY" ]; then
    "$PY" "$SRC/bench/tick_jit.py" "$JC" "$SCENE" --set run.duration="$D" > "$T/jit.txt"
    j=$(awk '$1 == "cpu_s" {print $2}' "$T/jit.txt")
    c=$(awk '$1 == "compile_s" {print $2}' "$T/jit.txt")
  fi
  echo "round $r: popc -q $q s, popc --summary $s s, numba loop $j s${PY:+ (compile $c s, not counted)}"
  best_q=$(awk -v a="$best_q" -v b="$q" 'BEGIN { print (b < a || a == "inf") ? b : a }')
  best_s=$(awk -v a="$best_s" -v b="$s" 'BEGIN { print (b < a || a == "inf") ? b : a }')
  [ "$j" = nan ] || best_j=$(awk -v a="$best_j" -v b="$j" 'BEGIN { print (b < a || a == "inf") ? b : a }')
done
"$POPC" bench loop --scene "$SCENE" --set run.duration="$D" --format csv --repeat "$ROUNDS" > "$T/loop.csv"
chain=$(awk -F, '$1 == "chain_floor_ns_per_tick" {print $2}' "$T/loop.csv")
loop=$(awk -F, '$1 == "loop_ns_per_tick" {print $2}' "$T/loop.csv")
proc=$(awk -F, '$1 == "process_ns_per_tick" {print $2}' "$T/loop.csv")
startup=$(awk -F, '$1 == "process_startup_ms" {print $2}' "$T/loop.csv")
ns() { awk -v s="$1" -v n="$ticks" 'BEGIN { printf "%.2f", 1e9 * s / n }'; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0 && a > 0) printf "%.2f", a / b; else print "nan" }'; }
q_ns=$(ns "$best_q") s_ns=$(ns "$best_s")
echo "fastest, ns per tick: popc run -q $q_ns, popc run --summary $s_ns," \
  "numba $( [ "$best_j" = inf ] && echo "not run (no numba: Debian python3-numba)" || ns "$best_j")," \
  "chain (bench loop's floor) $chain"
if [ "$best_j" != inf ]; then
  j_ns=$(ns "$best_j")
  echo "popc run -q / numba: $(ratio "$q_ns" "$j_ns")"
  echo "popc run --summary / numba (the same work): $(ratio "$s_ns" "$j_ns")"
fi
echo "popc run -q / chain: $(ratio "$q_ns" "$chain")"
# the process's start-up (loading, the scene, the matrices: a run of one
# period, timed by bench loop) in the fastest popc run -q of this duration
echo "popc's start-up: $startup ms, $(awk -v s="$startup" -v q="$best_q" \
  'BEGIN { printf "%.0f", (q > 0 ? 100 * s / 1e3 / q : 0) }') % of popc run -q at $D s" \
  "(the reference's figure has none: its loop alone)"
echo "bench loop: loop $loop ns, popc run -q as a process $proc ns (its own alternation)"
