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
 * sweep_pool.c), which the same command again makes again.
 *
 * -j N (N > 1) makes runs in the sweep's own process too, beside N - 1
 * workers (sweep_pool.c says why). A crash there ends those workers first
 * (SIGKILL, then waitpid, both async-signal-safe): a worker outlives an
 * execve of its parent (its parent-death signal fires on the parent's exit
 * only) and would go on writing rows into the directory the new popc
 * resumes. What a killed worker held and had not written is made again by
 * the new popc, as after any SIGKILL: nothing recorded is lost. */
#ifndef POPC_CLI_SWEEP_CRASH_H
#define POPC_CLI_SWEEP_CRASH_H

#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_plan.h"

#include <sys/types.h>

/* Arms the handlers of SIGSEGV, SIGBUS, SIGFPE, SIGILL and SIGABRT (on a
 * stack of their own: a run's stack overflow is a crash too). Returns 0, or
 * -1 when a crash could not be survived (no path of this program, no command
 * line kept): then the runs are made in a worker. */
int sweep_crash_arm(const popc_sweep_plan *p);

/* The batch of rows held in memory, written by the handler (NULL: none). */
void sweep_crash_hold(popc_sweep_rows_batch *rows);

/* The run being made (named by the handler), -1 between runs. */
void sweep_crash_in_hand(long long i);

/* The workers beside the runs of this process (pids[k] > 0: alive), which
 * the handler kills and reaps before it starts popc again; NULL, 0: none.
 * The array is read by the handler: its owner keeps it up to date. */
void sweep_crash_workers(volatile pid_t *pids, int n);

/* Puts back the handlers that were there before sweep_crash_arm. */
void sweep_crash_disarm(void);

#endif
