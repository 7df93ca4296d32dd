/* The simulated axis: operator intent, plant and encoder of a scene (sim_axis.h). */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/axes/sim_axis.h"
#include "axis_kind.h"
#include "popc/core/encoder.h"
#include "popc/core/intent.h"
#include "popc/log/log.h"
#include "popc/core/plant.h"
#include "popc/core/plant_dissipation.h"
#include "popc/scene/from_scene.h"

/* Divergence bound: a position beyond 10 x the largest position the scene
 * names (operator.x0, operator.x_end, x0 + amplitude, environment.position,
 * a position table's values, the static equilibrium under a force input) plus
 * 1 m is no physics. The operator's pull and the wall keep a passive loop
 * within the scene's positions plus an oscillation of the same order (a ramp
 * into an undamped spring overshoots by at most 2 V / w); a loop whose
 * physics diverges passes the bound long before its numbers turn to garbage.
 * A force input without any restoring spring can legitimately run away: then
 * only DIVERGED_MAX_M applies (the scene keys bound positions to +-1e3 m). */
#define DIVERGED_FACTOR 10.0
#define DIVERGED_MARGIN_M 1.0
#define DIVERGED_MAX_M 1e6

/* A fixed-step integrator is stopped as unstable when its position error
 * against the exact shadow exceeds this many times (the exact trajectory's
 * range so far + one encoder count). A stable integrator's error stays below
 * the range of the motion (at worst a phase error: |x - x_exact| <= 2 x the
 * amplitude); an unstable one grows geometrically, so the factor only decides
 * how early it is caught, never whether a stable run is stopped. */
#define ERROR_BOUND_FACTOR 10.0

/* Growth bound. The plant is linear and a fixed-step integrator is a fixed
 * linear map per substep, so its free (unforced) motion grows by exactly
 * rho^k in amplitude after k periods, rho = rho_1^n the spectral radius of the
 * one-substep matrix to the power of the n substeps (computed as n ln rho_1:
 * the product of n matrices overflows long before ln rho does); the exact
 * plant is passive (B, K >= 0: its rho <= 1). An integrator with rho > 1
 * amplifies every truncation and rounding error without bound; popc lets it
 * run while that growth stays below GROWTH_MAX in amplitude (GROWTH_MAX^2 =
 * 100 in energy) and stops the run before the period that would cross it.
 * RHO_MARGIN absorbs the rounding of rho itself (rho of an undamped exact
 * plant computes as 1 +- a few ulps), and RHO_ULPS per substep that of
 * n ln rho_1 (rho_1 = 1 +- a few ulps becomes n times that: semi-implicit
 * Euler on an undamped plant, rho_1 = 1 exactly in theory, would otherwise
 * count as growing at 1e6 substeps). */
#define GROWTH_MAX 10.0
#define RHO_MARGIN 1e-12
#define RHO_ULPS 8.0

/* Energy growth. For M x'' = u - B x' - K x the plant's energy
 * E = M v^2 / 2 + K x^2 / 2 obeys dE/dt = u v - B v^2 <= u v: it can never
 * gain more than the work of its inputs (the operator's pull and -f_c). The
 * surplus of a stretch of ticks, C = E(end) - E(start) - sum of the input work
 * (midpoint rule per period, u(t + T/2) (x(k+1) - x(k)), exact for an input
 * held over the period), is energy the integrator made up. This catches the
 * closed-loop case the shadow cannot: the exact shadow gets the same commands,
 * so an integrator whose garbage drives the wall and the PC drags its shadow
 * along (both energies grow together; explicit Euler on an undamped hand grows
 * 2 x in energy every ~1500 ticks in contact while |x - x_exact| stays ~1 %).
 *
 * What is judged is growth, not a sum since t = 0: the surplus made up over
 * the last ENERGY_WINDOW_BLOCKS - 1 to ENERGY_WINDOW_BLOCKS blocks of
 * ENERGY_BLOCK_TICKS ticks against the most energy the plant held in the
 * same length of time before that window (plus one count's worth). Crossing
 * it means the plant more than doubled its energy within the window from
 * energy no input supplied: geometric growth of doubling time D is caught as
 * soon as the window is longer than D (2^(W/D) - 1 > 1); slower growth is
 * left to the growth bound above. A sum since t = 0 instead grows linearly
 * with the run's length even for an accurate integrator: the bookkeeping
 * multiplies the chattering PC force (+-5 N every tick) by position errors of
 * 1e-8 m, a bias of 1e-7 J a tick, so explicit Euler x 100 on the paper scene
 * (max error 1.2e-6 m, 0.12 counts) was stopped at t = 27.6 s of a 600 s run.
 * The same bias makes the windowed surplus of accurate runs exceed their
 * small contact energy too (measured: 1.9 x for Euler x 100, 24 x for x 8),
 * so the guard applies only where growth is possible and visible:
 *   - the integrator amplifies free motion for this plant (rho above the
 *     exact plant's): with rho <= 1 a fixed linear map cannot create energy
 *     over a window beyond its bias, and a closed loop that diverges anyway is
 *     caught by the error bound (the integrator leaves the shadow) or by the
 *     divergence bound (it is the physics: the shadow diverges too);
 *   - and, with the exact shadow on, the position error against it has passed
 *     one encoder count: below that, the integrator's run is the exact run as
 *     far as the controller can see, whatever the bookkeeping says.
 * So a run with rho < 1, or with an error below one count, is never stopped
 * as unstable by this guard. */
#define ENERGY_SURPLUS_MAX 1.0
#define ENERGY_BLOCK_TICKS 500
#define ENERGY_WINDOW_BLOCKS 4
#define ENERGY_RING (2 * ENERGY_WINDOW_BLOCKS)

typedef struct energy_block {
	double surplus_start_J;    /* C since t = 0 at the block's first tick */
	double peak_J;             /* most energy held in the block */
} energy_block;

typedef struct sim_axis {
	popc_scene scene;
	popc_plant plant, exact;   /* exact: the reference the integrator is measured against */
	int shadow;                /* 1 when plant is not already exact */
	int exact_linear;          /* exact method without friction: sim_exchange's fast path */
	/* The damping's dissipation over a whole period (plant_dissipation.h),
	 * for exact_linear plants: the true trajectory is then the exact one.
	 * dissipated_J: over the last period (NaN when the axis cannot say). */
	popc_plant_dissipation diss;
	int has_diss;              /* diss holds a finite form */
	double dissipated_J;
	popc_intent intent;
	/* The plant integrates y = x - x_rest, the displacement from its initial
	 * rest position, with the input u - K x_rest (the same linear equation
	 * in y): a hand held at rest then stays exactly at y = 0, where
	 * stepping x itself drifts by an ulp or two per period (Phi x + Gam K x
	 * rounds), enough to cross a count boundary that x_rest sits on and log
	 * a spurious one-count velocity. x_true = x_rest + y. */
	popc_plant_state st, st_exact;
	double x_rest_m, k_x_rest_N; /* the origin, and K x_rest */
	double period_s, delta_m, tol_s;
	double diverged_m;         /* divergence bound of this scene (DIVERGED_FACTOR) */
	long long k;               /* index of the current tick */
	double max_error_m;
	double x_exact_min_m, x_exact_max_m; /* range of the exact trajectory so far */
	double log_rho;            /* ln of the free-motion growth per period (0 if exact; inf: overflow) */
	double log_rho_exact;      /* ln of the exact plant's growth per period */
	double log_rho_limit;      /* ln of max(1, exact growth) x (1 + RHO_MARGIN) */
	double energy_J, energy_peak_J, surplus_J, energy_floor_J; /* energy balance */
	energy_block blocks[ENERGY_RING]; /* per block of ENERGY_BLOCK_TICKS, by block index mod ring */
	long long k_unstable;      /* first tick whose growth rho^k passes GROWTH_MAX */
	popc_intent_segment seg;   /* the intent segment of the current tick (fast path) */
} sim_axis;

/* Spectral radius of a real 2 x 2 matrix: the growth factor of its free
 * motion. Scaled by its largest entry first, so that entries near the
 * overflow threshold still give a finite radius (or +inf, never NaN, for a
 * matrix with a non-finite entry). */
static double spectral_radius(double a, double b, double c, double d)
{
	if (!isfinite(a) || !isfinite(b) || !isfinite(c) || !isfinite(d))
		return HUGE_VAL;
	double sc = fmax(fmax(fabs(a), fabs(b)), fmax(fabs(c), fabs(d)));
	if (sc == 0.0)
		return 0.0;
	a /= sc;
	b /= sc;
	c /= sc;
	d /= sc;
	double half_tr = 0.5 * (a + d), det = a * d - b * c, disc = half_tr * half_tr - det;
	if (disc < 0.0)
		return sc * sqrt(det); /* complex pair: |lambda|^2 = det */
	double r = sqrt(disc);
	return sc * fmax(fabs(half_tr + r), fabs(half_tr - r));
}

/* ln of the growth factor per control period of the free (unforced) plant as
 * the configured integrator steps it with n substeps: n ln rho_1, rho_1 the
 * spectral radius of the one-substep transition matrix (built column by
 * column from unit states), since rho(M^n) = rho(M)^n. +inf when that matrix
 * overflows or cannot be built: unstable, never NaN. */
static double log_amplification(const popc_plant_config *cfg0, int n)
{
	popc_plant_config cfg = *cfg0;
	cfg.substeps = 1;
	cfg.period_s = cfg0->period_s / n;
	/* the linear part: friction only dissipates (and is not a linear map) */
	cfg.coulomb_N = cfg.stiction_N = 0.0;
	popc_plant p;
	if (popc_plant_init(&p, &cfg, NULL) != 0)
		return HUGE_VAL;
	popc_plant_input zero = {0.0, 0.0, 0.0, 0.0};
	popc_plant_state c0 = {1.0, 0.0}, c1 = {0.0, 1.0};
	popc_plant_step(&p, &c0, &zero);
	popc_plant_step(&p, &c1, &zero);
	double rho1 = spectral_radius(c0.x_m, c1.x_m, c0.v_mps, c1.v_mps);
	if (!(rho1 < HUGE_VAL))
		return HUGE_VAL;
	if (rho1 == 0.0)
		return -HUGE_VAL;
	return (double)n * log(rho1);
}

/* Whether ln rho over n substeps is growth beyond the exact plant's ln rho
 * limit and the rounding of rho (NaN and inf: yes). */
static int amplifies(double log_rho, double log_limit, int n)
{
	return !(log_rho <= log_limit + (double)n * RHO_ULPS * DBL_EPSILON);
}

/* rho = e^log_rho for a message: "%.6g" of it, or "e^%.6g" past overflow. */
static void format_growth(double log_rho, char *buf, size_t cap)
{
	if (log_rho < 700.0)
		snprintf(buf, cap, "%.6g", exp(log_rho));
	else if (log_rho < HUGE_VAL)
		snprintf(buf, cap, "e^%.6g", log_rho);
	else
		snprintf(buf, cap, "more than 1e308 (its one-substep matrix overflows)");
}

/* The error for an integrator that left the exact trajectory: names the
 * integrator, its step, whether it is unstable for this plant (growth factor
 * against the exact one) and a stable alternative. */
static int integrator_failed(const sim_axis *s, const char *what, popc_error *err)
{
	popc_plant_config cfg = s->plant.cfg;
	const char *name = popc_integrator_name(cfg.method);
	int n = cfg.substeps;
	int unstable = amplifies(s->log_rho, s->log_rho_limit, n);
	char verdict[320], alt[200], rho_txt[64], rho_ex_txt[64];
	format_growth(s->log_rho, rho_txt, sizeof rho_txt);
	format_growth(s->log_rho_exact, rho_ex_txt, sizeof rho_ex_txt);
	if (unstable)
		snprintf(verdict, sizeof verdict,
			 "is unstable for this plant: it amplifies free motion by %s per period, "
			 "the exact plant by %s",
			 rho_txt, rho_ex_txt);
	else
		snprintf(verdict, sizeof verdict, "is stable but too inaccurate for this scene");
	int n_ok = 0;
	for (long m = 2L * n; m <= 1000000L && !n_ok; m *= 2)
		if (!amplifies(log_amplification(&cfg, (int)m), s->log_rho_limit, (int)m))
			n_ok = (int)m;
	if (unstable && n_ok)
		snprintf(alt, sizeof alt, "integrator.method = exact (stable for any step), or "
			 "integrator.substeps >= %d", n_ok);
	else if (unstable)
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

POPC_FLOOR_CLONES
static int sim_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	sim_axis *s = a->priv;
	int ok;
	const double x_m = s->x_rest_m + s->st.x_m;
	out->count = popc_encoder_count(x_m, s->delta_m, &ok);
	out->x_true_m = x_m;
	out->dissipated_J = s->dissipated_J;
	out->dt_s = 0.0;
	out->rtt_s = 0.0;
	if (!isfinite(x_m) || !isfinite(s->st.v_mps) || fabs(x_m) > s->diverged_m) {
		char what[200];
		snprintf(what, sizeof what,
			 "the plant diverged (x = %g m, v = %g m/s; the bound is %g m, %g x the scene's "
			 "largest position + %g m)",
			 x_m, s->st.v_mps, s->diverged_m, DIVERGED_FACTOR, DIVERGED_MARGIN_M);
		/* an integrator that diverges together with its exact shadow (fed the
		 * same commands) only follows the physics */
		int with_shadow = s->shadow && isfinite(s->st.x_m) &&
				  fabs(s->st.x_m - s->st_exact.x_m) < 0.5 * fabs(x_m);
		if (s->scene.integrator != POPC_INTEGRATOR_EXACT && !with_shadow)
			return integrator_failed(s, what, err);
		char pc_note[96] = ", or use a PC variant";
		if (s->scene.variant != POPC_VARIANT_NONE)
			snprintf(pc_note, sizeof pc_note,
				 "; the PC, bounded at controller.pc_bound = %g N, did not keep it passive",
				 s->scene.pc_bound_N);
		/* Colgate and Schenkel's b > K T / 2, each period of loop delay
		 * adding K T (docs/ANALYSIS.md, "Loop delay moves the passivity
		 * boundary") */
		char passive[96] = "b > K_e T / 2";
		if (s->scene.delay_ticks > 0)
			snprintf(passive, sizeof passive, "b > K_e T (1/2 + d), d = run.delay_ticks = %d",
				 s->scene.delay_ticks);
		return popc_error_set(
			err, POPC_ERR_DIVERGED,
			"%s at t = %.9g s (tick %lld) %s: the closed loop of this scene diverged (the "
			"physics, not the integrator); add damping, lower the wall stiffness or "
			"raise the control rate (a sampled wall is passive for %s)%s",
			what, (double)s->k * s->period_s, s->k,
			s->scene.integrator == POPC_INTEGRATOR_EXACT
				? "with the exact integrator, which is exact for any step"
				: "and so does the exact integrator fed the same commands",
			passive, pc_note);
	}
	/* only a force with no spring to hold it gets here (every bounded
	 * scene's reach is within 2^53 counts: popc_intent_from_scene): a run
	 * that went unbounded, numeric failure (exit 6), not bad input */
	if (!ok)
		return popc_error_set(err, POPC_ERR_DIVERGED,
				      "encoder count overflow at t = %.9g s (tick %lld): x = %g m is %g "
				      "counts of encoder.resolution = %g m, beyond 2^53 counts (where count x "
				      "resolution stops being exact); nothing holds this pushed mass; raise "
				      "encoder.resolution",
				      (double)s->k * s->period_s, s->k, x_m,
				      x_m / s->delta_m, s->delta_m);
	return 0;
}

/* The damping's dissipation over a part h of a period split at a breakpoint
 * (its form computed for h: one 8 x 8 exponential, about 5 us). A ramp has
 * two such breakpoints per run; a table intent whose rows fall inside most
 * periods pays it every tick (measured: a 0.37 ms table, 7 s at 1 kHz, 0.01
 * s of CPU without the dissipation, 0.05 s with it). NaN when the form is not
 * finite, as the step's own matrices then fail too. */
static double part_dissipated_J(const popc_plant *p, const popc_plant_state *st,
				const popc_plant_input *u, double h_s)
{
	popc_plant_dissipation d;
	if (popc_plant_dissipation_init(&d, &p->cfg, h_s) != 0)
		return (double)NAN;
	return popc_plant_dissipated_J(&d, st, u);
}

/* Advances plant (and the exact shadow) over one control period with f_c held,
 * splitting the period at breakpoints of the operator's profile so that the
 * exact discretization stays exact. A breakpoint within tol_s before the
 * period's end counts as on the tick: the segment's line is followed that much
 * further (the ramp of the paper's scene ends at 1.2999999999999998 s, one ulp
 * before tick 1300). One just after t is a segment of its own, however short:
 * the rest of the period must not follow that segment's line, which can be
 * steep (a table's step in x_d over 1e-13 s, a slope of 1e9 m/s, sent the
 * plant to 70 m) or end a hold (at 3 kHz tick 51 is 0.016999999999999998 s,
 * one ulp before operator.t0 = 0.017: the ramp started a period late). Returns
 * 0 or the status of a partial step whose matrices could not be computed
 * (*h_failed_s: its length). */
static int advance(sim_axis *s, popc_plant *p, popc_plant_state *st, double f_c, double *h_failed_s,
		   double *dissipated_J)
{
	double t = (double)s->k * s->period_s, t_end = (double)(s->k + 1) * s->period_s;
	int whole = 1, status;
	if (dissipated_J)
		*dissipated_J = 0.0;
	for (;;) {
		popc_plant_input u;
		double next;
		popc_intent_input(&s->intent, t, &u, &next); /* next > t (intent.h) */
		u.u0_N = (u.u0_N - s->k_x_rest_N) - f_c; /* in y = x - x_rest */
		if (next < t_end - s->tol_s && next > t) {
			if (dissipated_J)
				*dissipated_J += part_dissipated_J(p, st, &u, next - t);
			if ((status = popc_plant_step_h(p, st, &u, next - t)) != 0) {
				*h_failed_s = next - t;
				return status;
			}
			t = next;
			whole = 0;
			continue;
		}
		if (dissipated_J)
			*dissipated_J += whole ? popc_plant_dissipated_J(&s->diss, st, &u)
					       : part_dissipated_J(p, st, &u, t_end - t);
		if (whole) {
			popc_plant_step(p, st, &u);
		} else if ((status = popc_plant_step_h(p, st, &u, t_end - t)) != 0) {
			*h_failed_s = t_end - t;
			return status;
		}
		return 0;
	}
}

/* The run cannot go on: a step split at a breakpoint of the operator's
 * profile has no finite matrices (popc_plant_init checked the full period). */
static int partial_step_failed(const sim_axis *s, double h_s, popc_error *err)
{
	const popc_plant_config *c = &s->plant.cfg;
	return popc_error_set(err, POPC_ERR_NUMERIC,
			      "the plant step of h = %g s at a breakpoint of the operator's profile "
			      "(t = %.9g s, tick %lld) has non-finite %s matrices (K/M = %g 1/s^2, "
			      "B/M = %g 1/s): the plant (operator.* + device.* mass, damping, "
			      "stiffness) is too stiff for double precision",
			      h_s, (double)s->k * s->period_s, s->k, popc_integrator_name(c->method),
			      c->stiffness_Npm / c->mass_kg, c->damping_Nspm / c->mass_kg);
}

/* The energy-growth guard (ENERGY_SURPLUS_MAX) after the step to tick j:
 * books the period's surplus and judges the current window. Returns 1 when
 * the window's made-up energy passes the bound (*made_J, *held_J: the two,
 * over the last *window_ticks ticks). */
static int energy_growth(sim_axis *s, long long j, double x_before, double f_c_N, double *made_J,
			 double *held_J, long long *window_ticks)
{
	const popc_plant_config *c = &s->plant.cfg;
	popc_plant_input um;
	double nb, t_mid = ((double)s->k + 0.5) * s->period_s;
	popc_intent_input(&s->intent, t_mid, &um, &nb);
	/* the balance of the y system (x_rest's spring force is part of its input) */
	double work = ((um.u0_N - s->k_x_rest_N) + um.uc_N - f_c_N) * (s->st.x_m - x_before);
	double e = 0.5 * c->mass_kg * s->st.v_mps * s->st.v_mps +
		   0.5 * c->stiffness_Npm * s->st.x_m * s->st.x_m;
	s->surplus_J += (e - s->energy_J) - work;
	s->energy_J = e;
	s->energy_peak_J = fmax(s->energy_peak_J, e);
	long long b = j / ENERGY_BLOCK_TICKS;
	energy_block *blk = &s->blocks[b % ENERGY_RING];
	if (j % ENERGY_BLOCK_TICKS == 0) {
		blk->surplus_start_J = s->surplus_J;
		blk->peak_J = e;
	} else {
		blk->peak_J = fmax(blk->peak_J, e);
	}
	/* the guard's gate (see ENERGY_SURPLUS_MAX): growth possible and visible */
	if (!amplifies(s->log_rho, s->log_rho_limit, s->plant.cfg.substeps) ||
	    (s->shadow && !(s->max_error_m > s->delta_m)))
		return 0;
	long long w0 = b - (ENERGY_WINDOW_BLOCKS - 1); /* first block of the window */
	double made, held;
	if (w0 <= 0) {
		/* the first window starts at t = 0: what the plant held so far */
		made = s->surplus_J;
		held = s->energy_peak_J;
		*window_ticks = j;
	} else {
		*window_ticks = j - w0 * ENERGY_BLOCK_TICKS;
		made = s->surplus_J - s->blocks[w0 % ENERGY_RING].surplus_start_J;
		held = 0.0;
		for (long long i = w0 - ENERGY_WINDOW_BLOCKS; i < w0; i++)
			if (i >= 0)
				held = fmax(held, s->blocks[i % ENERGY_RING].peak_J);
	}
	*made_J = made;
	*held_J = held;
	return made > ENERGY_SURPLUS_MAX * (held + s->energy_floor_J) && isfinite(made);
}

POPC_FLOOR_CLONES
static int sim_exchange(popc_axis *a, double f_c_N, popc_axis_sample *next, popc_error *err)
{
	sim_axis *s = a->priv;
	double h_failed = 0.0;
	if (s->exact_linear) {
		/* the hot path of a long exact run: no lookup, no call, no shadow */
		double t = (double)s->k * s->period_s, t_end = (double)(s->k + 1) * s->period_s;
		popc_plant_input u;
		if (popc_intent_period_input(&s->intent, &s->seg, t, t_end, s->tol_s, &u)) {
			u.u0_N = (u.u0_N - s->k_x_rest_N) - f_c_N; /* in y = x - x_rest */
			s->dissipated_J = s->has_diss ? popc_plant_dissipated_J(&s->diss, &s->st, &u)
						      : (double)NAN;
			popc_plant_step_exact(&s->plant.full, &s->st, &u);
		} else if (advance(s, &s->plant, &s->st, f_c_N, &h_failed,
				   s->has_diss ? &s->dissipated_J : NULL) != 0) {
			return partial_step_failed(s, h_failed, err);
		}
		s->k++;
		return sim_sample(a, next, err);
	}
	if (s->k + 1 >= s->k_unstable) {
		/* stop before computing a state past the growth bound */
		char what[320], g_txt[64], g2_txt[64];
		format_growth(s->log_rho * (double)(s->k + 1), g_txt, sizeof g_txt);
		format_growth(2.0 * s->log_rho * (double)(s->k + 1), g2_txt, sizeof g2_txt);
		snprintf(what, sizeof what,
			 "energy growth beyond the bound: its free motion would grow %s x in "
			 "amplitude (%s x in energy; the bound is %g x)",
			 g_txt, g2_txt, GROWTH_MAX);
		return integrator_failed(s, what, err);
	}
	double x_before = s->st.x_m;
	if (advance(s, &s->plant, &s->st, f_c_N, &h_failed, NULL) != 0)
		return partial_step_failed(s, h_failed, err);
	if (s->shadow) {
		if (advance(s, &s->exact, &s->st_exact, f_c_N, &h_failed, NULL) != 0)
			return partial_step_failed(s, h_failed, err);
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
	double made, held;
	long long window = 0;
	if (energy_growth(s, s->k + 1, x_before, f_c_N, &made, &held, &window)) {
		s->k++;
		char what[240];
		snprintf(what, sizeof what,
			 "energy growth beyond the bound: within the last %g s it made up %.3g J that "
			 "no input supplied, more than %g x the most energy the plant held %s (%.3g J)",
			 (double)window * s->period_s, made, ENERGY_SURPLUS_MAX,
			 window == s->k ? "so far" : "just before", held);
		return integrator_failed(s, what, err);
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

/* NaN with the shadow of a fixed-step integrator off: nothing measured it */
static double sim_integrator_error_m(const popc_axis *a)
{
	const sim_axis *s = a->priv;
	if (s->scene.integrator != POPC_INTEGRATOR_EXACT && !s->shadow)
		return (double)NAN;
	return s->max_error_m;
}

/* The exact integrator has no shadow to turn on or off */
static void sim_set_shadow(popc_axis *a, int on)
{
	sim_axis *s = a->priv;
	if (s->scene.integrator != POPC_INTEGRATOR_EXACT)
		s->shadow = on != 0;
}

static const popc_axis_ops sim_ops = {
	.name = "sim",
	.log_columns = POPC_LOG_COL_X_TRUE,
	.start = sim_start,
	.sample = sim_sample,
	.exchange = sim_exchange,
	.stop = sim_stop,
	.destroy = sim_destroy,
	.integrator_error_m = sim_integrator_error_m,
	.report = NULL,
	.set_shadow = sim_set_shadow,
};

/* The divergence bound of a scene (DIVERGED_FACTOR): its reach, 10 x the
 * largest position it names + 1 m (popc_scene_reach_m, which the scene layer
 * also checks against the encoder's 2^53 counts), at most DIVERGED_MAX_M. */
static double divergence_bound_m(const popc_scene *sc, const popc_intent *in)
{
	return fmin(popc_scene_reach_m(sc, in, NULL, 0), DIVERGED_MAX_M);
}

/* The plant starts at rest at its static equilibrium under the operator's
 * initial pull: K x = K_HO x_d(0) + f_op(0) with K = K_HO + K_HI (a device
 * spring shares the load with the hand's), so that nothing moves before the
 * operator does. Without any spring there is no equilibrium: x_d(0) (x0 for a
 * force intent). With K_HI = 0 and no initial force this is x_d(0) itself,
 * returned as such so that the paper's scene keeps its bits. */
static double initial_position_m(const popc_scene *sc, const popc_intent *in)
{
	double x_d0 = popc_intent_x_initial(in); /* x_d(0), or x0 for a force intent */
	double f0 = in->q_is_force ? in->q[0] : 0.0;
	double k = sc->op_stiffness_Npm + sc->dev_stiffness_Npm;
	if (!(k > 0.0) || (sc->dev_stiffness_Npm == 0.0 && f0 == 0.0))
		return x_d0;
	return (sc->op_stiffness_Npm * x_d0 + f0) / k;
}

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
	s->tol_s = POPC_INTENT_TICK_TOL_PERIODS * s->period_s;
	popc_plant_config cfg;
	popc_plant_config_from_scene(&cfg, sc);
	int st = popc_plant_init(&s->plant, &cfg, err);
	if (st)
		popc_plant_name_keys(sc, err); /* the plant's parameters as the scene's keys */
	s->exact_linear = !st && cfg.method == POPC_INTEGRATOR_EXACT && !s->plant.friction;
	/* the dissipation is exact where the trajectory is: exact and linear;
	 * a fixed-step integrator's or a friction plant's is not offered */
	s->dissipated_J = (double)NAN;
	if (s->exact_linear) {
		s->has_diss = popc_plant_dissipation_init(&s->diss, &cfg, s->period_s) == 0;
		if (s->has_diss)
			s->dissipated_J = 0.0; /* none before tick 0 */
	}
	s->log_rho = s->log_rho_exact = s->log_rho_limit = 0.0;
	s->k_unstable = LLONG_MAX;
	if (!st && cfg.method != POPC_INTEGRATOR_EXACT) {
		s->shadow = 1;
		popc_plant_config ex = cfg;
		ex.method = POPC_INTEGRATOR_EXACT;
		st = popc_plant_init(&s->exact, &ex, err);
		if (st)
			popc_plant_name_keys(sc, err);
		if (!st) {
			const popc_plant_step_coeffs *ec = &s->exact.full;
			double rho_exact = spectral_radius(ec->phi[0][0], ec->phi[0][1], ec->phi[1][0],
							   ec->phi[1][1]);
			s->log_rho_exact = log(rho_exact);
			s->log_rho_limit = log(fmax(1.0, rho_exact)) + log1p(RHO_MARGIN);
			s->log_rho = log_amplification(&cfg, cfg.substeps);
			/* NaN cannot come out of log_amplification; an overflowed one-substep
			 * matrix is +inf: stopped before the first step */
			if (amplifies(s->log_rho, s->log_rho_limit, cfg.substeps)) {
				double k = ceil(log(GROWTH_MAX) / s->log_rho);
				s->k_unstable = !(k >= 1.0) ? 1 : k < 1e18 ? (long long)k : LLONG_MAX;
			}
		}
	}
	if (!st)
		st = popc_intent_from_scene(&s->intent, sc, err);
	if (st) {
		popc_intent_free(&s->intent);
		free(s);
		free(a);
		return st;
	}
	s->diverged_m = divergence_bound_m(sc, &s->intent);
	s->x_rest_m = initial_position_m(sc, &s->intent);
	s->k_x_rest_N = cfg.stiffness_Npm * s->x_rest_m;
	s->st.x_m = 0.0; /* y(0): at rest at x_rest */
	s->st.v_mps = 0.0;
	s->st_exact = s->st;
	s->x_exact_min_m = s->x_exact_max_m = s->st.x_m;
	/* v(0) = 0; E counts the plant's spring from y = 0 (x = x_rest), like the
	 * energy balance's input work, which holds u - K x_rest */
	s->energy_J = s->energy_peak_J = 0.5 * cfg.stiffness_Npm * s->st.x_m * s->st.x_m;
	s->blocks[0].surplus_start_J = 0.0;
	s->blocks[0].peak_J = s->energy_J;
	/* one encoder count of the spring plus one count per period of motion */
	s->energy_floor_J = 0.5 * cfg.stiffness_Npm * s->delta_m * s->delta_m +
			    0.5 * cfg.mass_kg * (s->delta_m / s->period_s) * (s->delta_m / s->period_s);
	s->seg.t_lo_s = s->seg.t_next_s = 0.0; /* empty: looked up on the first step */
	a->ops = &sim_ops;
	a->priv = s;
	*out = a;
	return 0;
}

static int sim_kind_create(popc_axis **out, const popc_scene *s,
			   const popc_axis_create_options *opt, popc_error *err)
{
	(void)opt; /* pacing and notes are a real axis' */
	if (s->causality == POPC_CAUSALITY_ADMITTANCE)
		return popc_sim_admittance_axis_create(out, s, err);
	return popc_sim_axis_create(out, s, err);
}

const popc_axis_kind popc_axis_kind_sim = {"sim", 1, sim_kind_create};
