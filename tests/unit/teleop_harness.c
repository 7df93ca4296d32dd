/* What the teleoperation unit tests share (teleop_harness.h). */
#include "teleop_harness.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/axes/sim_axis.h"
#include "popc/core/random.h"
#include "popc/log/log.h"
#include "popc/log/log_reader.h"

const int teleop_study_delays[4] = {0, 25, 100, 350};

void teleop_load(popc_scene *s, const char *name)
{
	char path[1024];
	popc_error err;
	snprintf(path, sizeof path, "%s/data/scenes/%s", getenv("POPC_SOURCE_ROOT"), name);
	popc_scene_defaults(s);
	assert_int_equal(popc_scene_load(s, path, &err), 0);
	assert_int_equal(popc_scene_validate(s, &err), 0);
}

int teleop_run(const popc_scene *s, const char *path, popc_run_summary *sum)
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

char *teleop_slurp(const char *path, size_t *n)
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

char *teleop_direct_equals_zero_delay(const popc_scene *s0, const char *dir, size_t min_bytes)
{
	popc_scene s = *s0;
	s.fwd.delay_ticks = s.bwd.delay_ticks = 0;
	s.tele_tdpa = 0;
	char a[512], b[512];
	snprintf(a, sizeof a, "%s/channel.csv", dir);
	snprintf(b, sizeof b, "%s/direct.csv", dir);
	popc_run_summary sum;
	assert_int_equal(teleop_run(&s, a, &sum), 0);
	s.tele_link = POPC_TELEOP_LINK_DIRECT;
	assert_int_equal(teleop_run(&s, b, &sum), 0);
	size_t na, nb;
	char *ta = teleop_slurp(a, &na), *tb = teleop_slurp(b, &nb);
	const char *la = strstr(ta, "# link = channel\n"), *lb = strstr(tb, "# link = direct\n");
	assert_non_null(la);
	assert_non_null(lb);
	/* before the line, and after it: the rest of the header and every row */
	assert_int_equal(la - ta, lb - tb);
	assert_memory_equal(ta, tb, (size_t)(la - ta));
	const char *ra = la + strlen("# link = channel\n"), *rb = lb + strlen("# link = direct\n");
	assert_int_equal(na - (size_t)(ra - ta), nb - (size_t)(rb - tb));
	assert_memory_equal(ra, rb, na - (size_t)(ra - ta));
	assert_true(na > min_bytes);
	free(tb);
	return ta;
}

int teleop_cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

void teleop_study(const popc_scene *base, int d, int pc_on, const char *label, teleop_study_cell *c)
{
	enum { N = TELEOP_STUDY_OFFSETS };
	memset(c, 0, sizeof *c);
	for (int i = 0; i < N; i++) {
		popc_scene s = *base;
		s.fwd.delay_ticks = s.bwd.delay_ticks = d;
		s.tele_tdpa = pc_on;
		s.op_t0_s = 0.1 + 0.00037 * i;
		popc_run_summary sum;
		int st = teleop_run(&s, NULL, &sum);
		c->completed += st == 0;
		double pp = st == 0 ? sum.tele_xs_late_max_m - sum.tele_xs_late_min_m : (double)INFINITY;
		c->oscillating += !(pp <= TELEOP_OSC_PP_M);
		c->violations += sum.tele_violations > 0;
		c->clamped += sum.tele_clamped[0] + sum.tele_clamped[1] > 0;
		c->pp_m[i] = pp;
		c->fmax_N[i] = sum.tele_f_c_max_N;
	}
	qsort(c->pp_m, N, sizeof c->pp_m[0], teleop_cmp_double);
	qsort(c->fmax_N, N, sizeof c->fmax_N[0], teleop_cmp_double);
	print_message("%sround trip %3d ms, PCs %-3s: completed %2d/20, oscillating %2d/20, condition "
		      "broken %2d/20, clamped %2d/20; late peak to peak median %.3g mm [%.3g, %.3g]; max "
		      "|f_c| median %.3g N [%.3g, %.3g]\n",
		      label, 2 * d, pc_on ? "on" : "off", c->completed, c->oscillating, c->violations,
		      c->clamped, 0.5e3 * (c->pp_m[9] + c->pp_m[10]), 1e3 * c->pp_m[0],
		      1e3 * c->pp_m[N - 1], 0.5 * (c->fmax_N[9] + c->fmax_N[10]), c->fmax_N[0],
		      c->fmax_N[N - 1]);
}

void teleop_random_channel(popc_scene *s, uint64_t *rng)
{
	popc_scene_channel *dir[2] = {&s->fwd, &s->bwd};
	for (int j = 0; j < 2; j++) {
		dir[j]->delay_ticks = (int)(popc_uniform_int(rng, 299));
		dir[j]->jitter_ticks = (int)(popc_uniform_int(rng, 59));
		dir[j]->loss = 0.6 * popc_uniform(rng);
		dir[j]->in_order = (int)popc_uniform_int(rng, 1);
		dir[j]->seed = (int)popc_uniform_int(rng, 2147483646u);
	}
	s->op_t0_s = 0.1 + 0.01 * popc_uniform(rng);
}

long long teleop_rows_finite(const char *path)
{
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
	popc_log_reader_close(&rd);
	return rows;
}
