/* The loop of a teleoperation scene (run_teleop.c); popc_run calls it for
 * teleop.architecture other than off. Private to the run layer. */
#ifndef POPC_RUN_TELEOP_H
#define POPC_RUN_TELEOP_H

#include "popc/run/run.h"

int popc_run_teleop(const popc_scene *s, popc_axis *master, const popc_run_options *opt,
		    popc_run_summary *sum, popc_error *err);

#endif
