/* The simulated axis' period splitting (src/axes/sim_axis.c, advance()): a
 * breakpoint of the operator's profile just after the start of a step is a
 * segment of its own, never a line the rest of the period follows.
 *
 * The axis is driven with f_c = 0 (no controller, no wall feedback), so the
 * true position depends on the plant and the intent alone. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/axes/sim_axis.h"

#include "test_tmpdir.h"

static int setup(void **state)
{
	(void)state;
	return test_tmpdir_make("sim-axis");
}

static int teardown(void **state)
{
	(void)state;
	return test_tmpdir_remove();
}

/* The true positions of n ticks under f_c = 0; returns the axis' status
 * (0, or the exchange's error after *ticks samples). */
static int run_open_loop(const popc_scene *s, double *x, int n, int *ticks, popc_error *err)
{
	popc_axis *axis;
	if (popc_sim_axis_create(&axis, s, err))
		fail_msg("%s", err->msg);
	popc_axis_sample smp;
	int st = axis->ops->sample(axis, &smp, err);
	*ticks = 0;
	for (int k = 0; !st && k < n; k++) {
		x[k] = smp.x_true_m;
		*ticks = k + 1;
		if (k + 1 < n)
			st = axis->ops->exchange(axis, 0.0, &smp, err);
	}
	popc_axis_destroy(&axis);
	return st;
}

static double max_abs_difference(const double *a, const double *b, int n)
{
	double m = 0.0;
	for (int k = 0; k < n; k++)
		m = fmax(m, fabs(a[k] - b[k]));
	return m;
}

static void scene_no_contact(popc_scene *s)
{
	popc_scene_defaults(s);
	s->variant = POPC_VARIANT_NONE;
	s->env_position_m = 1.0; /* out of reach: the ramp ends at 0.03 m */
}

/* At 3 kHz tick 51 is (double)51 * (1 / 3000.) = 0.016999999999999998 s, one
 * ulp before operator.t0 = 0.017 s (0.017000000000000001): the hold segment
 * ends 3.5e-18 s after the tick. The rest of the period followed the hold,
 * and the ramp started a period late (1.8e-6 m = 0.18 counts off by 0.1 s).
 * Against a ramp that starts 1e-10 s later (split as any breakpoint inside a
 * period), the runs differ by that time shift: about |x'| 1e-10 s, |x'| <= 2 V
 * for a ramp into the undamped hand spring, 1e-11 m (measured 3.0e-12 m); the
 * bound is 1e-11 m. */
static void test_breakpoint_one_ulp_after_a_tick(void **state)
{
	(void)state;
	enum { N = 301 };
	double a[N], b[N];
	int ticks;
	popc_error err;
	popc_scene s;
	scene_no_contact(&s);
	s.rate_Hz = 3000.0;
	s.duration_s = 0.1;
	s.op_t0_s = 0.017;
	assert_true((double)51 * popc_scene_period_s(&s) < s.op_t0_s); /* the case itself */
	assert_int_equal(run_open_loop(&s, a, N, &ticks, &err), 0);
	s.op_t0_s = 0.017 + 1e-10;
	assert_int_equal(run_open_loop(&s, b, N, &ticks, &err), 0);
	/* the ramp moved the hand within the period that holds t0 */
	assert_true(a[52] > s.op_x0_m);
	double d = max_abs_difference(a, b, N);
	print_message("t0 one ulp after tick 51: max |x(t0) - x(t0 + 1e-10 s)| = %.3g m\n", d);
	assert_true(d <= 1e-11);
}

static void write_table(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

/* A table whose x_d steps by 1e-4 m within 1e-13 s, inside a control period
 * (the split tolerance is 1e-9 T = 1e-12 s). The step's line, 1e9 m/s, was
 * followed over the rest of the period: x_d went to 2.9e5 m and the run
 * stopped as a diverged closed loop ("the physics", exit 6). The same step
 * over 2e-12 s gives the same impulse B_HO dx_d and a spring force that
 * differs for 2e-12 s only: velocity K_HO dx_d dt / M = 3.3e-14 m/s, 3.3e-15 m
 * by 0.1 s (measured 1.1e-15 m); the bound is 1e-13 m. RK4 with 1000 substeps
 * agrees with the exact steps to rounding (measured 1.7e-15 m; bound 1e-14 m). */
static void test_steep_segment_shorter_than_the_tolerance(void **state)
{
	(void)state;
	enum { N = 401 };
	static double a[N], b[N], c[N];
	int ticks;
	popc_error err;
	popc_scene s;
	scene_no_contact(&s);
	s.duration_s = 0.4;
	s.intent = POPC_INTENT_TABLE;
	snprintf(s.op_table, sizeof s.op_table, "%s/sliver.csv", tmpdir);
	write_table(s.op_table, "t,x\n0,-0.01\n0.10003,-0.01\n0.30071,0.02\n0.3007100000001,0.0201\n");
	int st = run_open_loop(&s, a, N, &ticks, &err);
	if (st)
		fail_msg("tick %d: %s", ticks, err.msg);
	snprintf(s.op_table, sizeof s.op_table, "%s/split.csv", tmpdir);
	write_table(s.op_table, "t,x\n0,-0.01\n0.10003,-0.01\n0.30071,0.02\n0.300710000002,0.0201\n");
	assert_int_equal(run_open_loop(&s, b, N, &ticks, &err), 0);
	s.integrator = POPC_INTEGRATOR_RK4;
	s.substeps = 1000;
	snprintf(s.op_table, sizeof s.op_table, "%s/sliver.csv", tmpdir);
	assert_int_equal(run_open_loop(&s, c, N, &ticks, &err), 0);
	double d_split = max_abs_difference(a, b, N), d_rk4 = max_abs_difference(a, c, N);
	print_message("step over 1e-13 s: against 2e-12 s %.3g m, against rk4 x 1000 %.3g m\n",
		      d_split, d_rk4);
	assert_true(d_split <= 1e-13);
	assert_true(d_rk4 <= 1e-14);
	/* and the hand moved as a step response: an underdamped overshoot stays
	 * within 2 x the step (0.03 m) of x0, nowhere near 2.9e5 m */
	for (int k = 0; k < N; k++)
		assert_true(fabs(a[k]) < 0.06);
	assert_true(a[N - 1] > a[300] + 1e-3);
}

/* A hand held at rest with x0 exactly on a count boundary (x0 = n delta, the
 * ramp starting later) must read one count and zero velocity until it moves.
 * Before the plant stepped y = x - x_rest (sim_axis.c), the exact step of x
 * itself rounded Phi x + Gam K x to x - 1 ulp at the first period (x_true =
 * -0.010000000000000002 for x0 = -0.01) and kept drifting: the count fell to
 * n - 1 at t = 0.001 s, a logged velocity of -delta / T = -0.01 m/s in free
 * space. Now the state stays exactly at rest: every true position equals x0
 * bit for bit, for every integrator. */
static void test_rest_on_a_count_boundary(void **state)
{
	(void)state;
	enum { N = 500 }; /* 0.5 s, the ramp starts at 1 s */
	const double x0s[] = {-0.01, -0.02, -0.0125, -0.005, 0.0, 0.004};
	const popc_integrator methods[] = {POPC_INTEGRATOR_EXACT, POPC_INTEGRATOR_TRAPEZOID,
					   POPC_INTEGRATOR_RK4, POPC_INTEGRATOR_SEMI_IMPLICIT_EULER,
					   POPC_INTEGRATOR_EULER};
	for (size_t i = 0; i < sizeof x0s / sizeof x0s[0]; i++) {
		for (size_t m = 0; m < sizeof methods / sizeof methods[0]; m++) {
			popc_scene s;
			popc_error err;
			scene_no_contact(&s);
			s.op_x0_m = x0s[i];
			s.op_t0_s = 1.0;
			s.duration_s = 0.5;
			s.integrator = methods[m];
			s.substeps = 10;
			popc_axis *axis;
			if (popc_sim_axis_create(&axis, &s, &err))
				fail_msg("%s", err.msg);
			popc_axis_sample smp;
			assert_int_equal(axis->ops->sample(axis, &smp, &err), 0);
			const long long count0 = smp.count;
			/* the case itself: x0 is on the boundary of its count */
			assert_true((double)count0 * s.enc_resolution_m == x0s[i]);
			for (int k = 1; k < N; k++) {
				if (axis->ops->exchange(axis, 0.0, &smp, &err))
					fail_msg("%s", err.msg);
				if (smp.count != count0 || smp.x_true_m != x0s[i])
					fail_msg("x0 = %g, %s: tick %d: count %lld (at t = 0: %lld), "
						 "x_true = %.17g", x0s[i], popc_integrator_name(methods[m]), k,
						 smp.count, count0, smp.x_true_m);
			}
			popc_axis_destroy(&axis);
		}
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_breakpoint_one_ulp_after_a_tick),
		cmocka_unit_test(test_steep_segment_shorter_than_the_tolerance),
		cmocka_unit_test(test_rest_on_a_count_boundary),
	};
	return cmocka_run_group_tests_name("sim axis", tests, setup, teardown);
}
