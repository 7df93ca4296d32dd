#!/usr/bin/env bash
# popc bench as a user runs it: help and usage errors, the work-precision CSV
# (every integrator, the orders the theory gives), the loop and log benchmarks'
# shape, and the log recompute's bitwise check. Timings are printed, never
# asserted (shared machine); --min-time 0 --repeat 1 keeps this quick.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
T=$(mktemp -d /tmp/popc-bench-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

expect_exit 0 "bench --help" "$POPC" bench --help
check "  help names the three benchmarks" grep -q "integrators|loop|log" "$T/out"
expect_exit 2 "bench without what" "$POPC" bench
expect_exit 2 "bench of an unknown thing" "$POPC" bench everything
expect_exit 2 "bench with a bad format" "$POPC" bench loop --format xml
expect_exit 2 "bench with a bad repeat" "$POPC" bench loop --repeat 0
expect_exit 2 "bench with a bad scene key" "$POPC" bench loop --set run.rate=-1

expect_exit 0 "bench integrators, CSV" "$POPC" bench integrators --scene "$SRC/data/scenes/paper.ini" \
  --format csv --min-time 0 --repeat 1
cp "$T/out" "$T/wp.csv"
check "  CSV header" grep -qx "integrator,substeps,h_s,max_error_m,ns_per_step,status" "$T/wp.csv"
for m in exact trapezoid rk4 semi-implicit-euler euler; do
  check "  has $m" grep -q "^$m," "$T/wp.csv"
done
# measured order from the CSV: log2(error(n) / error(2n)) between n = 8 and 16
# for the first-order methods, 2 and 4 for the others (RK4 reaches the
# rounding floor by 8)
order() { awk -F, -v m="$1" -v n="$2" '$1 == m && $2 == n {a = $4} $1 == m && $2 == 2 * n {b = $4}
  END { if (a > 0 && b > 0) printf "%.2f", log(a / b) / log(2); else print "nan" }' "$T/wp.csv"; }
in_range() { awk -v x="$1" -v lo="$2" -v hi="$3" 'BEGIN { exit !(x >= lo && x <= hi) }'; }
# the theory: trapezoid 2, RK4 4, both Euler methods 1 (measured 2.00, 4.02, 1.00, 1.00)
check "  trapezoid converges at order 2 ($(order trapezoid 2))" in_range "$(order trapezoid 2)" 1.9 2.1
check "  rk4 converges at order 4 ($(order rk4 2))" in_range "$(order rk4 2)" 3.8 4.2
check "  semi-implicit-euler converges at order 1 ($(order semi-implicit-euler 8))" in_range "$(order semi-implicit-euler 8)" 0.9 1.1
check "  euler converges at order 1 ($(order euler 8))" in_range "$(order euler 8)" 0.9 1.1
# explicit Euler at 1 substep is stable for this damped plant (per step
# |1 + h lambda|^2 = 1 - h B/M + h^2 K/M = 1 - 1.5e-3 < 1): it completes with a
# first-order error, not garbage and not "unstable" (measured 1.24e-4 m, 12
# counts, halving at 2 substeps; it was stopped by an energy surplus summed
# since t = 0, which grew with the run's length)
check "  euler at 1 substep completes" grep -q "^euler,1,.*,ok$" "$T/wp.csv"
check "  euler converges at order 1 from 1 substep ($(order euler 1))" in_range "$(order euler 1)" 0.9 1.1
# the paper's scheme: trapezoid at 100 substeps, error of order 1e-11 m here (measured 1.93e-11)
tr100=$(awk -F, '$1 == "trapezoid" && $2 == 100 {print $4}' "$T/wp.csv")
check "  trapezoid x100 error $tr100 m in [1e-12, 1e-9]" in_range "$tr100" 1e-12 1e-9

# (what is checked here is the text and the plot, not the figures: a 1 s
# scene, a fifth of the work of the CSV run above)
expect_exit 0 "bench integrators, text and plot into a new directory" "$POPC" bench integrators --set run.duration=1 --min-time 0 --repeat 1 --plot "$T/fig/new"
check "  prints measured orders" grep -q "measured order" "$T/out"
check "  the gnuplot script" test -s "$T/fig/new/integrators.gp"
check "  the figure" test -s "$T/fig/new/integrators.png"
: > "$T/a-file"
# an unusable output named on the command line is bad usage before any work
# (exit 2; it was exit 1); a --plot that is a regular file passed mkdir
# (EEXIST) and failed after the half minute of measuring (issue 28)
expect_exit 2 "bench --plot where no directory can be made" "$POPC" bench integrators --plot "$T/a-file/x"
check "  says so before measuring" bash -c "grep -q 'popc bench: --plot $T/a-file/x: cannot create directory $T/a-file/x' '$T/err' && ! test -s '$T/out'"
expect_exit 2 "bench --plot onto a regular file" "$POPC" bench integrators --plot "$T/a-file"
check "  says so before measuring" bash -c "grep -qF 'popc bench: --plot $T/a-file: not a directory (the figure'\''s files go into a directory)' '$T/err' && ! test -s '$T/out'"
check "  the file is left as it was" test ! -s "$T/a-file"

expect_exit 0 "bench loop, CSV" "$POPC" bench loop --format csv --min-time 0 --repeat 1
check "  loop rows" grep -q "^loop_ns_per_tick," "$T/out"
check "  the loop against the chain, a number" grep -Eq "^loop_over_chain,[0-9.e+-]+,,$" "$T/out"
check "  exact's ticks per second" grep -q "^exact_ticks_per_s," "$T/out"
# the tick's dependency chain (src/cli/bench_floor.c) is timed only when its
# commands equal the real loop's bit for bit: for each variant it covers, on
# the wall and on the spring
for v in none po-pc ref-energy ignore hold improved; do
  for e in wall spring; do
    for m in literal undo; do
      expect_exit 0 "bench loop, chain of $v ($m) on a $e" "$POPC" bench loop --format csv --min-time 0 \
        --repeat 1 --set controller.variant=$v --set environment.kind=$e --set controller.ignore_mode=$m
      check "  its commands equal the loop's" grep -qx "chain_commands_equal,1,," "$T/out"
      check "  and it is timed" grep -Eq "^chain_floor_ns_per_tick,[0-9.e+-]+,[0-9.e+-]+,[0-9.e+-]+$" "$T/out"
    done
  done
done
# the loop beside `popc run SCENE -q` as a whole process (issue 23): its CPU
# per tick, its start-up and the ratio, printed with a verdict (never
# asserted: the figures are the machine's); the --set values reach the
# process (a scene it could not run would fail the benchmark)
expect_exit 0 "bench loop beside popc run as a process, CSV" "$POPC" bench loop --format csv \
  --min-time 0 --repeat 1 --scene "$SRC/data/scenes/paper.ini" --set run.duration=100
check "  the process's ns per tick, a number" grep -Eq "^process_ns_per_tick,[0-9.e+-]+,,$" "$T/out"
check "  its start-up, a number" grep -Eq "^process_startup_ms,[0-9.e+-]+,,$" "$T/out"
check "  the loop over the process, a number" grep -Eq "^loop_over_process,[0-9.e+-]+,,$" "$T/out"
expect_exit 0 "bench loop beside popc run as a process, text" "$POPC" bench loop --min-time 0 \
  --repeat 1 --scene "$SRC/data/scenes/paper.ini" --set run.duration=100
check "  names the process's figure" grep -q "^popc run -q as a process: [0-9.]* ns per tick over 100001 ticks" "$T/out"
check "  and says whether the two agree within 10 % or why not" \
  grep -Eq "they agree within 10 %|they differ by more than 10 %" "$T/out"
expect_exit 0 "bench loop of the built-in scene" "$POPC" bench loop --min-time 0 --repeat 1
check "  says why no process is timed" grep -q "popc run as a process: not measured (the built-in scene; give --scene FILE)" "$T/out"
expect_exit 0 "bench loop, a variant the chain does not cover" "$POPC" bench loop --min-time 0 \
  --repeat 1 --set controller.variant=filtered-velocity
check "  says why it is not measured" grep -q "not measured for this scene (every variant but filtered-velocity" "$T/out"

expect_exit 0 "bench log, CSV" "$POPC" bench log --format csv --rows 5000 --repeat 1 --dir "$T"
check "  recompute from the log is bitwise" grep -qx "recompute_bitwise,1,," "$T/out"
check "  leaves no scratch files" bash -c "! ls '$T'/popc-bench-* 2>/dev/null | grep -q ."

check_summary
