/* Adapters from the scene (popc/scene/scene.h) to the core modules'
 * configurations: the only place where scene keys meet the numerics, so that
 * a change of the scene format never reaches the controller or the plant. */
#ifndef POPC_SCENE_FROM_SCENE_H
#define POPC_SCENE_FROM_SCENE_H

#include <stddef.h>

#include "popc/core/admittance.h"
#include "popc/core/admittance_plant.h"
#include "popc/core/channel.h"
#include "popc/core/controller.h"
#include "popc/core/environment.h"
#include "popc/core/intent.h"
#include "popc/core/plant.h"
#include "popc/scene/delay_trace.h"
#include "popc/scene/scene.h"
#include "popc/util/error.h"

void popc_plant_config_from_scene(popc_plant_config *cfg, const popc_scene *s);
void popc_environment_from_scene(popc_environment *e, const popc_scene *s);
void popc_controller_config_from_scene(popc_controller_config *c, const popc_scene *s);
/* Admittance causality (docs/ADMITTANCE.md): the controller (its VE's wall or
 * spring is the [environment]) and the device with its servo; x_origin_m is
 * the plant's coordinate origin (the device's initial position). */
void popc_admittance_config_from_scene(popc_admittance_config *c, const popc_scene *s);
/* A teleoperation scene's slave device (docs/TELEOPERATION.md): [slave]'s
 * mass, damping and servo; no hand (the environment's force is the plant's
 * input, held over the period). */
void popc_teleop_slave_plant_config_from_scene(popc_admittance_plant_config *c,
					       const popc_scene *s, double x_origin_m);
/* One direction of a teleoperation scene's channel, [forward] or [backward]. */
void popc_channel_config_from_scene(popc_channel_config *c, const popc_scene_channel *dir);
/* The same, its delays in seconds converted and its trace read into *trace
 * (delay_trace.h; free it with popc_delay_trace_free after
 * popc_channel_init, which copies it). */
int popc_channel_config_load(popc_channel_config *c, const popc_scene *s,
			     const popc_scene_channel *dir, const char *name, popc_delay_trace *trace,
			     popc_error *err);
void popc_admittance_plant_config_from_scene(popc_admittance_plant_config *c, const popc_scene *s,
					     double x_origin_m);

/* popc_plant_init (and popc_admittance_plant_init, which calls it) names the
 * plant's own parameters, popc_plant_config's mass_kg, damping_Nspm,
 * stiffness_Npm, period_s, coulomb_N, stiction_N: this names in err's message
 * the scene keys that s sums into each (mass_kg: "(operator.mass +
 * device.mass)"; an admittance device's servo gains included), so the user
 * reads the keys to change. */
void popc_plant_name_keys(const popc_scene *s, popc_error *err);

/* A table intent's points, owned (free with popc_intent_points_free). */
typedef struct popc_intent_points {
	size_t n;
	double *t_s, *q;
} popc_intent_points;

/* Reads a table intent's CSV file of "t,value" rows. A table that cannot be
 * opened or read, or holds a bad row (not two finite numbers, times not
 * increasing, a value outside the range of the scene key it stands for, rows
 * too close in time for their change), is POPC_ERR_INVALID naming file:line
 * and column. k_op and b_op (K_HO, B_HO) check that the operator's input
 * between rows stays finite. */
int popc_intent_table_load(const char *path, popc_table_quantity quantity, double k_op_Npm,
			   double b_op_Nspm, popc_intent_points *out, popc_error *err);
void popc_intent_points_free(popc_intent_points *p);

/* Builds the intent of scene s; a table intent reads its file here
 * (popc_intent_table_load). Free with popc_intent_free. Positions travel as
 * integer counts in doubles (encoder.h): a scene whose reach (below), over
 * encoder.resolution, exceeds 2^53 counts is refused here, naming the keys,
 * before anything runs (popc_scene_validate checks the position keys alone;
 * the table and the force are known here). */
int popc_intent_from_scene(popc_intent *in, const popc_scene *s, popc_error *err);

/* The farthest a run of scene s with intent in may go before the simulated
 * axis calls it diverged: 10 x the largest position the scene names + 1 m,
 * where the largest position is the largest of |operator.x0|,
 * |environment.position|, the ramp's end or the sine's crest, a position
 * table's largest |value|, and for a force (intent or table) the static
 * equilibrium (K_HO |x0| + the largest |f|) / (K_HO + K_HI) on the springs
 * (or on a bilateral environment spring). A force with no spring to hold it
 * has no bound: INFINITY. why (may be NULL) gets what the bound is made of,
 * for messages. */
double popc_scene_reach_m(const popc_scene *s, const popc_intent *in, char *why, size_t cap);

#endif
