/* The simulated axis: operator intent, plant and encoder of a scene (axis.h). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
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

/* A fixed-step integrator is stopped as unstable when its position error
 * against the exact shadow exceeds this many times (the exact trajectory's
 * range so far + one encoder count). A stable integrator's error stays below
 * the range of the motion (at worst a phase error: |x - x_exact| <= 2 x the
 * amplitude); an unstable one grows geometrically, so the factor only decides
 * how early it is caught, never whether a stable run is stopped. */
#define ERROR_BOUND_FACTOR 10.0

/* Energy growth bound. The plant is linear and a fixed-step integrator is a
 * fixed linear map per control period, so its free (unforced) motion grows by
 * exactly rho^k in amplitude after k periods, rho its spectral radius; the
 * exact plant is passive (B, K >= 0: its rho <= 1). An integrator with
 * rho > 1 amplifies every truncation and rounding error without bound; popc
 * lets it run while that growth stays below GROWTH_MAX in amplitude
 * (GROWTH_MAX^2 = 100 in energy) and stops the run before the period that
 * would cross it. RHO_MARGIN absorbs the rounding of rho itself (rho of an
 * undamped exact plant computes as 1 +- a few ulps). */
#define GROWTH_MAX 10.0
#define RHO_MARGIN 1e-12

/* Energy balance. For M x'' = u - B x' - K x the plant's energy
 * E = M v^2 / 2 + K x^2 / 2 obeys dE/dt = u v - B v^2 <= u v: it can never
 * exceed E(0) plus the work of its inputs (the operator's pull and -f_c).
 * A fixed-step integrator's surplus, C = E(k) - E(0) - sum of the input work
 * (midpoint rule per period, u(t + T/2) (x(k+1) - x(k)), exact for an input
 * held over the period), is energy the integrator made up. The run stops
 * when C exceeds ENERGY_SURPLUS_MAX times the largest energy the plant held
 * (plus one count's worth): then the motion is made up, not simulated. This
 * catches the closed-loop case the shadow cannot: the exact shadow gets the
 * same commands, so an integrator whose garbage drives the PC drags its
 * shadow with it. A passive plant, a trapezoid (energy-conserving) and RK4
 * (dissipative) keep C <= 0 up to rounding and the work estimate's error;
 * semi-implicit Euler's energy error stays bounded by its modified energy. */
#define ENERGY_SURPLUS_MAX 1.0

typedef struct sim_axis {
	popc_scene scene;
	popc_plant plant, exact;   /* exact: the reference the integrator is measured against */
	int shadow;                /* 1 when plant is not already exact */
	popc_intent intent;
	popc_plant_state st, st_exact;
	double period_s, delta_m, tol_s;
	long long k;               /* index of the current tick */
	double max_error_m;
	double x_exact_min_m, x_exact_max_m; /* range of the exact trajectory so far */
	double rho;                /* integrator's free-motion growth per period (1 if exact) */
	double energy_J, energy_peak_J, surplus_J, energy_floor_J; /* energy balance */
	long long k_unstable;      /* first tick whose growth rho^k passes GROWTH_MAX */
	popc_intent_segment seg;   /* the intent segment of the current tick (fast path) */
} sim_axis;

/* Spectral radius of a real 2 x 2 matrix: the growth factor of its free motion. */
static double spectral_radius(double a, double b, double c, double d)
{
	double half_tr = 0.5 * (a + d), det = a * d - b * c, disc = half_tr * half_tr - det;
	if (disc < 0.0)
		return sqrt(det); /* complex pair: |lambda|^2 = det */
	double r = sqrt(disc);
	return fmax(fabs(half_tr + r), fabs(half_tr - r));
}

/* Growth factor per control period of the free (unforced) plant as the
 * configured integrator steps it with n substeps: the spectral radius of its
 * one-period transition matrix, built column by column from unit states. */
static double amplification(const popc_plant_config *cfg0, int n)
{
	popc_plant_config cfg = *cfg0;
	cfg.substeps = n;
	popc_plant p;
	if (popc_plant_init(&p, &cfg, NULL) != 0)
		return NAN;
	popc_plant_input zero = {0.0, 0.0, 0.0, 0.0};
	popc_plant_state c0 = {1.0, 0.0}, c1 = {0.0, 1.0};
	popc_plant_step(&p, &c0, &zero);
	popc_plant_step(&p, &c1, &zero);
	return spectral_radius(c0.x_m, c1.x_m, c0.v_mps, c1.v_mps);
}

/* The error for an integrator that left the exact trajectory: names the
 * integrator, its step, whether it is unstable for this plant (growth factor
 * against the exact one) and a stable alternative. */
static int integrator_failed(const sim_axis *s, const char *what, popc_error *err)
{
	popc_plant_config cfg = s->plant.cfg;
	const char *name = popc_integrator_name(cfg.method);
	int n = cfg.substeps;
	const double (*phi)[2] = s->exact.full.phi;
	double rho_exact = spectral_radius(phi[0][0], phi[0][1], phi[1][0], phi[1][1]);
	double limit = fmax(1.0, rho_exact) * (1.0 + RHO_MARGIN);
	double rho = s->rho;
	char verdict[160], alt[200];
	if (rho > limit)
		snprintf(verdict, sizeof verdict,
			 "is unstable for this plant: it amplifies free motion by %.6g per period, "
			 "the exact plant by %.6g",
			 rho, rho_exact);
	else
		snprintf(verdict, sizeof verdict, "is stable but too inaccurate for this scene");
	int n_ok = 0;
	for (long m = 2L * n; m <= 1000000L && !n_ok; m *= 2)
		if (amplification(&cfg, (int)m) <= limit)
			n_ok = (int)m;
	if (rho > limit && n_ok)
		snprintf(alt, sizeof alt, "integrator.method = exact (stable for any step), or "
			 "integrator.substeps >= %d", n_ok);
	else if (rho > limit)
		snprintf(alt, sizeof alt, "integrator.method = exact (stable for any step); no substep "
			 "count up to 1e6 makes %s stable here", name);
	else
		snprintf(alt, sizeof alt, "integrator.method = exact (stable for any step), or more "
			 "substeps");
	return popc_error_set(err, POPC_ERR_NUMERIC,
			      "%s at t = %.9g s (tick %lld): integrator %s with %d substeps, step h = "
			      "%g s, %s; use %s",
			      what, (double)s->k * s->period_s, s->k, name, n, s->period_s / n,
			      verdict, alt);
}

static int sim_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	sim_axis *s = a->priv;
	int ok;
	out->count = popc_encoder_count(s->st.x_m, s->delta_m, &ok);
	out->x_true_m = s->st.x_m;
	out->dt_s = 0.0;
	out->rtt_s = 0.0;
	if (!ok || !isfinite(s->st.v_mps) || fabs(s->st.x_m) > DIVERGED_M) {
		char what[96];
		snprintf(what, sizeof what, "the plant diverged (x = %g m, v = %g m/s)", s->st.x_m,
			 s->st.v_mps);
		/* an integrator that diverges together with its exact shadow (fed the
		 * same commands) only follows the physics */
		int with_shadow = s->shadow && isfinite(s->st.x_m) &&
				  fabs(s->st.x_m - s->st_exact.x_m) < 0.5 * fabs(s->st.x_m);
		if (s->scene.integrator != POPC_INTEGRATOR_EXACT && !with_shadow)
			return integrator_failed(s, what, err);
		return popc_error_set(
			err, POPC_ERR_NUMERIC,
			"%s at t = %.9g s (tick %lld) %s: the closed loop of this scene is unstable "
			"(the physics, not the integrator); add damping, lower the wall stiffness or "
			"raise the control rate (a sampled wall is passive for b > K_e T / 2), or use a "
			"PC variant",
			what, (double)s->k * s->period_s, s->k,
			s->scene.integrator == POPC_INTEGRATOR_EXACT
				? "with the exact integrator, which is exact for any step"
				: "and so does the exact integrator fed the same commands");
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
	if (s->k + 1 >= s->k_unstable) {
		/* stop before computing a state past the growth bound */
		char what[160];
		double g = pow(s->rho, (double)(s->k + 1));
		snprintf(what, sizeof what,
			 "energy growth beyond the bound: its free motion would grow %.3g x in "
			 "amplitude (%.3g x in energy; the bound is %g x)",
			 g, g * g, GROWTH_MAX);
		return integrator_failed(s, what, err);
	}
	double x_before = s->st.x_m;
	advance(s, &s->plant, &s->st, f_c_N);
	{
		/* energy balance (ENERGY_SURPLUS_MAX) */
		const popc_plant_config *c = &s->plant.cfg;
		popc_plant_input um;
		double nb, t_mid = ((double)s->k + 0.5) * s->period_s;
		popc_intent_input(&s->intent, t_mid, &um, &nb);
		double work = (um.u0_N + um.uc_N - f_c_N) * (s->st.x_m - x_before);
		double e = 0.5 * c->mass_kg * s->st.v_mps * s->st.v_mps +
			   0.5 * c->stiffness_Npm * s->st.x_m * s->st.x_m;
		s->surplus_J += (e - s->energy_J) - work;
		s->energy_J = e;
		s->energy_peak_J = fmax(s->energy_peak_J, e);
		double bound = ENERGY_SURPLUS_MAX * (s->energy_peak_J + s->energy_floor_J);
		if (s->surplus_J > bound && isfinite(s->surplus_J)) {
			s->k++;
			char what[200];
			snprintf(what, sizeof what,
				 "energy growth beyond the bound: it made up %.3g J that no input "
				 "supplied, more than %g x the most energy the plant held (%.3g J)",
				 s->surplus_J, ENERGY_SURPLUS_MAX, s->energy_peak_J);
			return integrator_failed(s, what, err);
		}
	}
	if (s->shadow) {
		advance(s, &s->exact, &s->st_exact, f_c_N);
		double x_ex = s->st_exact.x_m, e = fabs(s->st.x_m - x_ex);
		if (e > s->max_error_m || isnan(e))
			s->max_error_m = e;
		s->x_exact_min_m = fmin(s->x_exact_min_m, x_ex);
		s->x_exact_max_m = fmax(s->x_exact_max_m, x_ex);
		double bound = ERROR_BOUND_FACTOR * (s->x_exact_max_m - s->x_exact_min_m + s->delta_m);
		if (e > bound && isfinite(e)) {
			s->k++;
			char what[160];
			snprintf(what, sizeof what,
				 "the position error %.3g m against the exact discretization passed %.3g "
				 "m (%g x the exact motion's range + 1 count)",
				 e, bound, ERROR_BOUND_FACTOR);
			return integrator_failed(s, what, err);
		}
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
	s->rho = 1.0;
	s->k_unstable = LLONG_MAX;
	if (!st && cfg.method != POPC_INTEGRATOR_EXACT) {
		s->rho = amplification(&cfg, cfg.substeps);
		if (s->rho > 1.0 + RHO_MARGIN) {
			double k = ceil(log(GROWTH_MAX) / log(s->rho));
			s->k_unstable = k < 1.0 ? 1 : k < 1e18 ? (long long)k : LLONG_MAX;
		}
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
	s->x_exact_min_m = s->x_exact_max_m = s->st.x_m;
	s->energy_J = s->energy_peak_J =
		0.5 * cfg.stiffness_Npm * s->st.x_m * s->st.x_m; /* at rest */
	/* one encoder count of the spring plus one count per period of motion */
	s->energy_floor_J = 0.5 * cfg.stiffness_Npm * s->delta_m * s->delta_m +
			    0.5 * cfg.mass_kg * (s->delta_m / s->period_s) * (s->delta_m / s->period_s);
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
	const sim_axis *s = a->priv;
	if (s->scene.integrator != POPC_INTEGRATOR_EXACT && !s->shadow)
		return NAN;
	return s->max_error_m;
}

void popc_sim_axis_set_shadow(popc_axis *a, int on)
{
	if (!a || a->ops != &sim_ops)
		return;
	sim_axis *s = a->priv;
	if (s->scene.integrator != POPC_INTEGRATOR_EXACT)
		s->shadow = on != 0;
}

void popc_axis_destroy(popc_axis **a)
{
	if (a && *a) {
		(*a)->ops->destroy(*a);
		*a = NULL;
	}
}
