/* One run of a sweep, in this process (src/sweep/sweep_run.c). */
#ifndef POPC_SWEEP_RUN_H
#define POPC_SWEEP_RUN_H

#include <signal.h>

#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

typedef struct popc_sweep_result {
	int exit_status;          /* the run's exit code (popc/util/error.h) */
	int interrupted;          /* stopped by stop_flag: no summary written */
	int recorded;             /* the row is in the rows file, or held in the
				   * batch for it (even when the run's own
				   * summary.csv could not be written) */
	double wall_time_s;       /* scene, axis, run and log, without the summary */
	char reason[POPC_ERROR_MSG_MAX + 64]; /* why a failed run stopped; "" for one that succeeded */
} popc_sweep_result;

/* Runs run i of the plan on the simulated axis in this process and adds
 * its row to the rows batch (written with the batch; with keep_log, written
 * at once, with any rows held before it). With keep_log, DIR/runs/<id>/ gets the
 * resolved scene.ini, log.csv and then, once the row is recorded, a
 * summary.csv (header and row, renamed into place). A run stopped by
 * *stop_flag records nothing, so that a resumed sweep runs it again. Returns
 * 0 when the run was made and its result recorded (whatever the run's exit
 * status), or a negative popc_status when its row could not be written or,
 * with res->recorded set, when the row is recorded but the run's summary.csv
 * could not be written (err names it). */
int popc_sweep_run_one(const popc_sweep_plan *p, long long i, const char *dir, int keep_log,
		       popc_sweep_rows_batch *rows, volatile sig_atomic_t *stop_flag,
		       popc_sweep_result *res,
		       popc_error *err);

#endif
