/* The simulated axis: the scene's plant, operator intent and encoder, with the
 * stability guards of a fixed-step integrator (src/axes/sim_axis.c).
 *
 * Programs get it from popc_axis_create (axis.h) like any axis; this header
 * is for the code that needs the plant itself whatever the scene's
 * axis.kind says: the benchmarks, which time and replay it, and the drive
 * of popc-servo-sim, which puts it behind a register map. Besides the
 * mandatory operations it fills the optional integrator_error_m and
 * set_shadow (axis.h). */
#ifndef POPC_SIM_AXIS_H
#define POPC_SIM_AXIS_H

#include "popc/axes/axis.h"
#include "popc/util/error.h"
#include "popc/scene/scene.h"

/* Creates the simulated axis of the scene (any axis.kind); the caller frees
 * it with popc_axis_destroy. Returns 0 or a negative popc_status. */
int popc_sim_axis_create(popc_axis **out, const popc_scene *s, popc_error *err);
/* The simulated admittance-type device of the scene (sim_admittance_axis.c;
 * any axis.kind, any device.causality): force count and position in a
 * sample, a velocity command to exchange. For libpopc's admittance sim. */
int popc_sim_admittance_axis_create(popc_axis **out, const popc_scene *s, popc_error *err);
/* The simulated slave of a teleoperation scene (sim_slave_axis.c;
 * docs/TELEOPERATION.md): [slave]'s servoed device at rest at x0_m against
 * [environment]; force count, position and position command in a sample, a
 * velocity command to exchange. */
int popc_sim_slave_axis_create(popc_axis **out, const popc_scene *s, double x0_m, popc_error *err);

#endif
