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

#include "teleop_harness.h"
#include "test_tmpdir.h"

static void load_pp(popc_scene *s)
{
	teleop_load(s, "teleop-pp-wall.ini");
	assert_int_equal(s->tele_arch, POPC_TELEOP_POSITION_POSITION);
}

/* Zero delay, no loss, the PCs off: the channel is a direct coupling. The
 * two logs are the same bytes but for the resolved scene's teleop.link line. */
static void test_direct_equals_zero_delay(void **state)
{
	(void)state;
	popc_scene s;
	load_pp(&s);
	char *ta = teleop_direct_equals_zero_delay(&s, tmpdir, 5000 * 100);
	assert_non_null(strstr(ta, "# coupling_stiffness = 3000\n"));
	free(ta);
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
	assert_int_equal(teleop_run(&s, a, &sum), 0);
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

static void test_study(void **state)
{
	(void)state;
	popc_scene base;
	load_pp(&base);
	for (int j = 0; j < 4; j++) {
		teleop_study_cell off, on;
		teleop_study(&base, teleop_study_delays[j], 0, "position-position, ", &off);
		teleop_study(&base, teleop_study_delays[j], 1, "position-position, ", &on);
		/* with the PCs: every run completes, settles, and the condition
		 * holds at every tick, no PC ever at its bound */
		assert_int_equal(on.completed, TELEOP_STUDY_OFFSETS);
		assert_int_equal(on.oscillating, 0);
		assert_int_equal(on.violations, 0);
		assert_int_equal(on.clamped, 0);
		/* without: stable at 0 ms, oscillating or diverging from 50 ms */
		if (teleop_study_delays[j] == 0)
			assert_true(off.oscillating <= TELEOP_STUDY_OFFSETS - 18);
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
		teleop_random_channel(&s, &rng);
		char path[512];
		snprintf(path, sizeof path, "%s/random.csv", tmpdir);
		popc_run_summary sum;
		assert_int_equal(teleop_run(&s, path, &sum), 0);
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
		assert_int_equal(teleop_rows_finite(path), 3001); /* every cell finite */
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
