/* libpopc: the simulated devices (impedance- and admittance-type), the
 * environment and encoder alone, and a whole run (popc/popc.h), over the
 * axes layer's simulated axes and popc_run: the calls popc run makes
 * (src/cli/cmd_run.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lib_private.h"
#include "popc/axes/sim_axis.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/log/log.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"

POPC_API int popc_lib_sim_create(const popc_lib_scene *s, popc_lib_sim **out,
				 popc_lib_sample *first, popc_lib_error *err)
{
	return popc_lib_sim_create_options(s, 0, out, first, err);
}

POPC_API int popc_lib_sim_create_options(const popc_lib_scene *s, unsigned options,
					 popc_lib_sim **out, popc_lib_sample *first,
					 popc_lib_error *err)
{
	*out = NULL;
	int st = popc_lib_scene_validate(s, err);
	if (st)
		return st;
	if (s->scene.causality != POPC_CAUSALITY_IMPEDANCE)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_create: the scene's device.causality is "
					  "admittance; allowed: impedance (an admittance device: "
					  "popc_lib_sim_create_admittance)");
	if (options & ~(unsigned)POPC_LIB_SIM_NO_PORT_ENERGY)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_create_options: unknown option bits; allowed: "
					  "0 or POPC_LIB_SIM_NO_PORT_ENERGY (1)");
	popc_lib_sim *sim = calloc(1, sizeof *sim);
	if (!sim)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM, "popc_lib_sim_create: out of memory");
	sim->port_energy = !(options & POPC_LIB_SIM_NO_PORT_ENERGY);
	popc_error e;
	popc_axis_sample smp;
	smp.dissipated_J = (double)NAN;
	st = popc_sim_axis_create(&sim->axis, &s->scene, &e);
	if (!st)
		st = sim->axis->ops->start(sim->axis, &e);
	if (!st)
		st = sim->axis->ops->sample(sim->axis, &smp, &e);
	if (st) {
		popc_axis_destroy(&sim->axis);
		free(sim);
		return popc_lib_fail(err, st, &e);
	}
	popc_port_energy_init(&sim->port);
	popc_lib_sample_out(sim, &smp, first);
	*out = sim;
	return 0;
}

POPC_API int popc_lib_sim_exchange(popc_lib_sim *sim, double f_c_N, popc_lib_sample *next,
				   popc_lib_error *err)
{
	/* a non-finite command never reaches the plant: it would integrate to
	 * NaN and read as a diverged closed loop */
	if (!isfinite(f_c_N))
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_exchange: f_c_N is not finite (NaN or inf); "
					  "the device is left as it was");
	if (sim->admittance)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_exchange: the device is admittance-type; "
					  "use popc_lib_sim_exchange_admittance");
	return popc_lib_sim_exchange_impedance(sim, f_c_N, next, err);
}

static void adm_sample_out(const popc_axis_sample *in, popc_lib_admittance_sample *out)
{
	out->count = in->count;
	out->force_count = in->force_count;
	out->x_true_m = in->x_true_m;
	out->x_cmd_m = in->x_cmd_m;
}

POPC_API int popc_lib_sim_create_admittance(const popc_lib_scene *s, popc_lib_sim **out,
					    popc_lib_admittance_sample *first, popc_lib_error *err)
{
	*out = NULL;
	int st = popc_lib_scene_validate(s, err);
	if (st)
		return st;
	if (s->scene.causality != POPC_CAUSALITY_ADMITTANCE)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_create_admittance: the scene's device.causality "
					  "is impedance; allowed: admittance");
	popc_lib_sim *sim = calloc(1, sizeof *sim);
	if (!sim)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM,
					  "popc_lib_sim_create_admittance: out of memory");
	sim->admittance = 1;
	popc_error e;
	popc_axis_sample smp;
	memset(&smp, 0, sizeof smp);
	st = popc_sim_admittance_axis_create(&sim->axis, &s->scene, &e);
	if (!st)
		st = sim->axis->ops->start(sim->axis, &e);
	if (!st)
		st = sim->axis->ops->sample(sim->axis, &smp, &e);
	if (st) {
		popc_axis_destroy(&sim->axis);
		free(sim);
		return popc_lib_fail(err, st, &e);
	}
	adm_sample_out(&smp, first);
	*out = sim;
	return 0;
}

POPC_API int popc_lib_sim_exchange_admittance(popc_lib_sim *sim, double v_c_mps,
					      popc_lib_admittance_sample *next, popc_lib_error *err)
{
	if (!sim->admittance)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_exchange_admittance: the device is "
					  "impedance-type; use popc_lib_sim_exchange");
	/* a non-finite command never reaches the servo (as popc_lib_sim_exchange) */
	if (!isfinite(v_c_mps))
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_exchange_admittance: v_c_mps is not finite (NaN "
					  "or inf); the device is left as it was");
	popc_error e;
	popc_axis_sample smp;
	memset(&smp, 0, sizeof smp);
	int st = sim->axis->ops->exchange(sim->axis, v_c_mps, &smp, &e);
	if (st)
		return popc_lib_fail(err, st, &e);
	adm_sample_out(&smp, next);
	return 0;
}

POPC_API void popc_lib_sim_free(popc_lib_sim *sim)
{
	if (!sim)
		return;
	popc_error e;
	sim->axis->ops->stop(sim->axis, &e); /* a simulated axis stops without fail */
	popc_axis_destroy(&sim->axis);
	free(sim);
}

POPC_API double popc_lib_environment_force(const popc_lib_scene *s, double x_m, double v_mps)
{
	popc_environment env;
	popc_environment_from_scene(&env, &s->scene);
	return popc_environment_force(&env, x_m, v_mps);
}

POPC_API long long popc_lib_encoder_count(const popc_lib_scene *s, double x_m, int *ok)
{
	int ok_ = 0;
	long long c = popc_encoder_count(x_m, s->scene.enc_resolution_m, &ok_);
	if (ok)
		*ok = ok_;
	return c;
}

POPC_API int popc_lib_run(const popc_lib_scene *s, const char *log_path, popc_lib_error *err)
{
	int st = popc_lib_scene_validate(s, err);
	if (st)
		return st;
	popc_error e;
	popc_axis *axis = NULL;
	popc_axis_create_options opt = {0};
	st = popc_axis_create(&axis, &s->scene, &opt, &e);
	if (st)
		return popc_lib_fail(err, st, &e);
	popc_log_writer log;
	if (log_path) {
		st = popc_log_open(&log, log_path, popc_run_log_columns(&s->scene, axis), &e);
		if (!st && (st = popc_log_write_header(&log, axis->ops->name, &s->scene, NULL, &e)) != 0) {
			popc_error ce;
			popc_log_close(&log, &ce);
		}
		if (st) {
			popc_axis_destroy(&axis);
			return popc_lib_fail(err, st, &e);
		}
	}
	popc_run_options ro = {.log = log_path ? &log : NULL};
	popc_run_summary *sum = malloc(sizeof *sum);
	if (!sum)
		st = popc_error_set(&e, POPC_ERR_NOMEM, "popc_lib_run: out of memory");
	else
		st = popc_run(&s->scene, axis, &ro, sum, &e);
	free(sum);
	if (log_path) {
		popc_error ce;
		int cst = popc_log_close(&log, &ce);
		if (cst && !st) {
			st = cst;
			e = ce;
		}
	}
	popc_axis_destroy(&axis);
	return popc_lib_fail(err, st, &e);
}
