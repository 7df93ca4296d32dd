/* The loop of an admittance scene (run_admittance.c); popc_run calls it for
 * device.causality = admittance. Private to the run layer. */
#ifndef POPC_RUN_ADMITTANCE_H
#define POPC_RUN_ADMITTANCE_H

#include "popc/run/run.h"

int popc_run_admittance(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
			popc_run_summary *sum, popc_error *err);

#endif
