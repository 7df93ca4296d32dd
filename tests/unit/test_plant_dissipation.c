/* The damping's dissipation over a step (popc/core/plant_dissipation.h): the
 * quadratic form against Simpson's rule of B v(tau)^2 on the exact trajectory,
 * whose v(tau) comes from the plant's own step matrices for h = tau (a
 * computation independent of Van Loan's block exponential). Plants: the
 * paper's (underdamped), an overdamped stiff one (the closed-form step, a fast
 * mode 50 times shorter than the period), a sine input, a period long enough
 * for the form's doublings, and no damping (exactly 0). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "popc/core/plant.h"
#include "popc/core/plant_dissipation.h"

/* v(tau) from state st and input u after tau (exact step of length tau) */
static double v_at(const popc_plant_config *cfg, const popc_plant_state *st,
		   const popc_plant_input *u, double tau)
{
	if (tau == 0.0)
		return st->v_mps;
	popc_plant_step_coeffs c;
	assert_int_equal(popc_plant_coeffs(cfg, tau, &c), 0);
	popc_plant_state s = *st;
	popc_plant_step_exact(&c, &s, u);
	return s.v_mps;
}

/* Simpson's rule of B v^2 over [0, h] with n (even) subintervals */
static double simpson(const popc_plant_config *cfg, const popc_plant_state *st,
		      const popc_plant_input *u, double h, int n)
{
	double d = h / n, v0 = v_at(cfg, st, u, 0.0), v1 = v_at(cfg, st, u, h);
	double s = v0 * v0 + v1 * v1;
	for (int i = 1; i < n; i++) {
		double v = v_at(cfg, st, u, i * d);
		s += (i % 2 ? 4.0 : 2.0) * v * v;
	}
	return cfg->damping_Nspm * s * d / 3.0;
}

/* A deterministic pseudo-random value in [-1, 1) (xorshift) */
static double draw(uint64_t *r)
{
	*r ^= *r << 13;
	*r ^= *r >> 7;
	*r ^= *r << 17;
	return (double)(*r >> 11) * 0x1p-52 - 1.0;
}

/* Random states and inputs of the plant's scale: the largest relative
 * difference from Simpson (n subintervals) must stay within rel. */
static void check_plant(const popc_plant_config *cfg, double h, double x_scale, double v_scale,
			double u_scale, int n, double rel)
{
	popc_plant_dissipation d;
	assert_int_equal(popc_plant_dissipation_init(&d, cfg, h), 0);
	uint64_t r = 0x9e3779b97f4a7c15u;
	double worst = 0.0;
	for (int i = 0; i < 40; i++) {
		popc_plant_state st = {x_scale * draw(&r), v_scale * draw(&r)};
		popc_plant_input u = {u_scale * draw(&r), u_scale / h * draw(&r), 0.0, 0.0};
		if (cfg->omega_radps != 0.0) {
			u.us_N = u_scale * draw(&r);
			u.uc_N = u_scale * draw(&r);
		}
		double form = popc_plant_dissipated_J(&d, &st, &u), quad = simpson(cfg, &st, &u, h, n);
		assert_true(form >= 0.0 && quad > 0.0);
		double e = fabs(form - quad) / quad;
		worst = e > worst ? e : worst;
	}
	print_message("M %g kg, B %g N s/m, K %g N/m, w %g rad/s, h %g s: largest relative "
		      "difference from Simpson (%d) %.3g (bound %.1g)\n",
		      cfg->mass_kg, cfg->damping_Nspm, cfg->stiffness_Npm, cfg->omega_radps, h, n,
		      worst, rel);
	assert_true(worst <= rel);
}

static popc_plant_config plant(double m, double b, double k, double w)
{
	popc_plant_config c = {0};
	c.mass_kg = m;
	c.damping_Nspm = b;
	c.stiffness_Npm = k;
	c.omega_radps = w;
	c.method = POPC_INTEGRATOR_EXACT;
	c.substeps = 1;
	c.period_s = 1e-3;
	return c;
}

/* Simpson's error on a period with n subintervals is (h/n)^4 h f4/180 for
 * f = B v^2 (f4 its fourth derivative): with the draws' jerk u1/M up to
 * 3300 m/s^3 and a velocity that may pass near 0 in the period, f4 reaches
 * about 24 (u1/2M)^2 B, an error of 3e-21 J at n = 512 against a smallest
 * draw of 3e-11 J (1e-10 relative; measured 6e-11), so the reference takes
 * n = 4096 (4000 times smaller); the form itself is a few ulps of its terms. */
static void test_paper_plant(void **state)
{
	(void)state;
	popc_plant_config c = plant(0.3, 0.5, 50.0, 0.0);
	check_plant(&c, 1e-3, 0.01, 0.05, 1.0, 4096, 1e-12);
}

static void test_sine_input(void **state)
{
	(void)state;
	popc_plant_config c = plant(0.3, 0.5, 50.0, 2.0 * 3.141592653589793 * 5.0);
	check_plant(&c, 1e-3, 0.01, 0.05, 1.0, 4096, 1e-12);
}

/* A long step: ||A|| h > 1/2 makes the form double its short step 6 times */
static void test_long_step(void **state)
{
	(void)state;
	popc_plant_config c = plant(0.3, 0.5, 50.0, 0.0);
	c.period_s = 0.05;
	check_plant(&c, 0.05, 0.01, 0.05, 1.0, 4096, 1e-10);
}

/* The overdamped stiff plant (plant.c's closed form): the fast mode decays
 * with M / B = 2e-5 s, 50 per period; Simpson on 8192 subintervals resolves
 * it to about (2.4e-7 / 2e-5)^4 / 180 = 1e-10 */
static void test_overdamped_stiff(void **state)
{
	(void)state;
	popc_plant_config c = plant(1e-5, 0.5, 50.0, 0.0);
	check_plant(&c, 1e-3, 0.01, 0.05, 1.0, 8192, 1e-8);
}

static void test_no_damping(void **state)
{
	(void)state;
	popc_plant_config c = plant(0.3, 0.0, 50.0, 0.0);
	popc_plant_dissipation d;
	assert_int_equal(popc_plant_dissipation_init(&d, &c, 1e-3), 0);
	popc_plant_state st = {0.01, 0.3};
	popc_plant_input u = {1.0, 2.0, 0.0, 0.0};
	assert_true(popc_plant_dissipated_J(&d, &st, &u) == 0.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_paper_plant),      cmocka_unit_test(test_sine_input),
		cmocka_unit_test(test_long_step),        cmocka_unit_test(test_overdamped_stiff),
		cmocka_unit_test(test_no_damping),
	};
	return cmocka_run_group_tests_name("plant dissipation", tests, NULL, NULL);
}
