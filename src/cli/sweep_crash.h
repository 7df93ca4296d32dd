/* -j 1's runs in the sweep's own process, and a crash among them
 * (sweep_crash.c).
 *
 * popc sweep and popc map with -j 1 make their runs in their own process: a
 * worker's fork, copy-on-write faults and exit cost about 3 ms of CPU on the
 * VM of docs/BENCHMARKS.md section 6, 4 % of 300 paper-scene runs. What the
 * worker gave -j 1 is kept: a run that crashes (a fault, abort()) costs the
 * sweep that run only. The handler armed here writes the rows held so far
 * and starts popc again in the same process (execve, async-signal-safe: the
 * pid stays, so a shell or Slurm waiting for it waits for the rest) with the
 * same arguments and POPC_SWEEP_ISOLATE=1. That popc resumes the sweep with a
 * worker process, as --isolate: the run that crashed is made again there, and
 * when it crashes again it is recorded as failed and the sweep goes on.
 * SIGKILL alone loses the held rows (ROWS_HELD_MAX runs or a second of them,
 * sweep_pool.c), which the same command again makes again. */
#ifndef POPC_CLI_SWEEP_CRASH_H
#define POPC_CLI_SWEEP_CRASH_H

#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_plan.h"

/* Arms the handlers of SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT (on a
 * stack of their own: a run's stack overflow is a crash too). Returns 0, or
 * -1 when a crash could not be survived (no path of this program, no command
 * line kept): then the runs are made in a worker. */
int sweep_crash_arm(const popc_sweep_plan *p);

/* The batch of rows held in memory, written by the handler (NULL: none). */
void sweep_crash_hold(popc_sweep_rows_batch *rows);

/* The run being made (named by the handler), -1 between runs. */
void sweep_crash_in_hand(long long i);

/* Puts back the handlers that were there before sweep_crash_arm. */
void sweep_crash_disarm(void);

#endif
