# Sourced by bench/sweep_cost.sh and bench/sweep_pairs.sh after they have read
# SPEEDS into $speeds: the scratch directory, the CPU of one command, and the
# runs both measure.
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# CPU of the whole process tree (ms): perf stat's task-clock
cpu() { perf stat -x, -e task-clock "$@" 2>&1 >/dev/null | awk -F, '/task-clock/ {print $1}'; }
# $speeds operator speeds times the five controller variants
vary="--vary operator.speed=0.01:0.1:$speeds --vary controller.variant=none,ref-energy,ignore,hold,improved"
# contact runs: 21 ticks from inside the wall (bench/sweep_cost.sh says why)
contact="--set run.duration=0.02 --set operator.x0=0.005 --set operator.t0=0"
