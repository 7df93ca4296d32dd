/* The log's E_port column (the run loop, popc/core/port_energy.h) against an
 * independent computation of the true port energy.
 *
 * A constant command: the wall sits at -0.5 m and the encoder resolution is
 * 1 m, so the hand (held by the operator at x0 = 0.3 m, count 0) measures
 * x = 0 throughout and the VE commands f_c = K_e (0 - (-0.5)) = 0.5 N every
 * tick while the true plant responds to that push. With the operator holding
 * still, y = x - x0 obeys M y'' + B y' + K y = -f_c from rest: the step
 * response of an underdamped oscillator, in closed form. The true energy into
 * the port over period k is the integral of f_c v(t) over it, computed here
 * with Simpson's rule on 64 subintervals of v(t) in closed form, without the
 * plant's discretization or the log's sum. */
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
#include "popc/log/log.h"
#include "popc/log/log_reader.h"
#include "popc/run/run.h"

#include "test_tmpdir.h"

#define N_TICKS 1001 /* 1 s at 1 kHz */

static int setup(void **state)
{
	(void)state;
	return test_tmpdir_make("port-energy");
}

static int teardown(void **state)
{
	(void)state;
	return test_tmpdir_remove();
}

/* v(t) of M y'' + B y' + K y = -f from rest (underdamped):
 * y = -(f/K) (1 - e^(-a t) (cos wd t + (a/wd) sin wd t)), a = B / 2M,
 * v = -(f/K) (wn^2 / wd) e^(-a t) sin wd t. */
static double velocity(double f, double M, double B, double K, double t)
{
	const double a = B / (2.0 * M), wn2 = K / M, wd = sqrt(wn2 - a * a);
	return -(f / K) * (wn2 / wd) * exp(-a * t) * sin(wd * t);
}

/* Simpson's rule of f v(t) over [t0, t1] with n (even) subintervals. */
static double simpson_work(double f, double M, double B, double K, double t0, double t1, int n)
{
	const double h = (t1 - t0) / n;
	double s = velocity(f, M, B, K, t0) + velocity(f, M, B, K, t1);
	for (int i = 1; i < n; i++)
		s += (i % 2 ? 4.0 : 2.0) * velocity(f, M, B, K, t0 + i * h);
	return f * s * h / 3.0;
}

/* Simpson's rule of B v(t)^2 over [t0, t1] with n (even) subintervals: the
 * energy the plant's damping dissipates. */
static double simpson_dissipation(double f, double M, double B, double K, double t0, double t1,
				  int n)
{
	const double h = (t1 - t0) / n;
	double v0 = velocity(f, M, B, K, t0), v1 = velocity(f, M, B, K, t1);
	double s = v0 * v0 + v1 * v1;
	for (int i = 1; i < n; i++) {
		double v = velocity(f, M, B, K, t0 + i * h);
		s += (i % 2 ? 4.0 : 2.0) * v * v;
	}
	return B * s * h / 3.0;
}

static void test_constant_command_against_quadrature(void **state)
{
	(void)state;
	popc_scene s;
	popc_scene_defaults(&s);
	s.duration_s = 1.0;
	s.variant = POPC_VARIANT_NONE;
	s.op_x0_m = 0.3;
	s.op_t0_s = 10.0; /* the operator holds x0 for the whole run */
	s.env_position_m = -0.5;
	s.env_stiffness_Npm = 1.0;
	s.enc_resolution_m = 1.0;
	const double f_c = 0.5;
	const double M = s.op_mass_kg + s.dev_mass_kg, B = s.op_damping_Nspm + s.dev_damping_Nspm;
	const double K = s.op_stiffness_Npm + s.dev_stiffness_Npm;

	char path[1024];
	snprintf(path, sizeof path, "%s/constant.csv", tmpdir);
	popc_axis *axis;
	popc_error err;
	popc_log_writer w;
	if (popc_sim_axis_create(&axis, &s, &err) ||
	    popc_log_open(&w, path, axis->ops->log_columns, &err) ||
	    popc_log_write_header(&w, "sim", &s, NULL, &err))
		fail_msg("%s", err.msg);
	popc_run_options ro = {.log = &w};
	popc_run_summary sum;
	if (popc_run(&s, axis, &ro, &sum, &err) || popc_log_close(&w, &err))
		fail_msg("%s", err.msg);
	popc_axis_destroy(&axis);

	popc_log_reader rd;
	if (popc_log_reader_open(&rd, path, NULL, &err))
		fail_msg("%s", err.msg);
	const int c_t = popc_log_reader_column(&rd, "t"), c_f_c = popc_log_reader_column(&rd, "f_c");
	const int c_port = popc_log_reader_column(&rd, "E_port");
	assert_true(c_t >= 0 && c_f_c >= 0 && c_port >= 0);
	double val[POPC_LOG_MAX_COLUMNS], truth = 0.0, worst = 0.0, last = 0.0, dissipated = 0.0;
	int st, n = 0;
	while ((st = popc_log_reader_next(&rd, val, &err)) == 1) {
		/* the case itself: the command is the constant 0.5 N */
		assert_true(val[c_f_c] == f_c);
		double t = val[c_t];
		if (n > 0) {
			truth += simpson_work(f_c, M, B, K, t - 1e-3, t, 64);
			dissipated += simpson_dissipation(f_c, M, B, K, t - 1e-3, t, 64);
		}
		worst = fmax(worst, fabs(val[c_port] - truth));
		last = val[c_port];
		n++;
	}
	popc_log_reader_close(&rd);
	assert_int_equal(st, 0);
	assert_int_equal(n, N_TICKS);
	/* the push moves the hand toward -x: the VE does work on it, the port
	 * energy is negative (f_c v < 0), about f (static deflection f/K = 1 cm)
	 * times the displacement, a few mJ */
	print_message("constant f_c: E_port(1 s) = %.17g J, quadrature %.17g J, largest "
		      "|E_port - quadrature| over the ticks %.3g J\n", last, truth, worst);
	assert_true(last < -1e-3 && last > -1e-2);
	/* Simpson's error with h = 1/64 ms is below 1e-20 J a period; what is
	 * left is the rounding of positions near 0.3 m (ulp 5.6e-17 m) times
	 * 0.5 N over 1000 periods: bound 1e-15 J */
	assert_true(worst <= 1e-15);
	assert_true(sum.has_port_energy);
	assert_true(sum.port_energy_J == last);
	/* E_dev = E_port + B integral v^2: the form of plant_dissipation.h summed
	 * per period against Simpson on the closed-form velocity. The push gives
	 * the hand about f^2 / (2 K) = 2.5 mJ of spring energy plus motion; the
	 * damping takes a part of the work: E_dev lies between E_port and 0 */
	assert_true(sum.has_device_energy);
	double dev_truth = last + dissipated;
	print_message("constant f_c: E_dev(1 s) = %.17g J, quadrature %.17g J (dissipated %.6g J)\n",
		      sum.device_energy_J, dev_truth, dissipated);
	assert_true(dissipated > 1e-4);
	assert_true(sum.device_energy_J > last && sum.device_energy_J < 0.0);
	/* the form's rounding (a few ulps of J per period) over 1000 periods */
	assert_true(fabs(sum.device_energy_J - dev_truth) <= 1e-14);
	assert_true(sum.device_energy_min_J <= sum.device_energy_J);
}

/* One run of s, logged to path when path is not NULL, with the summary read
 * or unread (popc_run_options.summary_unread). */
static void run_once(const popc_scene *s, const char *path, int unread, popc_run_summary *sum)
{
	popc_axis *axis;
	popc_error err;
	popc_log_writer w;
	if (popc_sim_axis_create(&axis, s, &err) ||
	    (path && (popc_log_open(&w, path, axis->ops->log_columns, &err) ||
		      popc_log_write_header(&w, "sim", s, NULL, &err))))
		fail_msg("%s", err.msg);
	popc_run_options ro = {.log = path ? &w : NULL, .summary_unread = unread};
	if (popc_run(s, axis, &ro, sum, &err) || (path && popc_log_close(&w, &err)))
		fail_msg("%s", err.msg);
	popc_axis_destroy(&axis);
}

static char *slurp(const char *path, long *n)
{
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	fseek(f, 0, SEEK_END);
	*n = ftell(f);
	rewind(f);
	char *b = malloc((size_t)*n + 1);
	assert_non_null(b);
	assert_int_equal(fread(b, 1, (size_t)*n, f), (size_t)*n);
	fclose(f);
	return b;
}

/* Scenes that ask for less pay for less (issue 23): a run whose summary
 * nobody reads (popc run -q without --summary) computes no metrics and no
 * summary energies, and its log (E_port included) is the same bytes as the
 * log of a run that computes everything. */
static void test_summary_unread(void **state)
{
	(void)state;
	popc_scene s;
	popc_scene_defaults(&s);
	s.duration_s = 2.0; /* the ramp's end splits a period at 0.689 s */
	char full[1024], lean[1024];
	snprintf(full, sizeof full, "%s/full.csv", tmpdir);
	snprintf(lean, sizeof lean, "%s/lean.csv", tmpdir);
	popc_run_summary a, b, c;
	run_once(&s, full, 0, &a);
	run_once(&s, lean, 1, &b);
	run_once(&s, NULL, 1, &c);
	long na, nb;
	char *ta = slurp(full, &na), *tb = slurp(lean, &nb);
	assert_int_equal(na, nb);
	assert_memory_equal(ta, tb, (size_t)na);
	free(ta);
	free(tb);
	/* the run itself is the same: ticks, status, stop reason */
	assert_int_equal(a.ticks, 2001);
	assert_int_equal(b.ticks, a.ticks);
	assert_int_equal(c.ticks, a.ticks);
	assert_int_equal(b.status, a.status);
	assert_string_equal(c.stop_reason, a.stop_reason);
	/* the full run computed its metrics and energies, the unread ones not */
	assert_int_equal(a.metrics.all.ticks, 2001);
	assert_true(a.device_energy_J != 0.0 && a.metrics.pc_energy_J != 0.0);
	assert_int_equal(b.metrics.all.ticks, 0);
	assert_int_equal(c.metrics.all.ticks, 0);
	assert_true(b.metrics.pc_energy_J == 0.0 && b.device_energy_J == 0.0 &&
		    b.po_error_max_J == 0.0);
	assert_true(c.metrics.pc_energy_J == 0.0 && c.device_energy_J == 0.0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_constant_command_against_quadrature),
		cmocka_unit_test(test_summary_unread),
	};
	return cmocka_run_group_tests_name("port energy", tests, setup, teardown);
}
