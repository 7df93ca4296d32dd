/* How both loops end (run.c for impedance, run_admittance.c for admittance
 * causality): the stop line's reasons and the safe stop on every way out.
 * Private to the run layer. */
#ifndef POPC_RUN_STOP_H
#define POPC_RUN_STOP_H

#include "popc/run/run.h"

/* The stop line's reason for an axis' failure to bring a sample, the same
 * for the first sample as for every exchange after it (docs/MODBUS.md,
 * "Exit codes": each exit code's stop lines). */
const char *popc_run_sample_failure(int st);

/* Every way out of a loop: the axis' safe stop first, then the summary's
 * times, status and stop reason (why, and err's message when st != 0), then
 * the log's stop line and flush. An unconfirmed safe stop (the drive may
 * still be enabled) is never success: after a completed run it is the stop
 * reason and its status the exit code (communication: 4); after a failed one
 * the run's reason stays and the stop line says it as well. t0_s is when the
 * loop started (popc_now_s), ticks in sum already counted. Returns the run's
 * final status. */
int popc_run_finish(popc_axis *axis, popc_log_writer *log, popc_run_summary *sum, int st,
		    const char *why, double t0_s, double period_s, popc_error *err);

#endif
