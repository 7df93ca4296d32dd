/* The simulated axis: operator intent, plant and encoder of a scene (axis.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "popc/axis.h"
#include "popc/encoder.h"
#include "popc/intent.h"
#include "popc/log.h"
#include "popc/plant.h"

/* Positions beyond this are taken as divergence: the scene keys bound every
 * position to +-1e3 m, so a plant state past 1e6 m is no physics. */
#define DIVERGED_M 1e6

typedef struct sim_axis {
	popc_scene scene;
	popc_plant plant, exact;   /* exact: the reference the integrator is measured against */
	int shadow;                /* 1 when plant is not already exact */
	popc_intent intent;
	popc_plant_state st, st_exact;
	double period_s, delta_m, tol_s;
	long long k;               /* index of the current tick */
	double max_error_m;
	popc_intent_segment seg;   /* the intent segment of the current tick (fast path) */
} sim_axis;

static int sim_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	sim_axis *s = a->priv;
	int ok;
	out->count = popc_encoder_count(s->st.x_m, s->delta_m, &ok);
	out->x_true_m = s->st.x_m;
	out->dt_s = 0.0;
	out->rtt_s = 0.0;
	if (!ok || !isfinite(s->st.v_mps) || fabs(s->st.x_m) > DIVERGED_M) {
		const char *alt = s->scene.integrator == POPC_INTEGRATOR_EXACT
					  ? "a smaller run.duration or a physical scene"
					  : "integrator.method = exact (stable for any step)";
		return popc_error_set(
			err, POPC_ERR_NUMERIC,
			"the plant diverged at t = %g s (x = %g m): integrator %s with %d substeps, step "
			"h = %g s, is unstable for this scene; use %s or more substeps",
			(double)s->k * s->period_s, s->st.x_m, popc_integrator_name(s->scene.integrator),
			s->scene.substeps, s->period_s / s->scene.substeps, alt);
	}
	return 0;
}

/* Advances plant (and the exact shadow) over one control period with f_c held,
 * splitting the period at breakpoints of the operator's profile so that the
 * exact discretization stays exact. */
static void advance(sim_axis *s, popc_plant *p, popc_plant_state *st, double f_c)
{
	double t = (double)s->k * s->period_s, t_end = (double)(s->k + 1) * s->period_s;
	int whole = 1;
	for (;;) {
		popc_plant_input u;
		double next;
		popc_intent_input(&s->intent, t, &u, &next);
		u.u0_N -= f_c;
		if (next < t_end - s->tol_s && next > t + s->tol_s) {
			popc_plant_step_h(p, st, &u, next - t);
			t = next;
			whole = 0;
			continue;
		}
		if (whole)
			popc_plant_step(p, st, &u);
		else
			popc_plant_step_h(p, st, &u, t_end - t);
		return;
	}
}

/* The operator input for the whole period [t, t_end) from the cached intent
 * segment, when no breakpoint needs a split: then advance() would make one
 * popc_intent_input call and one full-period step with exactly this input.
 * Returns 0 when the period needs the general path. */
static int whole_period_input(sim_axis *s, double t, double t_end, popc_plant_input *u)
{
	popc_intent_segment *g = &s->seg;
	if (!(t >= g->t_lo_s && t < g->t_next_s && g->t_next_s >= t_end - s->tol_s)) {
		popc_intent_segment_at(&s->intent, t, g);
		if (!g->affine || !(g->t_next_s >= t_end - s->tol_s))
			return 0;
	}
	popc_intent_segment_input(g, t, u);
	return 1;
}

static int sim_exchange(popc_axis *a, double f_c_N, popc_axis_sample *next, popc_error *err)
{
	sim_axis *s = a->priv;
	if (!s->shadow && s->scene.integrator == POPC_INTEGRATOR_EXACT) {
		/* the hot path of a long exact run: no lookup, no call, no shadow */
		double t = (double)s->k * s->period_s, t_end = (double)(s->k + 1) * s->period_s;
		popc_plant_input u;
		if (whole_period_input(s, t, t_end, &u)) {
			u.u0_N -= f_c_N;
			popc_plant_step_exact(&s->plant.full, &s->st, &u);
		} else {
			advance(s, &s->plant, &s->st, f_c_N);
		}
		s->k++;
		return sim_sample(a, next, err);
	}
	advance(s, &s->plant, &s->st, f_c_N);
	if (s->shadow) {
		advance(s, &s->exact, &s->st_exact, f_c_N);
		double e = fabs(s->st.x_m - s->st_exact.x_m);
		if (e > s->max_error_m || isnan(e))
			s->max_error_m = e;
	}
	s->k++;
	return sim_sample(a, next, err);
}

static int sim_start(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

static int sim_stop(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

static void sim_destroy(popc_axis *a)
{
	sim_axis *s = a->priv;
	popc_intent_free(&s->intent);
	free(s);
	free(a);
}

static const popc_axis_ops sim_ops = {
	.name = "sim",
	.log_columns = POPC_LOG_COL_X_TRUE,
	.start = sim_start,
	.sample = sim_sample,
	.exchange = sim_exchange,
	.stop = sim_stop,
	.report = NULL,
	.destroy = sim_destroy,
};

int popc_sim_axis_create(popc_axis **out, const popc_scene *sc, popc_error *err)
{
	*out = NULL;
	popc_axis *a = calloc(1, sizeof *a);
	sim_axis *s = calloc(1, sizeof *s);
	if (!a || !s) {
		free(a);
		free(s);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	s->scene = *sc;
	s->period_s = popc_scene_period_s(sc);
	s->delta_m = sc->enc_resolution_m;
	/* breakpoints closer than this to a tick are taken as on the tick */
	s->tol_s = 1e-9 * s->period_s;
	popc_plant_config cfg;
	popc_plant_config_from_scene(&cfg, sc);
	int st = popc_plant_init(&s->plant, &cfg, err);
	if (!st && cfg.method != POPC_INTEGRATOR_EXACT) {
		s->shadow = 1;
		cfg.method = POPC_INTEGRATOR_EXACT;
		st = popc_plant_init(&s->exact, &cfg, err);
	}
	if (!st)
		st = popc_intent_init(&s->intent, sc, err);
	if (st) {
		popc_intent_free(&s->intent);
		free(s);
		free(a);
		return st;
	}
	s->st.x_m = popc_intent_x_initial(&s->intent);
	s->st_exact = s->st;
	s->seg.t_lo_s = s->seg.t_next_s = 0.0; /* empty: looked up on the first step */
	a->ops = &sim_ops;
	a->priv = s;
	*out = a;
	return 0;
}

double popc_sim_axis_max_error(const popc_axis *a)
{
	if (!a || a->ops != &sim_ops)
		return 0.0;
	return ((const sim_axis *)a->priv)->max_error_m;
}

void popc_axis_destroy(popc_axis **a)
{
	if (a && *a) {
		(*a)->ops->destroy(*a);
		*a = NULL;
	}
}
