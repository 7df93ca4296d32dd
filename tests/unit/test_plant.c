/* Plant: exact discretization against closed forms; fixed-step integrator
 * orders; expm. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "popc/core/plant.h"
#include "popc/scene/from_scene.h"
#include "popc/scene/scene.h"

static popc_plant make(double m, double b, double k, popc_integrator method, int substeps, double T)
{
	popc_plant_config cfg = {.mass_kg = m, .damping_Nspm = b, .stiffness_Npm = k,
				 .method = method, .substeps = substeps, .period_s = T};
	popc_plant p;
	popc_error err;
	assert_int_equal(popc_plant_init(&p, &cfg, &err), 0);
	return p;
}

/* Relative-or-absolute closeness: |a - b| <= tol * max(1, |b|) in scaled units. */
static void assert_close(double a, double b, double tol)
{
	double scale = fabs(b) > 1.0 ? fabs(b) : 1.0;
	if (!(fabs(a - b) <= tol * scale))
		fail_msg("%.17g differs from %.17g by %.3g (tolerance %.3g)", a, b, fabs(a - b),
			 tol * scale);
}

static void test_expm_zero_is_identity(void **state)
{
	(void)state;
	double a[9] = {0}, e[9];
	assert_int_equal(popc_expm(3, a, e), 0);
	for (int i = 0; i < 9; i++)
		assert_true(e[i] == (i % 4 == 0 ? 1.0 : 0.0)); /* exact: Pade of 0 is I */
}

static void test_expm_rotation_and_diagonal(void **state)
{
	(void)state;
	/* [[0, th], [-th, 0]] -> [[cos, sin], [-sin, cos]]; th large enough to square */
	const double th[] = {1e-3, 0.3, 2.0, 25.0};
	for (size_t i = 0; i < sizeof th / sizeof th[0]; i++) {
		double a[4] = {0, th[i], -th[i], 0}, e[4];
		assert_int_equal(popc_expm(2, a, e), 0);
		/* Scaling and squaring loses about log2(||A||) bits: 1e-13 covers th = 25. */
		assert_close(e[0], cos(th[i]), 1e-13);
		assert_close(e[1], sin(th[i]), 1e-13);
		assert_close(e[2], -sin(th[i]), 1e-13);
		assert_close(e[3], cos(th[i]), 1e-13);
	}
	double d[4] = {-3.0, 0, 0, 1.5}, e[4];
	assert_int_equal(popc_expm(2, d, e), 0);
	/* two squarings (||A|| = 3 > 0.54 * 2^2) amplify rounding: a few ulp, 1e-14 relative */
	assert_close(e[0], exp(-3.0), 1e-14);
	assert_close(e[3], exp(1.5), 1e-14);
	assert_true(e[1] == 0.0 && e[2] == 0.0);
}

/* Exact step: free mass under constant force, x = x0 + v0 t + F t^2 / (2 M). */
static void test_exact_free_mass_constant_force(void **state)
{
	(void)state;
	const double M = 0.3, F = 2.0, T = 1e-3;
	popc_plant p = make(M, 0, 0, POPC_INTEGRATOR_EXACT, 1, T);
	popc_plant_state st = {.x_m = -0.01, .v_mps = 0.05};
	popc_plant_input u = {.u0_N = F};
	for (int k = 1; k <= 5000; k++) {
		popc_plant_step(&p, &st, &u);
		double t = k * T;
		/* 5000 steps of rounding ~1e-16 each: 1e-13 m relative bound is generous */
		assert_close(st.x_m, -0.01 + 0.05 * t + F * t * t / (2 * M), 1e-13);
		assert_close(st.v_mps, 0.05 + F * t / M, 1e-13);
	}
}

/* Exact step: undamped and damped spring-mass, closed forms. */
static void test_exact_spring_mass(void **state)
{
	(void)state;
	const double M = 0.3, K = 1050.0, T = 1e-3, x0 = 0.002, v0 = -0.1;
	const double Bs[] = {0.0, 0.5, 5.0};
	for (size_t i = 0; i < 3; i++) {
		double B = Bs[i];
		popc_plant p = make(M, B, K, POPC_INTEGRATOR_EXACT, 1, T);
		popc_plant_state st = {.x_m = x0, .v_mps = v0};
		popc_plant_input u = {0};
		double z = B / (2 * M), wn2 = K / M, wd = sqrt(wn2 - z * z);
		for (int k = 1; k <= 3000; k++) {
			popc_plant_step(&p, &st, &u);
			double t = k * T;
			/* x = e^{-z t} (x0 cos(wd t) + (v0 + z x0) / wd sin(wd t)) */
			double x = exp(-z * t) * (x0 * cos(wd * t) + (v0 + z * x0) / wd * sin(wd * t));
			assert_close(st.x_m, x, 2e-13);
		}
	}
}

/* Exact FOH: spring-mass under a ramp input u = c t is exactly the particular
 * solution x_p = (c / K) (t - B / K) plus the homogeneous part. */
static void test_exact_ramp_input(void **state)
{
	(void)state;
	const double M = 0.3, K = 50.0, B = 0.5, T = 1e-3, c = 2.5;
	popc_plant p = make(M, B, K, POPC_INTEGRATOR_EXACT, 1, T);
	/* start on the particular solution: x(0) = -cB/K^2, v(0) = c/K */
	popc_plant_state st = {.x_m = -c * B / (K * K), .v_mps = c / K};
	for (int k = 0; k < 2000; k++) {
		popc_plant_input u = {.u0_N = c * k * T, .u1_Nps = c};
		popc_plant_step(&p, &st, &u);
		double t = (k + 1) * T;
		assert_close(st.x_m, c / K * (t - B / K), 1e-13);
		assert_close(st.v_mps, c / K, 1e-12);
	}
	/* and a period split in two exact steps equals one whole step */
	popc_plant_state a = {.x_m = 0.001, .v_mps = 0.02}, b = a;
	popc_plant_input u = {.u0_N = 1.0, .u1_Nps = 3.0};
	popc_plant_step(&p, &a, &u);
	popc_plant_step_h(&p, &b, &u, 0.4 * T);
	popc_plant_input u2 = {.u0_N = 1.0 + 3.0 * 0.4 * T, .u1_Nps = 3.0};
	popc_plant_step_h(&p, &b, &u2, T - 0.4 * T);
	assert_close(b.x_m, a.x_m, 1e-15);
	assert_close(b.v_mps, a.v_mps, 1e-14);
}

/* The sine input columns against RK4 with a very fine step. */
static void test_exact_sine_input(void **state)
{
	(void)state;
	const double M = 0.3, K = 50.0, B = 0.5, T = 1e-3, w = 2 * 3.141592653589793 * 2.0;
	popc_plant_config cfg = {.mass_kg = M, .damping_Nspm = B, .stiffness_Npm = K,
				 .omega_radps = w, .method = POPC_INTEGRATOR_EXACT, .substeps = 1,
				 .period_s = T};
	popc_plant ex, rk;
	popc_error err;
	assert_int_equal(popc_plant_init(&ex, &cfg, &err), 0);
	cfg.method = POPC_INTEGRATOR_RK4;
	cfg.substeps = 50;
	assert_int_equal(popc_plant_init(&rk, &cfg, &err), 0);
	popc_plant_state a = {0}, b = {0};
	for (int k = 0; k < 1000; k++) {
		double ph = w * k * T;
		/* u(t) = sin(w t) written relative to the step start */
		popc_plant_input u = {.us_N = cos(ph), .uc_N = sin(ph)};
		popc_plant_step(&ex, &a, &u);
		popc_plant_step(&rk, &b, &u);
	}
	/* RK4 at h = 2e-5 s: local error ~ (w_n h)^5, far below 1e-14 m here */
	assert_close(a.x_m, b.x_m, 1e-14);
	assert_true(fabs(a.x_m) > 1e-4); /* the input really moved the mass */
}

/* A stiff, light, undamped plant: det(Phi) = e^(-B/M T) = 1 exactly and Phi
 * = [[cos wT, sin wT / w], [-w sin wT, cos wT]]. Unbalanced, A T =
 * [[0, T], [-w^2 T, 0]] has a 1-norm of w^2 T (1e15 at w T = 1e6, T = 1 ms)
 * and eigenvectors of condition number w: det(Phi) came out 1 + 0.014 at
 * w T = 1e6 and 1 + 1.2e-7 at w T = 1e3 (M = 1e-3 kg, K = 1e9 N/m, 1 kHz), so
 * the "exact" step grew the free motion every period and an undamped hand
 * without contact ran to the divergence bound. Balanced, it is a rotation of
 * angle w T: each of the s = log2(w T / 0.54) squarings doubles the error
 * before it, about 2^s u = 2 w T u in all. The bound is 16 w T eps (measured
 * at most 2.6 w T eps for det and entries; the reference's own angle w T is
 * rounded by about w T eps). */
static void test_exact_stiff_light_plant(void **state)
{
	(void)state;
	const struct {
		double m, k, T;
	} cases[] = {
		{1e-3, 1e9, 1e-3},  /* w T = 1e3 */
		{1e-6, 1e9, 1e-3},  /* 3.2e4 */
		{1e-9, 1e9, 1e-4},  /* 1e5 */
		{1e-9, 1e9, 1e-3},  /* 1e6 */
		{1e-3, 1e9, 1.0},   /* 1e6 */
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_plant p = make(cases[i].m, 0.0, cases[i].k, POPC_INTEGRATOR_EXACT, 1, cases[i].T);
		const popc_plant_step_coeffs *c = &p.full;
		double w = sqrt(cases[i].k / cases[i].m), th = w * cases[i].T;
		double bound = 16.0 * th * DBL_EPSILON;
		double det = c->phi[0][0] * c->phi[1][1] - c->phi[0][1] * c->phi[1][0];
		double e[5] = {det - 1.0, c->phi[0][0] - cos(th), c->phi[0][1] * w - sin(th),
			       c->phi[1][0] / w + sin(th), c->phi[1][1] - cos(th)};
		for (int j = 0; j < 5; j++)
			if (!(fabs(e[j]) <= bound))
				fail_msg("M %g kg, K %g N/m, T %g s (w T = %g): error %d is %.3g, bound %.3g",
					 cases[i].m, cases[i].k, cases[i].T, th, j, e[j], bound);
	}
}

/* Each fixed-step integrator's order: error(h) / error(h/2) ~ 2^p. */
static void test_integrator_orders(void **state)
{
	(void)state;
	const struct {
		popc_integrator m;
		int p;
		int n;
	} cases[] = {
		{POPC_INTEGRATOR_TRAPEZOID, 2, 4},
		{POPC_INTEGRATOR_RK4, 4, 2},
		{POPC_INTEGRATOR_SEMI_IMPLICIT_EULER, 1, 64},
		{POPC_INTEGRATOR_EULER, 1, 64},
	};
	const double M = 0.3, K = 1050.0, B = 0.5, T = 1e-3;
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		double errs[2];
		for (int j = 0; j < 2; j++) {
			popc_plant ex = make(M, B, K, POPC_INTEGRATOR_EXACT, 1, T);
			popc_plant fx = make(M, B, K, cases[i].m, cases[i].n << j, T);
			popc_plant_state a = {.x_m = 0.001, .v_mps = 0.05}, b = a;
			double e = 0;
			for (int k = 0; k < 200; k++) {
				popc_plant_input u = {.u0_N = 1.0 - 0.5 * k * T, .u1_Nps = -0.5};
				popc_plant_step(&ex, &a, &u);
				popc_plant_step(&fx, &b, &u);
				if (fabs(a.x_m - b.x_m) > e)
					e = fabs(a.x_m - b.x_m);
			}
			errs[j] = e;
		}
		double ratio = errs[0] / errs[1], expect = (double)(1 << cases[i].p);
		print_message("integrator %d: errors %.3g %.3g ratio %.3f (2^p = %g)\n", (int)cases[i].m,
			      errs[0], errs[1], ratio, expect);
		assert_true(ratio > 0.8 * expect && ratio < 1.25 * expect);
	}
}

static void test_init_rejects_bad_config(void **state)
{
	(void)state;
	popc_plant p;
	popc_error err;
	popc_plant_config bad[] = {
		{.mass_kg = 0, .period_s = 1e-3, .substeps = 1},
		{.mass_kg = (double)NAN, .period_s = 1e-3, .substeps = 1},
		{.mass_kg = 1, .damping_Nspm = -1, .period_s = 1e-3, .substeps = 1},
		{.mass_kg = 1, .stiffness_Npm = (double)INFINITY, .period_s = 1e-3, .substeps = 1},
		{.mass_kg = 1, .period_s = 1e-3, .substeps = 0},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		assert_int_equal(popc_plant_init(&p, &bad[i], &err), POPC_ERR_INVALID);
}

/* A ratio that overflows is refused at init, naming the plant's own
 * parameters (K = 1e9 N/m on M = 2.3e-308 kg: K/M = inf; the run used to go
 * on with inf/NaN matrices, exit 0, and garbage encoder counts); the scene
 * layer names the keys behind them (popc_plant_name_keys): the core's message
 * names no scene key, the scene's no core field. */
static void test_init_rejects_overflowing_ratios(void **state)
{
	(void)state;
	popc_plant p;
	popc_error err;
	popc_scene s;
	popc_scene_defaults(&s);
	const popc_integrator methods[] = {POPC_INTEGRATOR_EXACT, POPC_INTEGRATOR_TRAPEZOID,
					   POPC_INTEGRATOR_RK4};
	for (size_t i = 0; i < sizeof methods / sizeof methods[0]; i++) {
		const struct {
			popc_plant_config cfg;
			const char *core[2], *keys[2];
		} cases[] = {
			{{.mass_kg = 2.3e-308, .stiffness_Npm = 1e9, .method = methods[i],
			  .substeps = 1, .period_s = 1e-3},
			 {"stiffness_Npm / mass_kg", "raise mass_kg"},
			 {"(operator.stiffness + device.stiffness) / (operator.mass + device.mass)",
			  "raise (operator.mass + device.mass)"}},
			{{.mass_kg = 2.3e-308, .damping_Nspm = 1e6, .method = methods[i],
			  .substeps = 1, .period_s = 1e-3},
			 {"damping_Nspm / mass_kg", "lower damping_Nspm"},
			 {"(operator.damping + device.damping) / (operator.mass + device.mass)",
			  "lower (operator.damping + device.damping)"}},
			{{.mass_kg = 1e-310, .method = methods[i], .substeps = 1, .period_s = 1e-3},
			 {"M = mass_kg = ", "raise mass_kg"},
			 {"M = (operator.mass + device.mass) = ",
			  "raise (operator.mass + device.mass)"}},
		};
		for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
			err.msg[0] = '\0';
			assert_int_equal(popc_plant_init(&p, &cases[c].cfg, &err), POPC_ERR_INVALID);
			for (size_t k = 0; k < 2; k++)
				assert_non_null(strstr(err.msg, cases[c].core[k]));
			assert_null(strstr(err.msg, "operator."));
			assert_null(strstr(err.msg, "device."));
			popc_plant_name_keys(&s, &err);
			for (size_t k = 0; k < 2; k++)
				assert_non_null(strstr(err.msg, cases[c].keys[k]));
			assert_null(strstr(err.msg, "mass_kg"));
			assert_null(strstr(err.msg, "_Npm"));
			assert_null(strstr(err.msg, "_Nspm"));
		}
	}
	/* friction and the period, and an admittance device's servo gains */
	popc_plant_config fr = {.mass_kg = 1, .method = POPC_INTEGRATOR_EXACT, .substeps = 1,
				.period_s = 1e-3, .coulomb_N = 2, .stiction_N = 1};
	assert_int_equal(popc_plant_init(&p, &fr, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "stiction_N = 1 N is below coulomb_N = 2 N"));
	popc_plant_name_keys(&s, &err);
	assert_non_null(strstr(err.msg, "device.stiction = 1 N is below device.coulomb = 2 N"));
	/* K/M finite, K/M T^2 not */
	popc_plant_config kt = {.mass_kg = 1, .stiffness_Npm = 1e300,
				.method = POPC_INTEGRATOR_EXACT, .substeps = 1, .period_s = 1e10};
	assert_int_equal(popc_plant_init(&p, &kt, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "times T^2 (T = period_s) is not finite"));
	s.causality = POPC_CAUSALITY_ADMITTANCE;
	s.adm_servo = POPC_SERVO_POSITION;
	popc_plant_name_keys(&s, &err);
	assert_non_null(strstr(err.msg, "times T^2 (T = 1 / run.rate) is not finite"));
	assert_non_null(strstr(err.msg, "(operator.stiffness + device.stiffness + "
					"admittance.servo_stiffness) / (operator.mass + device.mass)"));
}

/* The matrix exponential reports what it cannot compute instead of handing
 * back inf or NaN: e^(1e300) overflows after the squarings. */
static void test_expm_reports_overflow(void **state)
{
	(void)state;
	double a[4] = {1e300, 0, 0, -1e300}, e[4];
	assert_int_equal(popc_expm(2, a, e), POPC_ERR_NUMERIC);
	double nan_in[4] = {(double)NAN, 0, 0, 0};
	assert_int_equal(popc_expm(2, nan_in, e), POPC_ERR_NUMERIC);
	assert_int_equal(popc_expm(13, a, e), POPC_ERR_INVALID); /* n <= 12 */
}

/* popc_plant_coeffs and popc_plant_step_h propagate a failed exponential
 * (a passive plant's exponential is bounded, so the failure is provoked with
 * a config that bypassed init: K = -1e8 N/m on 1 kg grows as e^(1e4 t),
 * e^5000 over h = 0.5 s, past 1e308): POPC_ERR_NUMERIC, and the state is left
 * as it was. */
static void test_step_h_propagates_failure(void **state)
{
	(void)state;
	popc_plant p = make(1.0, 0.0, 1.0, POPC_INTEGRATOR_EXACT, 1, 1.0);
	p.cfg.stiffness_Npm = -1e8; /* as if init had let it through */
	popc_plant_step_coeffs c;
	assert_int_equal(popc_plant_coeffs(&p.cfg, 0.5, &c), POPC_ERR_NUMERIC);
	popc_plant_state st = {0.25, -1.5};
	popc_plant_input u = {.u0_N = 1.0};
	assert_int_equal(popc_plant_step_h(&p, &st, &u, 0.5), POPC_ERR_NUMERIC);
	assert_true(st.x_m == 0.25 && st.v_mps == -1.5);
	/* a valid plant: 0, and the step happens */
	popc_plant q = make(1.0, 0.0, 1.0, POPC_INTEGRATOR_EXACT, 1, 1.0);
	assert_int_equal(popc_plant_coeffs(&q.cfg, 0.5, &c), 0);
	assert_int_equal(popc_plant_step_h(&q, &st, &u, 0.5), 0);
	assert_true(st.x_m != 0.25);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_expm_zero_is_identity),
		cmocka_unit_test(test_expm_rotation_and_diagonal),
		cmocka_unit_test(test_exact_free_mass_constant_force),
		cmocka_unit_test(test_exact_spring_mass),
		cmocka_unit_test(test_exact_ramp_input),
		cmocka_unit_test(test_exact_sine_input),
		cmocka_unit_test(test_exact_stiff_light_plant),
		cmocka_unit_test(test_integrator_orders),
		cmocka_unit_test(test_init_rejects_bad_config),
		cmocka_unit_test(test_init_rejects_overflowing_ratios),
		cmocka_unit_test(test_expm_reports_overflow),
		cmocka_unit_test(test_step_h_propagates_failure),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
