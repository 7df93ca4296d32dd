/* How both loops end (run_stop.h). */
#include "run_stop.h"

#include <stdio.h>
#include <string.h>

#include "popc/util/clock.h"

const char *popc_run_sample_failure(int st)
{
	return st == POPC_ERR_NUMERIC       ? "integrator unstable"
	       : st == POPC_ERR_DIVERGED    ? "closed loop diverged"
	       : st == POPC_ERR_SAFETY      ? "safety stop"
	       : st == POPC_ERR_COMM        ? "communication lost"
	       : st == POPC_ERR_INTERRUPTED ? "signal" /* seen by the axis mid-transaction */
					    : "axis error";
}

int popc_run_finish(popc_axis *axis, popc_log_writer *log, popc_run_summary *sum, int st,
		    const char *why, double t0_s, double period_s, popc_error *err)
{
	/* safe state first, then the log */
	popc_error stop_err;
	int stop_st = axis->ops->stop(axis, &stop_err);
	int stop_is_reason = stop_st && !st;
	if (stop_is_reason) {
		st = stop_st;
		why = "safe stop incomplete";
		if (err)
			*err = stop_err;
	}
	sum->wall_time_s = popc_now_s() - t0_s;
	sum->sim_time_s = sum->ticks > 0 ? (double)(sum->ticks - 1) * period_s : 0.0;
	sum->status = st;
	if (st && err)
		snprintf(sum->stop_reason, sizeof sum->stop_reason, "%s: %s", why, err->msg);
	else
		snprintf(sum->stop_reason, sizeof sum->stop_reason, "%s", why);
	if (stop_st && !stop_is_reason) {
		size_t used = strlen(sum->stop_reason);
		snprintf(sum->stop_reason + used, sizeof sum->stop_reason - used,
			 "; safe stop incomplete: %s", stop_err.msg);
	}
	if (log) {
		popc_error lerr;
		int lst = popc_log_write_comment(log, "stop", sum->stop_reason, &lerr);
		if (!lst)
			lst = popc_log_flush(log, &lerr);
		if (lst && !st) {
			st = lst;
			if (err)
				*err = lerr;
		}
	}
	return st;
}
