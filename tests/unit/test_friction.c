/* Device friction (src/core/plant_friction.c): the exact method against an
 * independent fine-step reference written here (RK4 at 1e-7 s with its own
 * event location of v = 0 and of the stick/slip transitions), stick-slip on
 * a slow ramp, a mass sliding to rest (closed form), the fixed-step
 * integrators against the exact one, and the scene's friction keys (written
 * only when declared). */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/core/plant.h"
#include "popc/scene/scene.h"

/* The operator pulling through K_HO, B_HO on x_d(t) = speed t (t >= 0):
 * u(t) = K_HO speed t + B_HO speed; the plant's K is K_HO (no device spring). */
typedef struct ramp_case {
	double m, b, k, f_c, f_s, speed, period, duration;
	double b_ho; /* the part of b that is the operator's (drives B_HO x_d') */
	double sine_N, omega_radps; /* an exogenous force sine_N sin(omega t) (0: none) */
} ramp_case;

static double ramp_u(const ramp_case *c, double t)
{
	double u = c->k * c->speed * t + c->b_ho * c->speed;
	if (c->sine_N != 0.0)
		u += c->sine_N * sin(c->omega_radps * t);
	return u;
}

/* ---- the reference: RK4 at 1e-7 s with event location -------------------- */

static void ref_rk4(const ramp_case *c, double t, double h, double fric, double *x, double *v)
{
	double x0 = *x, v0 = *v;
#define ACC(tt, xx, vv) ((ramp_u(c, (tt)) + fric - c->b * (vv) - c->k * (xx)) / c->m)
	double k1x = v0, k1v = ACC(t, x0, v0);
	double k2x = v0 + h / 2 * k1v, k2v = ACC(t + h / 2, x0 + h / 2 * k1x, v0 + h / 2 * k1v);
	double k3x = v0 + h / 2 * k2v, k3v = ACC(t + h / 2, x0 + h / 2 * k2x, v0 + h / 2 * k2v);
	double k4x = v0 + h * k3v, k4v = ACC(t + h, x0 + h * k3x, v0 + h * k3v);
#undef ACC
	*x = x0 + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
	*v = v0 + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

typedef struct ref_state {
	double t, x, v;
	long sticks, slips; /* transitions seen: slide -> rest, rest -> slide */
} ref_state;

/* Advances the reference to t_to: steps of at most 1e-7 s; a step in which v
 * reaches 0 is cut there by bisection of its length (80 halvings of 1e-7 s:
 * below 1e-30 s), a stuck body's break-away time bisected on |g| > F_s. */
static void ref_advance(const ramp_case *c, ref_state *r, double t_to)
{
	const double dt = 1e-7;
	while (r->t < t_to) {
		double h = fmin(dt, t_to - r->t), s;
		if (r->v == 0.0) {
			double g = ramp_u(c, r->t) - c->k * r->x;
			if (!(fabs(g) > c->f_s)) {
				double g1 = ramp_u(c, r->t + h) - c->k * r->x;
				if (!(fabs(g1) > c->f_s)) {
					r->t += h;
					continue;
				}
				double lo = r->t, hi = r->t + h;
				for (int i = 0; i < 80; i++) {
					double mid = 0.5 * (lo + hi);
					if (fabs(ramp_u(c, mid) - c->k * r->x) > c->f_s)
						hi = mid;
					else
						lo = mid;
				}
				r->t = hi;
				r->slips++;
				continue;
			}
			s = g > 0 ? 1.0 : -1.0;
		} else {
			s = r->v > 0 ? 1.0 : -1.0;
		}
		double x = r->x, v = r->v;
		ref_rk4(c, r->t, h, -s * c->f_c, &x, &v);
		if (s * v > 0.0) {
			r->x = x;
			r->v = v;
			r->t += h;
			continue;
		}
		double lo = 0.0, hi = h, xh = x;
		for (int i = 0; i < 80; i++) {
			double mid = 0.5 * (lo + hi), xm = r->x, vm = r->v;
			ref_rk4(c, r->t, mid, -s * c->f_c, &xm, &vm);
			if (s * vm > 0.0)
				lo = mid;
			else {
				hi = mid;
				xh = xm;
			}
		}
		r->x = xh;
		r->v = 0.0;
		r->t += hi;
		if (fabs(ramp_u(c, r->t) - c->k * r->x) <= c->f_s)
			r->sticks++;
	}
}

/* popc's plant for a ramp case; method and substeps as given */
static popc_plant ramp_plant(const ramp_case *c, popc_integrator method, int substeps)
{
	popc_plant_config cfg = {.mass_kg = c->m, .damping_Nspm = c->b, .stiffness_Npm = c->k,
				 .method = method, .substeps = substeps, .period_s = c->period,
				 .coulomb_N = c->f_c, .stiction_N = c->f_s, .omega_radps = c->omega_radps};
	popc_plant p;
	popc_error err;
	assert_int_equal(popc_plant_init(&p, &cfg, &err), 0);
	assert_true(p.friction);
	return p;
}

/* The tick's input: u(t_k + tau) = u(t_k) + K speed tau (first-order hold),
 * plus the sine's two columns */
static popc_plant_input ramp_input(const ramp_case *c, long k)
{
	double t = (double)k * c->period;
	popc_plant_input u = {c->k * c->speed * t + c->b_ho * c->speed, c->k * c->speed, 0.0, 0.0};
	if (c->sine_N != 0.0) {
		/* sine_N sin(w (t + tau)) = us sin(w tau) + uc cos(w tau) */
		u.us_N = c->sine_N * cos(c->omega_radps * t);
		u.uc_N = c->sine_N * sin(c->omega_radps * t);
	}
	return u;
}

typedef struct run_result {
	double max_err_m;      /* |x - x_ref| over the ticks */
	long stuck_phases;     /* runs of ticks with v == 0 after motion began */
	long ref_sticks, ref_slips;
} run_result;

/* The reference's positions at the ticks of the last case asked for (the
 * fixed-step methods share the stick-slip case's: RK4 at 1e-7 s is most of
 * this file's time) */
static const ramp_case *ref_cached;
static double *ref_x;
static ref_state ref_end;

static run_result run_against_reference(const ramp_case *c, popc_integrator method, int substeps)
{
	popc_plant p = ramp_plant(c, method, substeps);
	popc_plant_state st = {0.0, 0.0};
	run_result out = {0.0, 0, 0, 0};
	long n = lround(c->duration / c->period);
	if (ref_cached != c) {
		free(ref_x);
		ref_x = malloc((size_t)n * sizeof *ref_x);
		assert_non_null(ref_x);
		ref_state r = {0.0, 0.0, 0.0, 0, 0};
		for (long k = 0; k < n; k++) {
			ref_advance(c, &r, (double)(k + 1) * c->period);
			ref_x[k] = r.x;
		}
		ref_end = r;
		ref_cached = c;
	}
	ref_state r = ref_end;
	int was_moving = 0;
	for (long k = 0; k < n; k++) {
		popc_plant_input u = ramp_input(c, k);
		popc_plant_step(&p, &st, &u);
		assert_true(isfinite(st.x_m) && isfinite(st.v_mps));
		out.max_err_m = fmax(out.max_err_m, fabs(st.x_m - ref_x[k]));
		if (st.v_mps != 0.0)
			was_moving = 1;
		else if (was_moving) {
			out.stuck_phases++;
			was_moving = 0;
		}
	}
	out.ref_sticks = r.sticks;
	out.ref_slips = r.slips;
	return out;
}

/* The paper's hand on the paper's device (M = 0.3 kg, B = 0.5 N s/m,
 * K_HO = 50 N/m), F_c = 0.3 N, F_s = 0.5 N, pulled at 20 mm/s: the spring
 * stretches to F_s / K = 10 mm, the device breaks away, slips about
 * 2 (F_s - F_c) / K = 8 mm in half an oscillation (0.24 s) and sticks again
 * (the spring then holds 2 F_c - F_s = 0.1 N < F_s); each stick lasts
 * 8 mm / 20 mm/s = 0.4 s. */
static const ramp_case stick_slip = {.m = 0.3, .b = 0.5, .k = 50.0, .f_c = 0.3, .f_s = 0.5,
				     .speed = 0.02, .period = 1e-3, .duration = 3.0, .b_ho = 0.5};

static void test_exact_stick_slip_against_reference(void **state)
{
	(void)state;
	run_result r = run_against_reference(&stick_slip, POPC_INTEGRATOR_EXACT, 1);
	print_message("exact with friction: max |x - x_ref| = %.3g m over %ld stick phases "
		      "(reference: %ld breaks, %ld sticks)\n",
		      r.max_err_m, r.stuck_phases, r.ref_slips, r.ref_sticks);
	/* stuck, broke away, slipped, stuck again, at least 3 times in 3 s */
	assert_true(r.ref_slips >= 3 && r.ref_sticks >= 3);
	assert_true(r.stuck_phases == r.ref_sticks);
	/* the stated error: 1e-10 m (1e-5 counts of the paper's encoder);
	 * the reference's own error is that of 2e7 RK4 steps at w h = 1.3e-6
	 * and its rounding, far below */
	assert_true(r.max_err_m < 1e-10);
}

/* Coulomb friction equal to stiction: stick band of one force */
static void test_exact_coulomb_only_against_reference(void **state)
{
	(void)state;
	static ramp_case c;
	c = stick_slip;
	c.f_s = c.f_c = 0.4;
	c.speed = 0.05;
	c.duration = 1.0;
	run_result r = run_against_reference(&c, POPC_INTEGRATOR_EXACT, 1);
	print_message("exact, F_s = F_c: max |x - x_ref| = %.3g m, %ld breaks\n", r.max_err_m,
		      r.ref_slips);
	assert_true(r.ref_slips >= 1);
	assert_true(r.max_err_m < 1e-10);
}

/* A stiffer plant at a slow control rate: v = 0 searched on sub-intervals
 * of the period (sqrt(K/M) T = 1.3 rad per period: 3 sub-intervals) */
static void test_exact_fast_plant_against_reference(void **state)
{
	(void)state;
	static const ramp_case c = {.m = 0.3, .b = 0.5, .k = 5000.0, .f_c = 2.0, .f_s = 3.0,
		       .speed = 0.02, .period = 1e-2, .duration = 0.5, .b_ho = 0.5};
	popc_plant p = ramp_plant(&c, POPC_INTEGRATOR_EXACT, 1);
	assert_true(p.friction_subs > 1);
	run_result r = run_against_reference(&c, POPC_INTEGRATOR_EXACT, 1);
	print_message("exact, %d sub-intervals: max |x - x_ref| = %.3g m, %ld breaks, %ld sticks\n",
		      p.friction_subs, r.max_err_m, r.ref_slips, r.ref_sticks);
	assert_true(r.ref_slips >= 2);
	assert_true(r.max_err_m < 1e-10);
}

/* A sine force on a held hand (speed 0): 1 N at 1 Hz against F_s = 0.5 N,
 * F_c = 0.3 N: the body slides with the force, sticks where it turns (the
 * net force there is about F_c < F_s) and breaks away when the force has
 * come back by about F_c + F_s; the break-away times are bisected on the
 * sine. Bound 1e-9 m (the sine's rounding: popc turns it per tick by the
 * angle-sum rule, the reference calls sin(w t)) */
static void test_exact_sine_against_reference(void **state)
{
	(void)state;
	static const ramp_case c = {.m = 0.3, .b = 0.5, .k = 50.0, .f_c = 0.3, .f_s = 0.5,
				    .speed = 0.0, .period = 1e-3, .duration = 2.5, .b_ho = 0.5,
				    .sine_N = 1.0, .omega_radps = 6.283185307179586};
	run_result r = run_against_reference(&c, POPC_INTEGRATOR_EXACT, 1);
	print_message("exact, sine force: max |x - x_ref| = %.3g m, %ld breaks, %ld sticks\n",
		      r.max_err_m, r.ref_slips, r.ref_sticks);
	assert_true(r.ref_slips >= 4 && r.ref_sticks >= 4);
	assert_true(r.stuck_phases == r.ref_sticks);
	assert_true(r.max_err_m < 1e-9);
}

/* The fixed-step integrators with the same law: their own error against the
 * reference, stated per method at 100 substeps (measured 2.05e-6 m for rk4
 * and trapezoid, 3.6e-7 m semi-implicit Euler, 6.4e-6 m Euler; bounds 10 x
 * that). The law is first order in the substep hs = 1e-5 s: a break-away is
 * seen at the first substep start past it (up to hs late: the slide at
 * ~0.05 m/s then lags by up to 5e-7 m), a stop at the substep end after it;
 * the integrators' own errors (rk4: (w hs)^4) are far below. */
static void test_fixed_step_against_reference(void **state)
{
	(void)state;
	const struct {
		popc_integrator m;
		double bound_m;
	} cases[] = {
		{POPC_INTEGRATOR_RK4, 2e-5},
		{POPC_INTEGRATOR_TRAPEZOID, 2e-5},
		{POPC_INTEGRATOR_SEMI_IMPLICIT_EULER, 4e-6},
		{POPC_INTEGRATOR_EULER, 6e-5},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		run_result r = run_against_reference(&stick_slip, cases[i].m, 100);
		print_message("%s x 100 with friction: max |x - x_ref| = %.3g m, %ld stick phases\n",
			      popc_integrator_name(cases[i].m), r.max_err_m, r.stuck_phases);
		assert_true(r.max_err_m < cases[i].bound_m);
		assert_true(r.stuck_phases >= 3);
	}
}

/* A mass sliding to rest: v0 > 0, no spring, F_c constant. With B = 0 it
 * stops at t = M v0 / F_c after M v0^2 / (2 F_c); with B > 0,
 *     v(t) = (v0 + F/B) e^(-B t / M) - F/B,
 *     t_stop = (M/B) ln(1 + B v0 / F),  x_stop = (M v0 - F t_stop) / B,
 * and it stays there (nothing pulls it). */
static void slide_to_rest(double m, double b, double f, double v0, double t_stop, double x_stop,
			  popc_integrator method, int substeps, double tol_m)
{
	double T = 1e-3;
	popc_plant_config cfg = {.mass_kg = m, .damping_Nspm = b, .stiffness_Npm = 0.0,
				 .method = method, .substeps = substeps, .period_s = T,
				 .coulomb_N = f};
	popc_plant p;
	popc_error err;
	assert_int_equal(popc_plant_init(&p, &cfg, &err), 0);
	popc_plant_state st = {0.0, v0};
	popc_plant_input u = {0.0, 0.0, 0.0, 0.0};
	long k_before = (long)floor(t_stop / T);
	for (long k = 0; k < 2 * k_before + 10; k++) {
		popc_plant_step(&p, &st, &u);
		if (k + 1 <= k_before)
			assert_true(st.v_mps > 0.0);
		if (k + 1 >= k_before + 1)
			assert_true(st.v_mps == 0.0); /* at rest from the tick after t_stop on */
	}
	print_message("%s: slide to rest x = %.17g m, closed form %.17g m (error %.3g m)\n",
		      popc_integrator_name(method), st.x_m, x_stop, fabs(st.x_m - x_stop));
	assert_true(fabs(st.x_m - x_stop) <= tol_m);
}

static void test_slide_to_rest_closed_form(void **state)
{
	(void)state;
	/* B = 0: t = 1/3 s, x = 1/6 m; exact within 64 ulps of x */
	slide_to_rest(1.0, 0.0, 3.0, 1.0, 1.0 / 3.0, 1.0 / 6.0, POPC_INTEGRATOR_EXACT, 1,
		      64 * DBL_EPSILON);
	double m = 0.3, b = 0.5, f = 0.2, v0 = 0.4;
	double ts = m / b * log1p(b * v0 / f), xs = (m * v0 - f * ts) / b;
	slide_to_rest(m, b, f, v0, ts, xs, POPC_INTEGRATOR_EXACT, 1, 1e-14);
	/* RK4 x 100: the slide is a polynomial it integrates exactly but for
	 * the last substep, cut at v = 0 by the reset: within a (F/M) hs^2 */
	slide_to_rest(1.0, 0.0, 3.0, 1.0, 1.0 / 3.0, 1.0 / 6.0, POPC_INTEGRATOR_RK4, 100,
		      3.0 * 1e-5 * 1e-5);
}

/* Friction 0 is no friction: the plant takes the linear path (bit for bit
 * the same steps) and the scene writes no friction keys, so that a log's
 * header keeps its bytes; declared, they are written and read back. */
static void test_no_friction_is_linear_and_unwritten(void **state)
{
	(void)state;
	popc_plant_config cfg = {.mass_kg = 0.3, .damping_Nspm = 0.5, .stiffness_Npm = 50.0,
				 .method = POPC_INTEGRATOR_EXACT, .substeps = 1, .period_s = 1e-3};
	popc_plant p;
	popc_error err;
	assert_int_equal(popc_plant_init(&p, &cfg, &err), 0);
	assert_false(p.friction);
	popc_plant_state a = {0.001, 0.02}, b = a;
	popc_plant_input u = {0.3, 1.0, 0.0, 0.0};
	for (int i = 0; i < 1000; i++) {
		popc_plant_step(&p, &a, &u);
		popc_plant_step_exact(&p.full, &b, &u);
	}
	assert_memory_equal(&a, &b, sizeof a);

	popc_scene s;
	popc_scene_defaults(&s);
	char *text = NULL;
	size_t len = 0;
	assert_int_equal(popc_scene_to_text(&s, &text, &len, &err), 0);
	assert_null(strstr(text, "coulomb"));
	assert_null(strstr(text, "stiction"));
	free(text);
	assert_int_equal(popc_scene_set(&s, "device", "coulomb", "0.25", &err), 0);
	assert_int_equal(popc_scene_to_text(&s, &text, &len, &err), 0);
	assert_non_null(strstr(text, "coulomb = 0.25\n"));
	assert_null(strstr(text, "stiction"));
	free(text);
	/* stiction below Coulomb is refused, naming both keys */
	assert_int_equal(popc_scene_set(&s, "device", "stiction", "0.1", &err), 0);
	assert_int_equal(popc_scene_validate(&s, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "device.stiction"));
	assert_non_null(strstr(err.msg, "device.coulomb"));
	assert_int_not_equal(popc_scene_set(&s, "device", "coulomb", "-1", &err), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_exact_stick_slip_against_reference),
		cmocka_unit_test(test_exact_coulomb_only_against_reference),
		cmocka_unit_test(test_exact_fast_plant_against_reference),
		cmocka_unit_test(test_exact_sine_against_reference),
		cmocka_unit_test(test_fixed_step_against_reference),
		cmocka_unit_test(test_slide_to_rest_closed_form),
		cmocka_unit_test(test_no_friction_is_linear_and_unwritten),
	};
	int failed = cmocka_run_group_tests(tests, NULL, NULL);
	free(ref_x);
	return failed;
}
