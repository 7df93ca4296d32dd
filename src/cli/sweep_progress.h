/* popc sweep's progress display (sweep_progress.c): a bar redrawn on a
 * terminal, else a plain line at every tenth of the way; failed runs named as
 * they happen on plain lines. */
#ifndef POPC_CLI_SWEEP_PROGRESS_H
#define POPC_CLI_SWEEP_PROGRESS_H

#include "popc/sweep/sweep_plan.h"
#include "progress.h"

typedef struct sweep_progress {
	int quiet, tty;
	/* a map's runs: a probe past the edge diverges (exit 6), a verdict the
	 * search asked for, labelled as expected, not as a failure */
	int map;
	long long total, done;         /* done includes runs finished before (resumed) */
	long long done_now, failed_now; /* runs made by this invocation, failed among them */
	double t_start;
	int last_decile;
	long long last_done;   /* done at the last plain line */
	cli_progress line;     /* the bar on a terminal (progress.h) */
} sweep_progress;

/* Starts the clock: total runs of the shard, done_before of them finished by
 * an earlier invocation. Draws a bar when stderr is a terminal. */
void sweep_progress_start(sweep_progress *p, int quiet, long long total, long long done_before);

/* Shows the counts (final: the last time, a bar ends its line). */
void sweep_progress_show(sweep_progress *p, int final);

/* Seconds since sweep_progress_start. */
double sweep_progress_elapsed_s(const sweep_progress *p);

/* A failed run, as it happens (plain lines only: on a terminal the bar counts
 * failures and the list at the end names them). One write(), so that lines of
 * different workers do not mix. */
void sweep_progress_failure(const sweep_progress *p, const popc_sweep_plan *plan, long long i,
			    int exit_status, const char *reason);

#endif
