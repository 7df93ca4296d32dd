/* Position-position teleoperation (issue 26, docs/TELEOPERATION.md,
 * "Position-position") on data/scenes/teleop-pp-wall.ini: a channel of no
 * delay against the direct link (the same rows, bit for bit), the coupling
 * being one spring-damper at no delay (f_e = F_S on every row), the keys,
 * the hard-wall delay study (round trips 0, 50, 200, 700 ms, 20 start
 * offsets each, the PCs off and on) and seeded random channels with the PCs
 * on. Counts, never times. */
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
#include "popc/core/random.h"
#include "popc/log/log.h"
#include "popc/log/log_reader.h"
#include "popc/run/run.h"

#include "test_tmpdir.h"

static void load_pp(popc_scene *s)
{
	char path[1024];
	popc_error err;
	snprintf(path, sizeof path, "%s/data/scenes/teleop-pp-wall.ini", getenv("POPC_SOURCE_ROOT"));
	popc_scene_defaults(s);
	assert_int_equal(popc_scene_load(s, path, &err), 0);
	assert_int_equal(popc_scene_validate(s, &err), 0);
	assert_int_equal(s->tele_arch, POPC_TELEOP_POSITION_POSITION);
}

/* Runs s (log to path unless NULL); returns the run's status. */
static int run(const popc_scene *s, const char *path, popc_run_summary *sum)
{
	popc_axis *axis;
	popc_error err;
	assert_int_equal(popc_axis_create(&axis, s, NULL, &err), 0);
	popc_log_writer w;
	popc_run_options ro = {0};
	if (path) {
		assert_int_equal(popc_log_open(&w, path, popc_run_log_columns(s, axis), &err), 0);
		assert_int_equal(popc_log_write_header(&w, "sim", s, NULL, &err), 0);
		ro.log = &w;
	}
	int st = popc_run(s, axis, &ro, sum, &err);
	if (path)
		assert_int_equal(popc_log_close(&w, &err), 0);
	popc_axis_destroy(&axis);
	return st;
}

static char *slurp(const char *path, size_t *n)
{
	FILE *f = fopen(path, "rb");
	assert_non_null(f);
	char *b = malloc(1 << 24);
	assert_non_null(b);
	*n = fread(b, 1, (1 << 24) - 1, f);
	b[*n] = '\0';
	fclose(f);
	return b;
}

/* Zero delay, no loss, the PCs off: the channel is a direct coupling. The
 * two logs are the same bytes but for the resolved scene's teleop.link line. */
static void test_direct_equals_zero_delay(void **state)
{
	(void)state;
	popc_scene s;
	load_pp(&s);
	s.fwd.delay_ticks = s.bwd.delay_ticks = 0;
	s.tele_tdpa = 0;
	char a[512], b[512];
	snprintf(a, sizeof a, "%s/channel.csv", tmpdir);
	snprintf(b, sizeof b, "%s/direct.csv", tmpdir);
	popc_run_summary sum;
	assert_int_equal(run(&s, a, &sum), 0);
	s.tele_link = POPC_TELEOP_LINK_DIRECT;
	assert_int_equal(run(&s, b, &sum), 0);
	size_t na, nb;
	char *ta = slurp(a, &na), *tb = slurp(b, &nb);
	const char *la = strstr(ta, "# link = channel\n"), *lb = strstr(tb, "# link = direct\n");
	assert_non_null(la);
	assert_non_null(lb);
	assert_non_null(strstr(ta, "# coupling_stiffness = 3000\n"));
	assert_int_equal(la - ta, lb - tb);
	assert_memory_equal(ta, tb, (size_t)(la - ta));
	const char *ra = la + strlen("# link = channel\n"), *rb = lb + strlen("# link = direct\n");
	assert_int_equal(na - (size_t)(ra - ta), nb - (size_t)(rb - tb));
	assert_memory_equal(ra, rb, na - (size_t)(ra - ta));
	assert_true(na > 5000 * 100);
	free(ta);
	free(tb);
}

/* With no delay the two couplings are one spring-damper: the master's force
 * F_M = K_c (x_s - x_m) + B_c (v_s - v_m) is exactly -F_S, so f_e = -F_M
 * equals the slave's F_S (vs_c with the PCs off) bit for bit on every row,
 * and xs_cmd is the master's measured position x. */
static void test_zero_delay_one_coupling(void **state)
{
	(void)state;
	popc_scene s;
	load_pp(&s);
	s.tele_link = POPC_TELEOP_LINK_DIRECT;
	s.tele_tdpa = 0;
	char a[512];
	snprintf(a, sizeof a, "%s/one.csv", tmpdir);
	popc_run_summary sum;
	assert_int_equal(run(&s, a, &sum), 0);
	popc_log_reader rd;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&rd, a, NULL, &err), 0);
	const int c_fe = popc_log_reader_column(&rd, "f_e"), c_vsc = popc_log_reader_column(&rd, "vs_c");
	const int c_x = popc_log_reader_column(&rd, "x"), c_xsc = popc_log_reader_column(&rd, "xs_cmd");
	const int c_fs = popc_log_reader_column(&rd, "fs");
	assert_true(c_fe >= 0 && c_vsc >= 0 && c_x >= 0 && c_xsc >= 0 && c_fs >= 0);
	double v[POPC_LOG_MAX_COLUMNS];
	long long rows = 0, contact = 0, nonzero = 0;
	int st;
	while ((st = popc_log_reader_next(&rd, v, &err)) == 1) {
		if (v[c_fe] != v[c_vsc] || v[c_x] != v[c_xsc])
			fail_msg("row %lld: f_e %.17g, F_S %.17g; x %.17g, xs_cmd %.17g", rows, v[c_fe],
				 v[c_vsc], v[c_x], v[c_xsc]);
		contact += v[c_fs] != 0.0;
		nonzero += v[c_fe] != 0.0;
		rows++;
	}
	assert_int_equal(st, 0);
	popc_log_reader_close(&rd);
	assert_int_equal(rows, 5001);
	/* the slave met the wall and the coupling carried force */
	assert_true(contact > 1000);
	assert_true(nonzero > 1000);
}

/* Bad position-position keys are refused naming the key and its range (exit
 * 2); the coupling's keys are written only for this architecture. */
static void test_keys(void **state)
{
	(void)state;
	static const struct {
		const char *key, *value;
	} bad[] = {
		{"coupling_stiffness", "-1"},
		{"coupling_stiffness", "2e9"},
		{"coupling_damping", "-0.1"},
		{"coupling_damping", "nan"},
		{"slave_pc_force_bound", "0"},
		{"slave_pc_force_bound", "1e7"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		popc_scene s;
		load_pp(&s);
		popc_error err;
		int st = popc_scene_set(&s, "teleop", bad[i].key, bad[i].value, &err);
		assert_int_equal(popc_status_exit_code(st), 2);
		char named[64];
		snprintf(named, sizeof named, "teleop.%s", bad[i].key);
		if (!strstr(err.msg, named) || !strstr(err.msg, "allowed"))
			fail_msg("teleop.%s = %s: %s", bad[i].key, bad[i].value, err.msg);
	}
	/* no coupling at all */
	popc_scene s;
	load_pp(&s);
	s.tele_coupling_K_Npm = 0.0;
	s.tele_coupling_B_Nspm = 0.0;
	popc_error err;
	assert_int_equal(popc_status_exit_code(popc_scene_validate(&s, &err)), 2);
	assert_non_null(strstr(err.msg, "teleop.coupling_stiffness > 0"));
	s.tele_coupling_B_Nspm = 1.0; /* a damper alone couples */
	assert_int_equal(popc_scene_validate(&s, &err), 0);
	/* written only for position-position */
	char *text;
	size_t n;
	load_pp(&s);
	assert_int_equal(popc_scene_to_text(&s, &text, &n, &err), 0);
	assert_non_null(strstr(text, "coupling_stiffness = 3000\n"));
	assert_non_null(strstr(text, "coupling_damping = 3\n"));
	assert_non_null(strstr(text, "slave_pc_force_bound = 100\n"));
	free(text);
	s.tele_arch = POPC_TELEOP_POSITION_FORCE;
	assert_int_equal(popc_scene_to_text(&s, &text, &n, &err), 0);
	assert_null(strstr(text, "coupling_"));
	assert_null(strstr(text, "slave_pc_force_bound"));
	assert_non_null(strstr(text, "architecture = position-force\n"));
	free(text);
}

/* The study: round trip 2 d ticks at 1 kHz, start offsets operator.t0 = 0.1 s
 * + i x 0.37 ms (contact at a different phase of the tick and the delay). */
#define N_OFFSETS 20
static const int study_d[4] = {0, 25, 100, 350};

typedef struct study_cell {
	int completed, oscillating, violations, clamped;
	double pp_m[N_OFFSETS], fmax_N[N_OFFSETS];
} study_cell;

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* a run that stopped diverged, or whose slave still moves by more than
 * 1 mm peak to peak over the last second, oscillates (test_teleop.c's rule) */
#define OSC_PP_M 1e-3

static void study(int d, int pc_on, study_cell *c)
{
	memset(c, 0, sizeof *c);
	for (int i = 0; i < N_OFFSETS; i++) {
		popc_scene s;
		load_pp(&s);
		s.fwd.delay_ticks = s.bwd.delay_ticks = d;
		s.tele_tdpa = pc_on;
		s.op_t0_s = 0.1 + 0.00037 * i;
		popc_run_summary sum;
		int st = run(&s, NULL, &sum);
		c->completed += st == 0;
		double pp = st == 0 ? sum.tele_xs_late_max_m - sum.tele_xs_late_min_m : (double)INFINITY;
		c->oscillating += !(pp <= OSC_PP_M);
		c->violations += sum.tele_violations > 0;
		c->clamped += sum.tele_clamped[0] + sum.tele_clamped[1] > 0;
		c->pp_m[i] = pp;
		c->fmax_N[i] = sum.tele_f_c_max_N;
	}
	qsort(c->pp_m, N_OFFSETS, sizeof c->pp_m[0], cmp_double);
	qsort(c->fmax_N, N_OFFSETS, sizeof c->fmax_N[0], cmp_double);
	print_message("position-position, round trip %3d ms, PCs %-3s: completed %2d/20, oscillating "
		      "%2d/20, condition broken %2d/20, clamped %2d/20; late peak to peak median %.3g mm "
		      "[%.3g, %.3g]; max |f_c| median %.3g N [%.3g, %.3g]\n",
		      2 * d, pc_on ? "on" : "off", c->completed, c->oscillating, c->violations, c->clamped,
		      0.5e3 * (c->pp_m[9] + c->pp_m[10]), 1e3 * c->pp_m[0], 1e3 * c->pp_m[19],
		      0.5 * (c->fmax_N[9] + c->fmax_N[10]), c->fmax_N[0], c->fmax_N[19]);
}

static void test_study(void **state)
{
	(void)state;
	for (int j = 0; j < 4; j++) {
		study_cell off, on;
		study(study_d[j], 0, &off);
		study(study_d[j], 1, &on);
		/* with the PCs: every run completes, settles, and the condition
		 * holds at every tick, no PC ever at its bound */
		assert_int_equal(on.completed, N_OFFSETS);
		assert_int_equal(on.oscillating, 0);
		assert_int_equal(on.violations, 0);
		assert_int_equal(on.clamped, 0);
		/* without: stable at 0 ms, oscillating or diverging from 50 ms */
		if (study_d[j] == 0)
			assert_true(off.oscillating <= N_OFFSETS - 18);
		else
			assert_true(off.oscillating >= 18);
	}
}

/* Seeded random channels, PCs on: the two-port condition never fails, every
 * cell of the log is finite, no PC's |d| beyond its bound. */
static void test_random_channels(void **state)
{
	(void)state;
	uint64_t rng = 2610;
	const int n_runs = 24;
	int active = 0, active_m = 0, active_s = 0;
	for (int i = 0; i < n_runs; i++) {
		popc_scene s;
		load_pp(&s);
		s.duration_s = 3;
		popc_scene_channel *dir[2] = {&s.fwd, &s.bwd};
		for (int j = 0; j < 2; j++) {
			dir[j]->delay_ticks = (int)(popc_uniform_int(&rng, 299));
			dir[j]->jitter_ticks = (int)(popc_uniform_int(&rng, 59));
			dir[j]->loss = 0.6 * popc_uniform(&rng);
			dir[j]->in_order = (int)popc_uniform_int(&rng, 1);
			dir[j]->seed = (int)popc_uniform_int(&rng, 2147483646u);
		}
		s.op_t0_s = 0.1 + 0.01 * popc_uniform(&rng);
		char path[512];
		snprintf(path, sizeof path, "%s/random.csv", tmpdir);
		popc_run_summary sum;
		assert_int_equal(run(&s, path, &sum), 0);
		if (sum.tele_violations || sum.tele_clamped[0] || sum.tele_clamped[1])
			fail_msg("run %d (delays %d+%d, %d+%d, loss %g, %g): %lld ticks break the condition, "
				 "%lld + %lld clamped",
				 i, s.fwd.delay_ticks, s.fwd.jitter_ticks, s.bwd.delay_ticks, s.bwd.jitter_ticks,
				 s.fwd.loss, s.bwd.loss, sum.tele_violations, sum.tele_clamped[0],
				 sum.tele_clamped[1]);
		assert_true(sum.tele_d_max[0] <= s.tele_master_bound_N);
		assert_true(sum.tele_d_max[1] <= s.tele_slave_bound_N);
		active += sum.tele_active[0] > 0 || sum.tele_active[1] > 0;
		active_m += sum.tele_active[0] > 0;
		active_s += sum.tele_active[1] > 0;
		popc_log_reader rd;
		popc_error err;
		assert_int_equal(popc_log_reader_open(&rd, path, NULL, &err), 0);
		double val[POPC_LOG_MAX_COLUMNS];
		long long rows = 0;
		int st, n = rd.n_cols;
		while ((st = popc_log_reader_next(&rd, val, &err)) == 1) {
			for (int c = 0; c < n; c++)
				assert_true(isfinite(val[c]));
			rows++;
		}
		assert_int_equal(st, 0);
		assert_int_equal(rows, 3001);
		popc_log_reader_close(&rd);
	}
	/* the PCs had work to do: a PC acted in most runs, each side's in some */
	print_message("position-position: a PC acted in %d of %d runs (the master's in %d, the "
		      "slave's in %d)\n",
		      active, n_runs, active_m, active_s);
	assert_true(active >= n_runs / 2);
	assert_true(active_m > 0 && active_s > 0);
}

static int teardown(void **state)
{
	(void)state;
	return test_tmpdir_remove();
}

int main(void)
{
	if (test_tmpdir_make("teleop-pp") != 0)
		return 1;
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_direct_equals_zero_delay),
		cmocka_unit_test(test_zero_delay_one_coupling),
		cmocka_unit_test(test_keys),
		cmocka_unit_test(test_study),
		cmocka_unit_test(test_random_channels),
	};
	return cmocka_run_group_tests(tests, NULL, teardown);
}
