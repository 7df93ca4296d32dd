/* The loop of a teleoperation scene (run_teleop.c); popc_run calls it for
 * teleop.architecture other than off. Private to the run layer. */
#ifndef POPC_RUN_TELEOP_H
#define POPC_RUN_TELEOP_H

#include "popc/run/run.h"

/* axis: the program's axis of the scene (popc_axis_create). With axis.kind
 * = sim it is the master, and the runner makes the simulated slave
 * (sim_slave_axis.c); with axis.kind = modbus it is the slave, an
 * admittance-type drive, and the runner makes the simulated master
 * (sim_axis.c). Either way the loop sees two axes behind one interface. */
int popc_run_teleop(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
		    popc_run_summary *sum, popc_error *err);

/* 1 when the program's axis is a teleoperation scene's slave (an
 * admittance-type axis: POPC_LOG_COL_ADMITTANCE in its log_columns), 0 when
 * it is the master. */
int popc_run_teleop_axis_is_slave(const popc_axis *axis);

#endif
