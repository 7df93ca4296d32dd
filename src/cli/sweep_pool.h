/* popc sweep's worker pool (sweep_pool.c): forked worker processes that make
 * the runs of a todo list in-process (popc_sweep_run_one), each appending to
 * a rows file of its own; with one job, the sweep's own process makes them
 * (sweep_crash.h). It never loses a run: every run it is given ends
 * with a row in some rows file (its result, or a failure naming why), or, when
 * the sweep is interrupted, with nothing, so that a resumed sweep runs it. */
#ifndef POPC_CLI_SWEEP_POOL_H
#define POPC_CLI_SWEEP_POOL_H

#include "popc/sweep/sweep_plan.h"
#include "sweep_progress.h"

typedef struct sweep_pool_config {
	const popc_sweep_plan *plan;
	const char *dir;              /* the sweep directory (prepared) */
	int keep_log;                 /* runs write DIR/runs/<id>/ (sweep_run.h) */
	int jobs;                     /* workers at most; 1: the runs in this process */
	int isolate;                  /* a worker process even for -j 1 (--isolate) */
	long rows_pid;                /* the pid in rows file names: 0 the process' own (test hook) */
	long long die_after_claim;    /* test hook: run index, -1 off */
	long long crash_at;           /* test hook: run index, -1 off */
	long long interrupt_after;    /* test hook: runs taken before ^C, -1 off */
} sweep_pool_config;

/* Test hooks (docs/SWEEPS.md, "Test hooks"), for tests that must make a rare
 * event happen; unset in normal use:
 *   POPC_SWEEP_TEST_ROWS_PID=N     name rows files after pid N instead of the
 *                                  process' own (a pid used again)
 *   POPC_SWEEP_TEST_DIE_AFTER_CLAIM=I  the worker that takes run I dies by
 *                                  SIGKILL before saying so in its slot
 *                                  (once per invocation)
 *   POPC_SWEEP_TEST_CRASH_AT=I     the process that makes run I calls abort()
 *                                  instead (every time: a run that crashes)
 *   POPC_SWEEP_TEST_INTERRUPT_AFTER=N  the process that makes runs sends the
 *                                  sweep SIGINT when it takes its run N + 1
 *                                  (N made before it; a map's rounds counted
 *                                  together)
 * Sets cfg's hook fields from the environment (left as they are when unset). */
void sweep_pool_test_hooks(sweep_pool_config *cfg);

/* Makes the runs todo[0 .. n_todo) (run indices of cfg->plan), counting them
 * in prog and showing it. Stops early, recording nothing more, when
 * popc_cli_stop is set (cli.h). Returns 0, or 1 when a row could not be
 * written or a worker could not be started (said on stderr). */
int sweep_pool_run(const sweep_pool_config *cfg, const long long *todo, long long n_todo,
		   sweep_progress *prog);

/* The workers of a sweep or a map without -j: SLURM_CPUS_PER_TASK when set
 * (1 to 4096), else the online processors. */
int sweep_pool_default_jobs(void);

/* The shard this invocation makes: --shard I/N when given (shard_text), else
 * Slurm's array task (SLURM_ARRAY_TASK_*), else 1/1. Negative with err set
 * when either is malformed. */
int sweep_pool_shard(const char *shard_text, popc_sweep_shard *shard, popc_error *err);

#endif
