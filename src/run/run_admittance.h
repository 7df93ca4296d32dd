/* The loop of an admittance scene (run_admittance.c); popc_run calls it for
 * device.causality = admittance. Private to the run layer. */
#ifndef POPC_RUN_ADMITTANCE_H
#define POPC_RUN_ADMITTANCE_H

#include "popc/run/run.h"

int popc_run_admittance(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
			popc_run_summary *sum, popc_error *err);

/* The stop line's reason for an axis' failure to bring a sample, the same
 * for the first sample as for every exchange after it, in both loops
 * (docs/MODBUS.md, "Exit codes": each exit code's stop lines). */
const char *popc_run_sample_failure(int st);

#endif
