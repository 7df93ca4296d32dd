/* The simulated admittance-type device (docs/ADMITTANCE.md): operator intent,
 * the device with its position or velocity servo (admittance_plant.h), the
 * encoder and the force sensor. The command of exchange() is the velocity
 * v_c(k), held over the period; the servo's position command follows it,
 * x_c(k+1) = x_c(k) + v_c(k) T. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "axis_kind.h"
#include "popc/axes/sim_axis.h"
#include "popc/core/admittance.h"
#include "popc/core/admittance_plant.h"
#include "popc/core/encoder.h"
#include "popc/core/intent.h"
#include "popc/log/log_columns.h"
#include "popc/scene/from_scene.h"

/* the device is called diverged beyond the scene's reach (sim_axis.c's rule,
 * at most this far) */
#define ADM_DIVERGED_MAX_M 1e6

typedef struct adm_axis {
	popc_admittance_plant plant;
	popc_intent intent;
	popc_force_sensor sensor;
	popc_plant_state st;       /* y = x - x0, v */
	double x0_m;               /* the device's initial position, the plant's origin */
	double x_cmd_m;            /* the position command at the current tick */
	double period_s, delta_m, tol_s, diverged_m;
	long long k;               /* index of the current tick */
	int exact;                 /* the exact method: adm_exchange's fast path */
	popc_intent_segment seg;   /* the intent segment of the current tick (fast path) */
} adm_axis;

static int adm_start(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

/* The sample of the current tick: the count and the force the sensor reads
 * (f_s from the hand's input and the command of the period that ended: the
 * left limit at the tick). */
static int fill_sample(adm_axis *s, const popc_plant_input *hand, const popc_plant_input *u,
		       double tau_s, popc_axis_sample *out, popc_error *err)
{
	const double x = s->x0_m + s->st.x_m;
	if (!isfinite(x) || !isfinite(s->st.v_mps))
		return popc_error_set(err, POPC_ERR_NUMERIC,
				      "admittance device: the state is not finite at t = %g s",
				      (double)s->k * s->period_s);
	if (!(fabs(x) <= s->diverged_m))
		return popc_error_set(err, POPC_ERR_DIVERGED,
				      "admittance device: x = %g m at t = %g s, beyond %g m",
				      x, (double)s->k * s->period_s, s->diverged_m);
	int ok = 1;
	out->count = popc_encoder_count(x, s->delta_m, &ok);
	const double f = popc_admittance_plant_sensed_N(&s->plant, &s->st, hand, u, tau_s);
	if (!ok || !isfinite(f))
		return popc_error_set(err, POPC_ERR_NUMERIC,
				      "admittance device: x = %g m or sensed force %g N out of range at "
				      "t = %g s",
				      x, f, (double)s->k * s->period_s);
	out->force_count = popc_force_sensor_read(&s->sensor, f);
	out->x_true_m = x;
	out->x_cmd_m = s->x_cmd_m;
	out->dissipated_J = (double)NAN;
	out->dt_s = 0.0;
	out->rtt_s = 0.0;
	return 0;
}

static int adm_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	adm_axis *s = a->priv;
	popc_plant_input hand, u;
	double next;
	popc_intent_input(&s->intent, 0.0, &hand, &next);
	/* before tick 0 the servo holds x0 at rest */
	popc_admittance_plant_input(&s->plant, &hand, s->x_cmd_m, 0.0, 0.0, &u);
	return fill_sample(s, &hand, &u, 0.0, out, err);
}

/* One period with v_c held, split at the intent's breakpoints as the
 * impedance axis splits it (sim_axis.c, advance): exact on each part. */
static int adm_exchange(popc_axis *a, double v_c_mps, popc_axis_sample *next_out, popc_error *err)
{
	adm_axis *s = a->priv;
	const double tk = (double)s->k * s->period_s, t_end = (double)(s->k + 1) * s->period_s;
	double t = tk;
	popc_plant_input hand, u;
	/* the hot path (sim_axis.c's): no breakpoint in the period, the exact
	 * step inline */
	if (s->exact && popc_intent_period_input(&s->intent, &s->seg, tk, t_end, s->tol_s, &hand)) {
		popc_admittance_plant_input(&s->plant, &hand, s->x_cmd_m, v_c_mps, 0.0, &u);
		popc_plant_step_exact(&s->plant.plant.full, &s->st, &u);
		s->k++;
		s->x_cmd_m += v_c_mps * s->period_s;
		return fill_sample(s, &hand, &u, s->period_s, next_out, err);
	}
	int whole = 1;
	for (;;) {
		double next;
		popc_intent_input(&s->intent, t, &hand, &next);
		popc_admittance_plant_input(&s->plant, &hand, s->x_cmd_m, v_c_mps, t - tk, &u);
		if (next < t_end - s->tol_s && next > t) {
			if (popc_plant_step_h(&s->plant.plant, &s->st, &u, next - t) != 0)
				return popc_error_set(err, POPC_ERR_NUMERIC,
						      "admittance device: no finite step of %g s at t = %g s",
						      next - t, t);
			t = next;
			whole = 0;
			continue;
		}
		if (whole)
			popc_plant_step(&s->plant.plant, &s->st, &u);
		else if (popc_plant_step_h(&s->plant.plant, &s->st, &u, t_end - t) != 0)
			return popc_error_set(err, POPC_ERR_NUMERIC,
					      "admittance device: no finite step of %g s at t = %g s",
					      t_end - t, t);
		break;
	}
	s->k++;
	/* the command of the next tick starts where this one's ramp ended */
	s->x_cmd_m += v_c_mps * s->period_s;
	return fill_sample(s, &hand, &u, whole ? s->period_s : t_end - t, next_out, err);
}

static int adm_stop(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

static void adm_destroy(popc_axis *a)
{
	adm_axis *s = a->priv;
	popc_intent_free(&s->intent);
	free(s);
	free(a);
}

static const popc_axis_ops adm_ops = {
	.name = "sim",
	.log_columns = POPC_LOG_COL_ADMITTANCE,
	.start = adm_start,
	.sample = adm_sample,
	.exchange = adm_exchange,
	.stop = adm_stop,
	.destroy = adm_destroy,
};

int popc_sim_admittance_axis_create(popc_axis **out, const popc_scene *sc, popc_error *err)
{
	*out = NULL;
	popc_axis *a = calloc(1, sizeof *a);
	adm_axis *s = calloc(1, sizeof *s);
	if (!a || !s) {
		free(a);
		free(s);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	int st = popc_intent_from_scene(&s->intent, sc, err);
	if (st) {
		free(s);
		free(a);
		return st;
	}
	s->period_s = popc_scene_period_s(sc);
	s->delta_m = sc->enc_resolution_m;
	s->tol_s = POPC_INTENT_TICK_TOL_PERIODS * s->period_s;
	s->diverged_m = fmin(popc_scene_reach_m(sc, &s->intent, NULL, 0), ADM_DIVERGED_MAX_M);
	/* at rest where the hand wants it, the servo holding it there */
	s->x0_m = popc_intent_x_initial(&s->intent);
	s->x_cmd_m = s->x0_m;
	popc_admittance_plant_config pc;
	popc_admittance_plant_config_from_scene(&pc, sc, s->x0_m);
	st = popc_admittance_plant_init(&s->plant, &pc, err);
	if (st) {
		popc_plant_name_keys(sc, err); /* the plant's parameters as the scene's keys */
		popc_intent_free(&s->intent);
		free(s);
		free(a);
		return st;
	}
	s->exact = pc.method == POPC_INTEGRATOR_EXACT;
	s->seg.t_lo_s = s->seg.t_next_s = 0.0; /* empty: looked up on the first step */
	popc_force_sensor_init(&s->sensor, sc->adm_force_resolution_N, sc->adm_force_noise_N,
			       (uint64_t)sc->adm_force_noise_seed);
	a->ops = &adm_ops;
	a->priv = s;
	*out = a;
	return 0;
}
