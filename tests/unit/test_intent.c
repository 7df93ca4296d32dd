/* Operator intents: ramp, table, force, sine, as plant inputs; a table with
 * the ramp's points reproduces the ramp run bitwise; breakpoints inside a
 * control period keep the exact discretization exact. */
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
#include "popc/core/intent.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"

#include "test_tmpdir.h"

static int setup(void **state)
{
	(void)state;
	return test_tmpdir_make("intent");
}

static int teardown(void **state)
{
	(void)state;
	return test_tmpdir_remove();
}

/* Runs a scene, returning the true positions at every tick. */
static int run_positions(const popc_scene *s, double *x, int n)
{
	popc_axis *axis;
	popc_error err;
	if (popc_sim_axis_create(&axis, s, &err))
		fail_msg("%s", err.msg);
	popc_axis_sample smp;
	axis->ops->sample(axis, &smp, &err);
	x[0] = smp.x_true_m;
	for (int k = 1; k < n; k++) {
		if (axis->ops->exchange(axis, 0.0, &smp, &err))
			fail_msg("%s", err.msg);
		x[k] = smp.x_true_m;
	}
	double e = axis->ops->integrator_error_m(axis);
	popc_axis_destroy(&axis);
	return e > 0; /* whether a shadow measured any error */
}

/* The defaults with the ramp these tests were written for (rest at -0.01 m
 * until 0.5 s, 0.05 m/s to 0.03 m): they test the intent's arithmetic, not
 * the paper scene's calibrated ramp (docs/TIMELINE.md). */
static void ramp_scene(popc_scene *s)
{
	popc_scene_defaults(s);
	s->op_x0_m = -0.01;
	s->op_t0_s = 0.5;
	s->op_speed_mps = 0.05;
	s->op_x_end_m = 0.03;
}

static void test_ramp_values(void **state)
{
	(void)state;
	popc_scene s;
	ramp_scene(&s);
	popc_intent in;
	popc_error err;
	assert_int_equal(popc_intent_from_scene(&in, &s, &err), 0);
	assert_true(popc_intent_xd(&in, 0.0) == -0.01);
	assert_true(popc_intent_xd(&in, 0.5) == -0.01);
	assert_true(fabs(popc_intent_xd(&in, 0.9) - 0.01) < 1e-15);
	assert_true(popc_intent_xd(&in, 2.0) == 0.03);
	assert_true(popc_intent_x_initial(&in) == -0.01);
	/* u = K x_d + B x_d' during the ramp: 50 * 0.01 + 0.5 * 0.05 at 0.9 s */
	popc_plant_input u;
	double next;
	popc_intent_input(&in, 0.9, &u, &next);
	assert_true(fabs(u.u0_N - (50 * 0.01 + 0.5 * 0.05)) < 1e-13);
	assert_true(fabs(u.u1_Nps - 50 * 0.05) < 1e-13);
	assert_true(fabs(next - 1.3) < 1e-15);
	popc_intent_free(&in);
}

static void test_table_equals_ramp(void **state)
{
	(void)state;
	char path[512];
	snprintf(path, sizeof path, "%s/ramp.csv", tmpdir);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	/* header, comment and the ramp's breakpoints; t_end = 0.5 + 0.04 / 0.05 */
	fprintf(f, "t,x_d\n# the paper ramp\n0,-0.01\n0.5,-0.01\n%.17g,0.03\n", 0.5 + 0.04 / 0.05);
	fclose(f);
	popc_scene a, b;
	ramp_scene(&a);
	a.duration_s = 2.0;
	b = a;
	b.intent = POPC_INTENT_TABLE;
	snprintf(b.op_table, sizeof b.op_table, "%s", path);
	static double xa[2001], xb[2001];
	run_positions(&a, xa, 2001);
	run_positions(&b, xb, 2001);
	assert_memory_equal(xa, xb, sizeof xa);
	assert_true(xa[2000] > 0.0); /* the hand reached the wall */
}

/* A breakpoint off the control grid: the exact plant splits the period, so a
 * 1 kHz run and a 10 kHz run agree at the common ticks to rounding, where a
 * run that ignored the breakpoint would differ by ~(speed T)-sized errors. */
static void test_breakpoint_inside_period(void **state)
{
	(void)state;
	popc_scene a, b;
	ramp_scene(&a);
	a.duration_s = 1.0;
	a.op_t0_s = 0.10037;       /* not on either grid */
	a.op_stiffness_Npm = 5000; /* a stiff hand makes the input matter */
	b = a;
	b.rate_Hz = 10000.0;
	static double xa[1001], xb[10001];
	run_positions(&a, xa, 1001);
	run_positions(&b, xb, 10001);
	double worst = 0;
	for (int k = 0; k <= 1000; k++)
		worst = fmax(worst, fabs(xa[k] - xb[10 * k]));
	print_message("max difference 1 kHz vs 10 kHz: %.3g m\n", worst);
	assert_true(worst < 1e-13);
}

static void test_force_and_sine_intents(void **state)
{
	(void)state;
	popc_scene s;
	ramp_scene(&s);
	s.duration_s = 1.0;
	s.intent = POPC_INTENT_FORCE;
	s.op_force_N = 2.0;
	s.op_force_rate_Nps = 20.0;
	s.op_stiffness_Npm = 0.0; /* a pure force on the free masses before contact */
	s.op_damping_Nspm = 0.0;
	s.op_x0_m = -0.5;
	static double x[1001];
	run_positions(&s, x, 1001);
	/* t < 0.5: rest; 0.5..0.6: ramp to 2 N; after: 2 N on 0.3 kg. Closed form at 1 s:
	 * x = x0 + int int f/M = x0 + (20/6 * 0.1^3 + 1 * 0.1^2 * ... ) computed piecewise */
	double M = 0.3, tr = 0.1, v1 = 20.0 * tr * tr / 2 / M, x1 = 20.0 * tr * tr * tr / 6 / M;
	double tl = 0.4, xe = -0.5 + x1 + v1 * tl + 2.0 * tl * tl / 2 / M;
	assert_true(fabs(x[1000] - xe) < 1e-12);

	ramp_scene(&s);
	s.intent = POPC_INTENT_SINE;
	s.duration_s = 1.0;
	s.op_x0_m = -0.05; /* stays out of the wall */
	s.op_frequency_Hz = 5.0;
	static double xe2[1001], xr[1001];
	run_positions(&s, xe2, 1001);
	s.integrator = POPC_INTEGRATOR_RK4;
	s.substeps = 20;
	assert_int_equal(run_positions(&s, xr, 1001), 1);
	double worst = 0, moved = 0;
	for (int k = 0; k <= 1000; k++) {
		worst = fmax(worst, fabs(xe2[k] - xr[k]));
		moved = fmax(moved, fabs(xe2[k] + 0.05));
	}
	/* RK4 at h = 5e-5 s on this plant: error ~1e-15 m; the motion is millimetres */
	assert_true(worst < 1e-12);
	assert_true(moved > 1e-3);
}

static const char *write_table(const char *name, const char *text)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/%s", tmpdir, name);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(text, f);
	fclose(f);
	return path;
}

static int load_table(const char *path, popc_intent *in, popc_error *err)
{
	popc_scene s;
	ramp_scene(&s);
	s.intent = POPC_INTENT_TABLE;
	snprintf(s.op_table, sizeof s.op_table, "%s", path);
	return popc_intent_from_scene(in, &s, err);
}

/* A 600-character number: fgets into 512 bytes used to read it as two lines. */
static char long_zeros[601];

static void test_bad_tables(void **state)
{
	(void)state;
	memset(long_zeros, '0', 600);
	char long_bad[800];
	snprintf(long_bad, sizeof long_bad, "t,x\n0,0\n2,0.01%sx\n3,1\n", long_zeros);
	const struct {
		const char *text;
		const char *must_contain[2];
	} bad[] = {
		{"t,x\n0,0\n0,1\n", {":3:", "does not increase"}},
		{"t,x\n0,0\n1,abc\n", {":3:", "column 2"}},
		{"t,x\n0\n", {":2:", "two columns"}},
		{"t,x\n", {"the table has no rows", NULL}},
		{"t,x\n0 1\n", {":2:", "two columns"}},          /* blanks alone do not separate */
		{"t,x\n0,1,2\n", {":2:", "column 2"}},           /* a third column */
		{"t,x\n0,1\nt,x\n", {":3:", "column 1"}},       /* a header after a row */
		{"t,x\n\nt,x\n0,1\n", {":3:", "column 1"}},    /* two headers */
		{"t,x\n0,1\n1e400,2\n", {":3:", "column 1"}},
		{"t,x\n0\t\n", {":2:", "two columns"}},
		{long_bad, {":3:", "column 2"}},                /* the real line, not ":4:" */
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		char name[32];
		snprintf(name, sizeof name, "bad%zu.csv", i);
		const char *path = write_table(name, bad[i].text);
		popc_intent in;
		popc_error err = {{0}};
		assert_int_equal(load_table(path, &in, &err), POPC_ERR_INVALID);
		if (strncmp(err.msg, path, strlen(path)) != 0)
			fail_msg("case %zu: '%s' does not start with the table", i, err.msg);
		for (int j = 0; j < 2 && bad[i].must_contain[j]; j++)
			if (!strstr(err.msg, bad[i].must_contain[j]))
				fail_msg("case %zu: '%s' lacks '%s'", i, err.msg, bad[i].must_contain[j]);
		popc_intent_free(&in);
	}
	/* a directory opens but cannot be read: not "no rows", and bad input
	 * (exit 2) naming the path, as a missing table */
	popc_intent in;
	popc_error err = {{0}};
	assert_int_equal(load_table(tmpdir, &in, &err), POPC_ERR_INVALID);
	assert_int_equal(strncmp(err.msg, tmpdir, strlen(tmpdir)), 0);
	assert_non_null(strstr(err.msg, ": cannot read table: Is a directory"));
	popc_intent_free(&in);
}

/* Tab, ';' and ',' delimiters, comments and blank lines before the header,
 * CRLF, a byte order mark, and a number longer than any line buffer. */
static void test_good_tables(void **state)
{
	(void)state;
	memset(long_zeros, '0', 600);
	char long_good[800];
	snprintf(long_good, sizeof long_good, "t,x\n0,0.01%s\n1,2\n", long_zeros);
	const struct {
		const char *text;
		double t1, q0, q1;
	} good[] = {
		{"0\t-0.01\n1\t0.02\n", 1, -0.01, 0.02},
		{"t\tx_d\n0 \t -0.01\n1\t\t0.02\n", 1, -0.01, 0.02},
		{"# made by hand\n\nt,x_d\n0,1\n2,3\n", 2, 1, 3},
		{"t,x\r\n0,1\r\n1.5,2\r\n", 1.5, 1, 2},
		{"\xEF\xBB\xBFt;x\r\n 0 ; 1 \r\n# note\r\n1 ;2", 1, 1, 2},
		{long_good, 1, 0.01, 2},
	};
	for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
		char name[32];
		snprintf(name, sizeof name, "good%zu.csv", i);
		popc_intent in;
		popc_error err = {{0}};
		if (load_table(write_table(name, good[i].text), &in, &err) != 0)
			fail_msg("case %zu: %s", i, err.msg);
		if (in.n != 2 || in.t[0] != 0.0 || in.t[1] != good[i].t1 || in.q[0] != good[i].q0 ||
		    in.q[1] != good[i].q1)
			fail_msg("case %zu: %zu rows, (%g, %g) (%g, %g)", i, in.n, in.t[0], in.q[0],
				 in.n > 1 ? in.t[1] : (double)NAN, in.n > 1 ? in.q[1] : (double)NAN);
		popc_intent_free(&in);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_ramp_values),
		cmocka_unit_test(test_table_equals_ramp),
		cmocka_unit_test(test_breakpoint_inside_period),
		cmocka_unit_test(test_force_and_sine_intents),
		cmocka_unit_test(test_bad_tables),
		cmocka_unit_test(test_good_tables),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
