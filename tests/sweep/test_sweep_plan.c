/* The sweep planner (sweep_plan.h, sweep_row.h): value lists and ranges, the product, run ids,
 * shards (cover, no overlap), the Slurm array mapping and summary rows. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "popc/sweep/sweep.h"

static void test_expand_table(void **state)
{
	(void)state;
	const struct {
		const char *spec;
		int ok, n;
		const char *first, *third, *last;
	} cases[] = {
		{"a,b,c", 1, 3, "a", "c", "c"},
		{"none", 1, 1, "none", NULL, "none"},
		{"0:1:11", 1, 11, "0", "0.2", "1"},          /* 12 digits: 0.2, not 0.20000000000000001 */
		{"0.01:0.1:10", 1, 10, "0.01", "0.03", "0.1"},
		{"1:1000:4:log", 1, 4, "1", "100", "1000"},  /* exp(log) lands off 10 and 100 by an ulp */
		{"1e-6:1e-4:3:log", 1, 3, "1e-06", "0.0001", "0.0001"},
		{"-1:1:3", 1, 3, "-1", "1", "1"},            /* the middle is 0, never "-0" */
		{"5:5:1", 1, 1, "5", NULL, "5"},
		{"0:1:1", 0, 0, NULL, NULL, NULL},           /* one point cannot hold both ends */
		{"0x1:0x2:2", 0, 0, NULL, NULL, NULL},       /* decimal only */
		{"0:1:0x2", 0, 0, NULL, NULL, NULL},
		{" 0 : 1 : 2 ", 1, 2, "0", NULL, "1"},       /* blanks around the parts, as around list items */
		{"3:1:3", 1, 3, "3", "1", "1"},              /* descending is fine */
		{"0:1:0", 0, 0, NULL, NULL, NULL},           /* n >= 1 */
		{"0:1:2.5", 0, 0, NULL, NULL, NULL},         /* n whole */
		{"0:1", 0, 0, NULL, NULL, NULL},             /* not a range */
		{"0:1:3:lin", 0, 0, NULL, NULL, NULL},
		{"0:1:3:log", 0, 0, NULL, NULL, NULL},       /* log needs lo > 0 */
		{"x:1:3", 0, 0, NULL, NULL, NULL},
		{"0:inf:3", 0, 0, NULL, NULL, NULL},
		{"a,,b", 0, 0, NULL, NULL, NULL},            /* empty item */
		{"a,b,a", 0, 0, NULL, NULL, NULL},           /* duplicate */
		{"1:1:2", 0, 0, NULL, NULL, NULL},           /* duplicate points */
		{"1:1.0000000000001:3", 0, 0, NULL, NULL, NULL}, /* equal at 12 digits */
		{"a\"b", 0, 0, NULL, NULL, NULL},            /* no quotes in CSV cells */
		{"", 0, 0, NULL, NULL, NULL},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		char **v = NULL;
		int n = -1;
		popc_error err;
		int st = popc_sweep_expand(cases[k].spec, &v, &n, &err);
		if (!cases[k].ok) {
			if (st == 0)
				fail_msg("'%s' accepted", cases[k].spec);
			assert_true(strlen(err.msg) > 0);
			assert_null(v);
			continue;
		}
		if (st != 0)
			fail_msg("'%s': %s", cases[k].spec, err.msg);
		assert_int_equal(n, cases[k].n);
		assert_string_equal(v[0], cases[k].first);
		if (cases[k].third)
			assert_string_equal(v[2], cases[k].third);
		assert_string_equal(v[n - 1], cases[k].last);
		popc_sweep_values_free(v, n);
	}
}

/* A linear range's points read back within 12 significant digits of the
 * exact lo + (hi - lo) i / (n - 1), and a log range's are geometric. */
static void test_range_points(void **state)
{
	(void)state;
	char **v;
	int n;
	popc_error err;
	assert_int_equal(popc_sweep_expand("0.01:0.1:100", &v, &n, &err), 0);
	assert_int_equal(n, 100);
	for (int i = 0; i < n; i++) {
		double want = 0.01 + 0.09 * i / 99.0;
		/* 12 significant digits: at most half a unit of the 12th, 5e-12 relative */
		assert_true(fabs(strtod(v[i], NULL) - want) <= 6e-12 * want);
	}
	popc_sweep_values_free(v, n);
	assert_int_equal(popc_sweep_expand("1e-6:1e-2:9:log", &v, &n, &err), 0);
	for (int i = 0; i + 1 < n; i++) {
		double ratio = strtod(v[i + 1], NULL) / strtod(v[i], NULL);
		assert_true(fabs(ratio - 3.1622776601683795) < 1e-10);
	}
	popc_sweep_values_free(v, n);
}

static popc_sweep_plan make_plan(const char *const *vary, int n_axes, int check)
{
	popc_scene base;
	popc_scene_defaults(&base);
	popc_sweep_axis *axes = calloc((size_t)n_axes, sizeof *axes);
	assert_non_null(axes);
	popc_error err;
	for (int a = 0; a < n_axes; a++)
		if (popc_sweep_axis_parse(vary[a], &axes[a], &err) != 0)
			fail_msg("%s: %s", vary[a], err.msg);
	popc_sweep_plan p;
	if (popc_sweep_plan_init(&p, &base, axes, n_axes, check, &err) != 0)
		fail_msg("plan: %s", err.msg);
	return p;
}

/* Last axis fastest; every combination once; the run's scene holds it. */
static void test_product_order(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01,0.02", "controller.variant=none,hold,improved",
			      "encoder.resolution=1e-5:1e-4:2"};
	popc_sweep_plan p = make_plan(vary, 3, 1);
	assert_int_equal(p.n_runs, 12);
	assert_int_equal(p.id_width, 4);
	int seen[2][3][2] = {{{0}}};
	for (long long i = 0; i < p.n_runs; i++) {
		int idx[3];
		popc_sweep_run_values(&p, i, idx);
		assert_int_equal(i, (idx[0] * 3 + idx[1]) * 2 + idx[2]);
		seen[idx[0]][idx[1]][idx[2]]++;
		popc_scene s;
		popc_error err;
		assert_int_equal(popc_sweep_run_scene(&p, i, &s, &err), 0);
		assert_true(s.op_speed_mps == strtod(p.axes[0].values[idx[0]], NULL));
		assert_string_equal(popc_variant_name(s.variant), p.axes[1].values[idx[1]]);
		assert_true(s.enc_resolution_m == strtod(p.axes[2].values[idx[2]], NULL));
	}
	for (int a = 0; a < 2; a++)
		for (int b = 0; b < 3; b++)
			for (int c = 0; c < 2; c++)
				assert_int_equal(seen[a][b][c], 1);
	assert_string_equal(p.columns,
			    "run,operator.speed,controller.variant,encoder.resolution,exit_status,ticks,"
			    "pc_rms,pc_max,pc_active,pc_energy,w_minus_eref_min,w_minus_eref_end,"
			    "vsign_rate,pc_rms_late,vsign_rate_late,integrator_error_m,"
			    "port_energy_end,port_energy_min,po_error_end,po_error_max,device_energy_end,"
			    "device_energy_min,rendered_stiffness,chatter_s,"
			    "chatter_intervals,limit_cycle,wall_time_s\n");
	popc_sweep_plan_free(&p);
}

static void test_ids(void **state)
{
	(void)state;
	const char *small[] = {"operator.speed=0.01:0.1:7"};
	popc_sweep_plan p = make_plan(small, 1, 0);
	char id[POPC_SWEEP_ID_MAX];
	popc_sweep_run_id(&p, 6, id);
	assert_string_equal(id, "0006");
	assert_int_equal(popc_sweep_id_parse(&p, "0006"), 6);
	assert_int_equal(popc_sweep_id_parse(&p, "0007"), -1); /* beyond the plan */
	assert_int_equal(popc_sweep_id_parse(&p, "006"), -1);  /* wrong width */
	assert_int_equal(popc_sweep_id_parse(&p, "00a6"), -1);
	assert_int_equal(popc_sweep_id_parse(&p, ".."), -1);
	popc_sweep_plan_free(&p);

	/* 10001 runs need 5 digits: ids still sort as text in run order */
	const char *big[] = {"operator.speed=0.01:0.1:10001"};
	p = make_plan(big, 1, 0);
	assert_int_equal(p.id_width, 5);
	popc_sweep_run_id(&p, 10000, id);
	assert_string_equal(id, "10000");
	char prev[POPC_SWEEP_ID_MAX] = "";
	for (long long i = 0; i < p.n_runs; i += 997) {
		popc_sweep_run_id(&p, i, id);
		assert_true(strcmp(prev, id) < 0);
		strcpy(prev, id);
	}
	popc_sweep_plan_free(&p);
}

/* The plan id is a function of the base scene and the axes: the same sweep
 * gets the same id, any change another. */
static void test_plan_id(void **state)
{
	(void)state;
	const char *a[] = {"operator.speed=0.01,0.02", "controller.variant=none,improved"};
	const char *b[] = {"operator.speed=0.01,0.03", "controller.variant=none,improved"};
	const char *c[] = {"controller.variant=none,improved", "operator.speed=0.01,0.02"};
	popc_sweep_plan pa = make_plan(a, 2, 0), pa2 = make_plan(a, 2, 0);
	popc_sweep_plan pb = make_plan(b, 2, 0), pc = make_plan(c, 2, 0);
	assert_true(pa.plan_id == pa2.plan_id);
	assert_true(pa.plan_id != pb.plan_id);
	assert_true(pa.plan_id != pc.plan_id);
	popc_sweep_plan_free(&pa);
	popc_sweep_plan_free(&pa2);
	popc_sweep_plan_free(&pb);
	popc_sweep_plan_free(&pc);
}

/* Errors before anything runs: the message names the key, the value and the
 * allowed range (from popc_scene_set). */
static void test_plan_errors(void **state)
{
	(void)state;
	const struct {
		const char *vary[2];
		const char *want[3];
	} cases[] = {
		{{"encoder.resolution=1e-5,-1", NULL}, {"encoder.resolution", "-1", "allowed"}},
		{{"controller.variant=none,fancy", NULL}, {"controller.variant", "fancy", "improved"}},
		{{"operator.nosuch=1,2", NULL}, {"operator.nosuch", "", ""}},
		{{"integrator.substeps=1:10:3", NULL}, {"integrator.substeps", "5.5", "whole"}},
		{{"operator.speed=0.01", "operator.speed=0.02"}, {"operator.speed", "twice", ""}},
		/* one value in two spellings: compared by value, not as text */
		{{"operator.speed=0.01,0.010", NULL}, {"operator.speed", "'0.01'", "'0.010'"}},
		{{"operator.speed=0.02,1e-2,0.01", NULL}, {"items 2 ('1e-2') and 3 ('0.01')", "", ""}},
		{{"integrator.substeps=2,2.0", NULL}, {"integrator.substeps", "'2'", "'2.0'"}},
		{{"operator.x0=0,-0.0", NULL}, {"operator.x0", "'0'", "'-0.0'"}},
		{{"controller.variant=none,none", NULL}, {"controller.variant", "none", "twice"}},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		int n_axes = cases[k].vary[1] ? 2 : 1;
		popc_sweep_axis *axes = calloc(2, sizeof *axes);
		popc_error err;
		int st = 0;
		for (int a = 0; a < n_axes && !st; a++)
			st = popc_sweep_axis_parse(cases[k].vary[a], &axes[a], &err);
		if (st) { /* the same text twice: refused by the list itself */
			for (int a = 0; a < n_axes; a++)
				popc_sweep_axis_free(&axes[a]);
			free(axes);
		} else {
			popc_scene base;
			popc_scene_defaults(&base);
			popc_sweep_plan p;
			st = popc_sweep_plan_init(&p, &base, axes, n_axes, 1, &err);
			popc_sweep_plan_free(&p);
		}
		assert_int_equal(st, POPC_ERR_INVALID);
		for (int w = 0; w < 3; w++)
			if (!strstr(err.msg, cases[k].want[w]))
				fail_msg("case %zu: '%s' lacks '%s'", k, err.msg, cases[k].want[w]);
	}
	/* a combination the scene's cross-key checks refuse: a ramp that ends
	 * where it starts (each value alone is fine) */
	const char *bad[] = {"operator.x0=-0.01,0.03", "operator.x_end=0.03"};
	popc_sweep_axis *axes = calloc(2, sizeof *axes);
	popc_error err;
	for (int a = 0; a < 2; a++)
		assert_int_equal(popc_sweep_axis_parse(bad[a], &axes[a], &err), 0);
	popc_scene base;
	popc_scene_defaults(&base);
	popc_sweep_plan p;
	int st = popc_sweep_plan_init(&p, &base, axes, 2, 1, &err);
	popc_sweep_plan_free(&p);
	assert_int_equal(st, POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "run 0001"));
	assert_non_null(strstr(err.msg, "operator.x_end"));

	/* values that differ, however little, are kept: the value check is
	 * not a tolerance */
	const char *near[] = {"operator.speed=0.01,0.0100000000000001",
			      "operator.x0=-0.01,0,-1e-300"};
	p = make_plan(near, 2, 0);
	assert_int_equal(p.n_runs, 6);
	popc_sweep_plan_free(&p);
}

/* Every run in exactly one shard, shards within one of each other in size,
 * for many sweep sizes and shard counts. */
static void test_shards_cover(void **state)
{
	(void)state;
	const long long sizes[] = {1, 2, 3, 7, 10, 100, 1001};
	const long long counts[] = {1, 2, 3, 4, 7, 16, 1000, 2000};
	for (size_t a = 0; a < sizeof sizes / sizeof sizes[0]; a++) {
		for (size_t b = 0; b < sizeof counts / sizeof counts[0]; b++) {
			long long n = sizes[a], count = counts[b];
			long long min_share = n, max_share = 0;
			for (long long s = 0; s < count; s++) {
				popc_sweep_shard sh = {.index = s, .count = count};
				long long share = 0;
				for (long long i = 0; i < n; i++)
					share += popc_sweep_in_shard(&sh, i);
				min_share = share < min_share ? share : min_share;
				max_share = share > max_share ? share : max_share;
			}
			for (long long i = 0; i < n; i++) {
				int owners = 0;
				for (long long s = 0; s < count; s++) {
					popc_sweep_shard sh = {.index = s, .count = count};
					owners += popc_sweep_in_shard(&sh, i);
				}
				assert_int_equal(owners, 1);
			}
			assert_true(max_share - min_share <= 1);
		}
	}
}

static void test_shard_parse(void **state)
{
	(void)state;
	const struct {
		const char *text;
		int ok;
		long long index, count;
	} cases[] = {
		/* I from 1 to N (Playwright, Jest, node --test); index I - 1 */
		{"1/1", 1, 0, 1},   {"4/4", 1, 3, 4},  {"1/4", 1, 0, 4}, {"5/4", 0, 0, 0},
		{"0/4", 0, 0, 0},   {"0/1", 0, 0, 0},  {"-1/4", 0, 0, 0},
		{"1/0", 0, 0, 0},   {"1", 0, 0, 0},    {"a/b", 0, 0, 0}, {"1/2x", 0, 0, 0},
		{"1 /2", 0, 0, 0},
		/* whole numbers as everywhere (popc/util/parse.h): no blanks (strtoll
		 * alone skips leading space), a sign and "1.0" are fine, no hex */
		{" 1/2", 0, 0, 0},  {"1/ 2", 0, 0, 0}, {"+1/2", 1, 0, 2}, {"1/+2", 1, 0, 2},
		{"-0/2", 0, 0, 0},  {"/2", 0, 0, 0},   {"1/", 0, 0, 0},   {"1/2 ", 0, 0, 0},
		{"\t1/2", 0, 0, 0}, {"10/20", 1, 9, 20}, {"20/20", 1, 19, 20}, {"1.0/2e0", 1, 0, 2},
		{"0x1/2", 0, 0, 0},
		{"0.5/2", 0, 0, 0},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		popc_sweep_shard sh;
		popc_error err;
		int st = popc_sweep_shard_parse(cases[k].text, &sh, &err);
		assert_int_equal(st == 0, cases[k].ok);
		if (cases[k].ok) {
			assert_int_equal(sh.index, cases[k].index);
			assert_int_equal(sh.count, cases[k].count);
		}
	}
	/* 0/N, the old 0-based spelling, says why it is refused */
	popc_sweep_shard sh;
	popc_error err;
	assert_int_equal(popc_sweep_shard_parse("0/2", &sh, &err), POPC_ERR_INVALID);
	if (!strstr(err.msg, "count from 1") || !strstr(err.msg, "--shard 1/2 ... --shard 2/2"))
		fail_msg("0/2: %s", err.msg);
}

static void test_shard_slurm(void **state)
{
	(void)state;
	const struct {
		const char *id, *count, *min, *step;
		int ret;
		long long index, count_out;
	} cases[] = {
		{NULL, NULL, NULL, NULL, 0, 0, 0},       /* not in an array job */
		{"3", NULL, NULL, NULL, 0, 0, 0},
		/* index = shard - 1: the array's first task is shard 1/N, whatever
		 * its index */
		{"0", "2", "0", "1", 1, 0, 2},           /* --array=0-1: shards 1/2, 2/2 */
		{"1", "2", "0", "1", 1, 1, 2},
		{"1", "2", "1", "1", 1, 0, 2},           /* --array=1-2: shards 1/2, 2/2 */
		{"2", "2", "1", "1", 1, 1, 2},
		{"5", "4", "2", "1", 1, 3, 4},           /* --array=2-5 */
		{"6", "3", "2", "2", 1, 2, 3},           /* --array=2-6:2 */
		{"1", "2", NULL, NULL, 1, 1, 2},         /* no MIN/STEP: 0 and 1 */
		{"3", "2", "1", "1", POPC_ERR_INVALID, 0, 0}, /* past the last task */
		{"0", "2", "1", "1", POPC_ERR_INVALID, 0, 0}, /* before the first */
		{"7", "2", "0", "1", POPC_ERR_INVALID, 0, 0}, /* --array=0,7: not regular */
		{"3", "3", "2", "2", POPC_ERR_INVALID, 0, 0},
		{"x", "2", "0", "1", POPC_ERR_INVALID, 0, 0},
		{" 1", "2", "0", "1", POPC_ERR_INVALID, 0, 0},  /* no blanks */
		{"1", "0x2", "0", "1", POPC_ERR_INVALID, 0, 0}, /* no hex */
		{"1", "+2", "0", "1", 1, 1, 2},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		popc_sweep_shard sh = {0, 0};
		popc_error err;
		int r = popc_sweep_shard_from_slurm(cases[k].id, cases[k].count, cases[k].min,
						    cases[k].step, &sh, &err);
		assert_int_equal(r, cases[k].ret);
		if (r == 1) {
			assert_int_equal(sh.index, cases[k].index);
			assert_int_equal(sh.count, cases[k].count_out);
		}
	}
}

/* A sweep row takes the metric cells of a popc run summary by name, bytes
 * unchanged; a run without a summary gets empty cells. */
static void test_rows(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01,0.02", "controller.variant=none,improved"};
	popc_sweep_plan p = make_plan(vary, 2, 0);
	/* the columns in another order than run.c writes them, and one more */
	const char *header = "status,extra,pc_rms,pc_max,pc_active,pc_energy,w_minus_eref_min,"
			     "w_minus_eref_end,vsign_rate,pc_rms_late,vsign_rate_late,"
			     "integrator_error_m,rendered_stiffness,ticks,wall_time_s,port_energy_end,port_energy_min,"
			     "po_error_end,po_error_max,device_energy_end,device_energy_min\n";
	/* the port cells empty, as a real axis' summary has them: empty here too */
	const char *row = "-4,x,1.5,5,0.25,-0.001,-2e-05,3,12.5,1.25,13,0,1000,5001,0.002,,,,,,\n";
	popc_chatter_result chat;
	memset(&chat, 0, sizeof chat);
	chat.chatter_s = 0.5;
	chat.n_intervals = 2;
	chat.limit_cycle = 1;
	/* 5001 ticks at 1 kHz: every window full, the last limit-cycle window too */
	chat.windows = 491;
	chat.window_ticks = 100;
	chat.lc_ticks = 2001;
	chat.lc_min_ticks = 1000;
	char buf[POPC_SWEEP_ROW_MAX];
	popc_error err;
	int n = popc_sweep_row(&p, 3, 6, header, row, &chat, 0.25, buf, sizeof buf, &err);
	assert_true(n > 0);
	assert_string_equal(buf, "0003,0.02,improved,6,5001,1.5,5,0.25,-0.001,-2e-05,3,12.5,1.25,13,0,"
				 ",,,,,,1000,0.5,2,1,0.25\n");
	assert_int_equal(popc_sweep_row_exit_status(&p, buf), 6);
	int status;
	assert_int_equal(popc_sweep_run_csv_status(header, row, &status), 0);
	assert_int_equal(status, -4);

	n = popc_sweep_row(&p, 0, 1, NULL, NULL, NULL, 0.0, buf, sizeof buf, &err);
	assert_true(n > 0);
	/* a real cell with its point, as every summary's (0.0, not 0) */
	assert_string_equal(buf, "0000,0.01,none,1,,,,,,,,,,,,,,,,,,,,,,0.0\n");

	/* a run too short for a verdict has empty cells, not 0: 500 ticks have
	 * chatter windows but less than half a limit-cycle window ... */
	memset(&chat, 0, sizeof chat);
	chat.windows = 41;
	chat.window_ticks = 100;
	chat.lc_ticks = 500;
	chat.lc_min_ticks = 1000;
	n = popc_sweep_row(&p, 3, 0, header, row, &chat, 0.25, buf, sizeof buf, &err);
	assert_true(n > 0);
	assert_string_equal(buf, "0003,0.02,improved,0,5001,1.5,5,0.25,-0.001,-2e-05,3,12.5,1.25,13,0,,,,,,,1000,"
				 "0.0,0,,0.25\n");
	assert_int_equal(popc_sweep_row_exit_status(&p, buf), 0);
	/* ... 50 ticks not one chatter window either */
	chat.windows = 0;
	chat.lc_ticks = 50;
	n = popc_sweep_row(&p, 3, 0, header, row, &chat, 0.25, buf, sizeof buf, &err);
	assert_true(n > 0);
	assert_string_equal(buf, "0003,0.02,improved,0,5001,1.5,5,0.25,-0.001,-2e-05,3,12.5,1.25,13,0,,,,,,,1000,"
				 ",,,0.25\n");
	/* limit cycle checked, chatter not (a longer chatter window) */
	chat.lc_ticks = 1000;
	chat.limit_cycle = 0;
	n = popc_sweep_row(&p, 3, 0, header, row, &chat, 0.25, buf, sizeof buf, &err);
	assert_true(n > 0);
	assert_string_equal(buf, "0003,0.02,improved,0,5001,1.5,5,0.25,-0.001,-2e-05,3,12.5,1.25,13,0,,,,,,,1000,"
				 ",,0,0.25\n");

	/* a run summary without a metric column is an error naming it */
	n = popc_sweep_row(&p, 0, 0, "status,ticks\n", "0,5\n", NULL, 0.0, buf, sizeof buf, &err);
	assert_true(n < 0);
	assert_non_null(strstr(err.msg, "pc_rms"));
	/* too small a buffer is an error, not a cut row */
	n = popc_sweep_row(&p, 3, 6, header, row, &chat, 0.25, buf, 20, &err);
	assert_true(n < 0);
	popc_sweep_plan_free(&p);
}

/* Which popc made a plan: not part of its id; the directory refuses a
 * resume by another build unless allowed, then records that build once. */
static void test_plan_build(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01,0.02"};
	popc_sweep_plan a = make_plan(vary, 1, 0), b = make_plan(vary, 1, 0);
	popc_sweep_plan_set_build(&a, "0.1.0", "abc123");
	popc_sweep_plan_set_build(&b, "0.1.0", "def456\nplan_id = 0");
	assert_int_equal(a.plan_id, b.plan_id);
	assert_string_equal(b.popc_build, "def456"); /* one line of the plan file */
	assert_false(popc_sweep_plan_same_build(&a, &b));
	char text[256];
	popc_sweep_plan_describe_build(&a, text, sizeof text);
	assert_string_equal(text, "popc 0.1.0 (build abc123)");

	char dir[] = "/tmp/popc-test-sweep-build-XXXXXX", plan_path[64], cmd[96];
	assert_non_null(mkdtemp(dir));
	popc_error err;
	assert_int_equal(popc_sweep_dir_prepare(&a, dir, "scene.ini", 0, &err), 0);
	popc_sweep_plan back;
	assert_int_equal(popc_sweep_plan_from_dir(&back, dir, &err), 0);
	assert_true(popc_sweep_plan_same_build(&back, &a));
	popc_sweep_plan_free(&back);
	assert_int_equal(popc_sweep_dir_prepare(&a, dir, "scene.ini", 0, &err), 0);
	assert_int_equal(popc_sweep_dir_prepare(&b, dir, "scene.ini", 0, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "made by popc 0.1.0 (build abc123); this is popc 0.1.0 (build def456)"));
	assert_int_equal(popc_sweep_dir_prepare(&b, dir, "scene.ini", 1, &err), 1);
	assert_int_equal(popc_sweep_dir_prepare(&b, dir, "scene.ini", 1, &err), 1);
	char *plan;
	size_t len;
	snprintf(plan_path, sizeof plan_path, "%s/sweep.plan", dir);
	assert_int_equal(popc_sweep_read_file(plan_path, &plan, &len, &err), 1);
	const char *line = "\nalso_built_by = popc 0.1.0 (build def456)\n";
	const char *at = strstr(plan, line);
	assert_non_null(at);
	assert_null(strstr(at + 1, line)); /* once */
	assert_non_null(strstr(plan, "\npopc_build = abc123\n")); /* the maker stays */
	free(plan);
	/* the plan, noted, still reads as the same plan of the first build */
	assert_int_equal(popc_sweep_plan_from_dir(&back, dir, &err), 0);
	assert_true(popc_sweep_plan_same_build(&back, &a));
	assert_int_equal(back.plan_id, a.plan_id);
	popc_sweep_plan_free(&back);
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	assert_int_equal(system(cmd), 0);
	popc_sweep_plan_free(&a);
	popc_sweep_plan_free(&b);
}

/* A rows file of n_rows runs' rows (the last one cut, as by a kill), run 1
 * failed with its reason line before it; a NUL in row nul_at (if >= 0).
 * Returns the file's size. */
static size_t write_rows_file(const popc_sweep_plan *p, const char *dir, int n_rows, int nul_at)
{
	char path[128];
	snprintf(path, sizeof path, "%s/rows", dir);
	assert_int_equal(mkdir(path, 0777), 0);
	snprintf(path, sizeof path, "%s/rows/test.1.csv", dir);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(p->columns, f);
	for (int i = 0; i < n_rows; i++) {
		char row[POPC_SWEEP_ROW_MAX], id[POPC_SWEEP_ID_MAX];
		popc_error err;
		popc_sweep_run_id(p, i, id);
		if (i == 1)
			fprintf(f, "# %s stop = diverged at tick 3\n", id);
		int n = popc_sweep_row(p, i, i == 1, NULL, NULL, NULL, 0.0, row, sizeof row, &err);
		assert_true(n > 2);
		if (i == nul_at)
			row[2] = '\0';
		fwrite(row, 1, (size_t)(i == n_rows - 1 ? n / 2 : n), f);
	}
	long size = ftell(f);
	assert_int_equal(fclose(f), 0);
	return (size_t)size;
}

/* Rows files read back alike whether mapped (a large one) or read (a small
 * one): every complete row, the failure's reason, nothing of a cut last
 * line, nothing from a line with a NUL on. */
static void test_results_load(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01:0.1:3000"};
	popc_sweep_plan p = make_plan(vary, 1, 0);
	const struct {
		int n_rows, nul_at, mapped;
	} cases[] = {{3000, -1, 1}, {3000, 2500, 1}, {100, -1, 0}, {100, 50, 0}};
	for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		char dir[] = "/tmp/popc-test-sweep-results-XXXXXX", cmd[96];
		assert_non_null(mkdtemp(dir));
		size_t size = write_rows_file(&p, dir, cases[c].n_rows, cases[c].nul_at);
		/* mapped from 64 kB on (sweep_files.c) */
		assert_int_equal(size >= ((size_t)64 << 10), cases[c].mapped);
		popc_sweep_results r;
		popc_error err;
		const char *dirs[] = {dir};
		assert_int_equal(popc_sweep_results_load(&r, &p, dirs, 1, 0, &err), 0);
		assert_int_equal(r.n_texts, 1);
		assert_int_equal(r.texts[0].map != NULL, cases[c].mapped);
		int end = cases[c].nul_at >= 0 ? cases[c].nul_at : cases[c].n_rows - 1;
		for (long long i = 0; i < p.n_runs; i++) {
			const popc_sweep_result_entry *e = &r.run[i];
			if (i >= end) {
				assert_null(e->row);
				continue;
			}
			char row[POPC_SWEEP_ROW_MAX];
			int n = popc_sweep_row(&p, i, i == 1, NULL, NULL, NULL, 0.0, row, sizeof row, &err);
			assert_int_equal(e->len, n);
			assert_memory_equal(e->row, row, (size_t)n);
			assert_int_equal(e->exit_status, i == 1);
			if (i == 1)
				assert_true(e->reason_len == 18 && memcmp(e->reason, "diverged at tick 3", 18) == 0);
			else
				assert_null(e->reason);
		}
		popc_sweep_results_free(&r);
		snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
		assert_int_equal(system(cmd), 0);
	}
	popc_sweep_plan_free(&p);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_expand_table), cmocka_unit_test(test_range_points),
		cmocka_unit_test(test_product_order), cmocka_unit_test(test_ids),
		cmocka_unit_test(test_plan_id),      cmocka_unit_test(test_plan_errors),
		cmocka_unit_test(test_shards_cover), cmocka_unit_test(test_shard_parse),
		cmocka_unit_test(test_shard_slurm),  cmocka_unit_test(test_rows),
		cmocka_unit_test(test_plan_build),   cmocka_unit_test(test_results_load),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
