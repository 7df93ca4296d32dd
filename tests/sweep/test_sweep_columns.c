/* summary.csv's column table (sweep_columns.h): the header, the rows, the
 * cell count and the exit_status cell all follow it, and its run-summary
 * metrics are columns that popc run's summary really has. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/run/run.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/sweep/sweep_row.h"
#include "popc/sweep/sweep_teleop.h"

static popc_sweep_plan make_plan(const char *const *vary, int n_axes)
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
	if (popc_sweep_plan_init(&p, &base, axes, n_axes, 0, &err) != 0)
		fail_msg("plan: %s", err.msg);
	return p;
}

/* popc run's summary header as its text (malloc'd). */
static char *run_summary_header(void)
{
	char *header = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&header, &len);
	assert_non_null(f);
	popc_run_summary_csv_header(f);
	assert_int_equal(fclose(f), 0);
	return header;
}

/* A detector verdict of a 5001-tick run at 1 kHz: every window full, the
 * last limit-cycle window too. */
static popc_chatter_result checked_chatter(double chatter_s, int n_intervals)
{
	popc_chatter_result c;
	memset(&c, 0, sizeof c);
	c.windows = 491;
	c.window_ticks = 100;
	c.lc_ticks = 2001;
	c.lc_min_ticks = 1000;
	c.chatter_s = chatter_s;
	c.n_intervals = n_intervals;
	return c;
}

static int count_cells(const char *line)
{
	int n = 1;
	for (const char *c = line; *c && *c != '\n'; c++)
		n += *c == ',';
	return n;
}

/* The header cell by cell: the table's names, the axes' keys in their place. */
static void test_header_follows_table(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01,0.02", "controller.variant=none,improved"};
	popc_sweep_plan p = make_plan(vary, 2);
	/* the header summary.csv has had since issue 11 (issue 6's, with the
	 * true port energy's three columns): a change here changes every
	 * sweep's plan id and every reader of summary.csv */
	assert_string_equal(p.columns,
			    "run,operator.speed,controller.variant,exit_status,ticks,pc_rms,pc_max,"
			    "pc_active,pc_energy,w_minus_eref_min,w_minus_eref_end,vsign_rate,"
			    "pc_rms_late,vsign_rate_late,integrator_error_m,port_energy_end,"
			    "port_energy_min,po_error_end,po_error_max,device_energy_end,"
			    "device_energy_min,rendered_stiffness,chatter_s,"
			    "chatter_intervals,limit_cycle,wall_time_s\n");
	assert_int_equal(count_cells(p.columns), popc_sweep_columns_count(2));
	const char *cell = p.columns;
	int k = 0;
	for (int c = 0; c < popc_sweep_n_columns; c++) {
		const popc_sweep_column *col = &popc_sweep_columns[c];
		int n = col->source == POPC_SWEEP_CELL_AXES ? 2 : 1;
		if (col->source != POPC_SWEEP_CELL_AXES) {
			assert_non_null(col->name);
			size_t l = strcspn(cell, ",\n");
			assert_int_equal(l, strlen(col->name));
			assert_memory_equal(cell, col->name, l);
		}
		/* the index of a source is its first column (the metrics share one) */
		if (c == 0 || popc_sweep_columns[c - 1].source != col->source)
			assert_int_equal(popc_sweep_column_index(2, col->source), k);
		for (int m = 0; m < n; m++) {
			cell += strcspn(cell, ",\n");
			cell += *cell == ',';
		}
		k += n;
	}
	assert_int_equal(*cell, '\n');
	assert_int_equal(k, popc_sweep_columns_count(2));
	/* no axes: the axis columns vanish, nothing else moves */
	char *h0 = popc_sweep_columns_header(NULL, 0);
	assert_non_null(h0);
	assert_string_equal(h0, "run,exit_status,ticks,pc_rms,pc_max,pc_active,pc_energy,"
				"w_minus_eref_min,w_minus_eref_end,vsign_rate,pc_rms_late,"
				"vsign_rate_late,integrator_error_m,port_energy_end,port_energy_min,po_error_end,"
				"po_error_max,device_energy_end,device_energy_min,rendered_stiffness,chatter_s,"
				"chatter_intervals,limit_cycle,wall_time_s\n");
	assert_int_equal(popc_sweep_columns_count(0), count_cells(h0));
	assert_int_equal(popc_sweep_column_index(0, POPC_SWEEP_CELL_EXIT_STATUS), 1);
	free(h0);
	popc_sweep_plan_free(&p);
}

/* Every metric the table takes from popc run's summary is a column of it: a
 * renamed run-summary column fails here, not in a sweep of every run. */
static void test_metrics_in_run_summary(void **state)
{
	(void)state;
	char *header = run_summary_header();
	int n_metrics = 0;
	for (int c = 0; c < popc_sweep_n_columns; c++) {
		const popc_sweep_column *col = &popc_sweep_columns[c];
		if (col->source != POPC_SWEEP_CELL_RUN_SUMMARY)
			continue;
		n_metrics++;
		size_t l = strlen(col->name);
		int found = 0;
		for (const char *p = header; *p && !found; p += strcspn(p, ",\n"), p += *p != '\0')
			found = strncmp(p, col->name, l) == 0 && (p[l] == ',' || p[l] == '\n');
		if (!found)
			fail_msg("sweep column '%s' is not in the run summary header %s", col->name,
				 header);
		/* copied text, empty for a run without a summary */
		assert_int_equal(col->format, POPC_SWEEP_FORMAT_TEXT);
		assert_int_equal(col->empty, POPC_SWEEP_EMPTY_WITHOUT_SUMMARY);
	}
	assert_int_equal(n_metrics, 18);
	free(header);
}

/* Rows with and without a summary and a detector verdict all have the
 * header's cell count, and their exit_status reads back. */
static void test_rows_have_header_cells(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01,0.02,0.03"};
	popc_sweep_plan p = make_plan(vary, 1);
	const char *header = "status,pc_rms,pc_max,pc_active,pc_energy,w_minus_eref_min,"
			     "w_minus_eref_end,vsign_rate,pc_rms_late,vsign_rate_late,"
			     "integrator_error_m,rendered_stiffness,ticks,wall_time_s,port_energy_end,port_energy_min,"
			     "po_error_end,po_error_max,device_energy_end,device_energy_min\n";
	const char *row = "0,1.5,5,0.25,-0.001,-2e-05,3,12.5,1.25,13,0,1000,5001,0.002,1e-3,-4e-4,-2e-5,"
			  "3e-5,2e-3,-1e-7\n";
	popc_chatter_result full = checked_chatter(0.125, 0), none = full;
	none.windows = 0;
	none.lc_ticks = 0;
	const struct {
		const char *run_row;
		const popc_chatter_result *chat;
		int exit_status;
	} cases[] = {
		{row, &full, 0}, {row, &none, 6}, {row, NULL, 1}, {NULL, NULL, 1},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		char buf[POPC_SWEEP_ROW_MAX];
		popc_error err;
		int n = popc_sweep_row(&p, 2, cases[k].exit_status, header, cases[k].run_row,
				       cases[k].chat, 0.5, buf, sizeof buf, &err);
		assert_true(n > 0);
		assert_int_equal(count_cells(buf), popc_sweep_columns_count(1));
		assert_int_equal(popc_sweep_row_exit_status(&p, buf), cases[k].exit_status);
		assert_int_equal(buf[n - 1], '\n');
	}
	popc_sweep_plan_free(&p);
}

/* The row a sweep makes from a run's summary in its own process
 * (popc_sweep_row_of_run) is, byte for byte, the row made from the text that
 * `popc run --summary` writes for it (popc_sweep_row, as for --list runs):
 * with and without the true port energy and the device port's, awkward
 * numbers (subnormal, negative zero, the largest double, integers past
 * 2^53), with and without a detector verdict, and without a summary. */
static void test_row_of_run_is_row_of_text(void **state)
{
	(void)state;
	const char *vary[] = {"operator.speed=0.01,0.02,0.03", "controller.variant=none,improved"};
	popc_sweep_plan p = make_plan(vary, 2);
	char *header = run_summary_header();
	popc_scene s;
	popc_error err;
	assert_int_equal(popc_sweep_run_scene(&p, 3, &s, &err), 0);
	popc_chatter_result chat = checked_chatter(0.125, 3);
	const double awkward[] = {0.0, -0.0, 4.9406564584124654e-324, 1.7976931348623157e308,
				  -2.5e-7, 9007199254740993.0, 0.1, 1e22, -123.456};
	for (int k = 0; k < 12; k++) {
		popc_run_summary sum;
		memset(&sum, 0, sizeof sum);
		double a = awkward[k % 9], b = awkward[(k + 4) % 9];
		sum.ticks = 5001 + k;
		sum.sim_time_s = 5.0;
		sum.wall_time_s = k % 3 ? 0.0123 : 0.0;
		sum.integrator = s.integrator;
		sum.substeps = k;
		sum.integrator_error_m = b;
		sum.metrics.pc_energy_J = a;
		sum.metrics.period_s = 0.001;
		sum.metrics.all.ticks = 5001;
		sum.metrics.all.active_ticks = k * 37;
		sum.metrics.all.pc_max_N = b;
		sum.metrics.all.contact_ticks = 100 + k;
		sum.metrics.all.vsign_changes = 7 * k;
		sum.metrics.w_minus_eref_min_J = b;
		sum.metrics.w_minus_eref_end_J = a;
		sum.metrics.fc_pen_sum_Nm = k % 5 ? 3.25 * k : 0.0;
		sum.metrics.pen_sq_sum_m2 = k % 5 ? 1e-6 * (k + 1) : 0.0;
		sum.has_port_energy = k % 2;
		sum.port_energy_J = a;
		sum.port_energy_min_J = b;
		sum.po_error_end_J = b;
		sum.po_error_max_J = a;
		sum.has_device_energy = (k / 2) % 2;
		sum.device_energy_J = b;
		sum.device_energy_min_J = a;
		sum.status = k % 4 == 3 ? -6 : 0;
		char run_row[POPC_SWEEP_ROW_MAX], text_row[POPC_SWEEP_ROW_MAX], own_row[POPC_SWEEP_ROW_MAX];
		assert_true(popc_run_summary_csv_row_text(&sum, &s, run_row, sizeof run_row) <
			    sizeof run_row);
		const popc_chatter_result *c = k % 3 == 2 ? NULL : &chat;
		int n1 = popc_sweep_row(&p, 3, sum.status ? 6 : 0, header, run_row, c, 0.5, text_row,
					sizeof text_row, &err);
		int n2 = popc_sweep_row_of_run(&p, 3, sum.status ? 6 : 0, &sum, &s, c, 0.5, own_row,
					       sizeof own_row, &err);
		assert_true(n1 > 0);
		assert_int_equal(n1, n2);
		assert_string_equal(text_row, own_row);
	}
	/* no summary: the same empty cells */
	char text_row[POPC_SWEEP_ROW_MAX], own_row[POPC_SWEEP_ROW_MAX];
	int n1 = popc_sweep_row(&p, 4, 1, NULL, NULL, NULL, 0.25, text_row, sizeof text_row, &err);
	int n2 = popc_sweep_row_of_run(&p, 4, 1, NULL, &s, NULL, 0.25, own_row, sizeof own_row, &err);
	assert_true(n1 > 0);
	assert_int_equal(n1, n2);
	assert_string_equal(text_row, own_row);
	free(header);
	popc_sweep_plan_free(&p);
}

/* A popc run summary's cells read back by name. */
static void test_run_csv_cells(void **state)
{
	(void)state;
	const char *header = "variant,status,ticks,wall_time_s\n";
	int status = 0;
	assert_int_equal(popc_sweep_run_csv_status(header, "none,-6,5,0.25\n", &status), 0);
	assert_int_equal(status, -6);
	assert_true(popc_sweep_run_csv_wall_time_s(header, "none,-6,5,0.25\n") == 0.25);
	/* no wall_time_s column, or a row cut short: 0 */
	assert_true(popc_sweep_run_csv_wall_time_s("variant,status\n", "none,0\n") == 0.0);
	assert_true(popc_sweep_run_csv_wall_time_s(header, "none,0\n") == 0.0);
	assert_int_equal(popc_sweep_run_csv_status(header, "none,x,5,0.25\n", &status), -1);
	assert_int_equal(popc_sweep_run_csv_status(header, "none,0,5\n", &status), -1);
}

/* The teleoperation table (issue 26): the one-port columns in their order,
 * then the tele_* columns, then wall_time_s; every tele_* column has a cell
 * function; the one-port table is unchanged by it. */
static void test_teleop_table(void **state)
{
	(void)state;
	int n1, nt;
	const popc_sweep_column *one = popc_sweep_columns_of(0, &n1);
	const popc_sweep_column *tele = popc_sweep_columns_of(1, &nt);
	assert_ptr_equal(one, popc_sweep_columns);
	assert_int_equal(n1, popc_sweep_n_columns);
	assert_true(nt > n1);
	for (int c = 0; c < n1 - 1; c++) /* the same columns, wall_time_s aside */
		assert_ptr_equal(one[c].name, tele[c].name);
	assert_string_equal(tele[nt - 1].name, "wall_time_s");
	popc_run_summary sum;
	memset(&sum, 0, sizeof sum);
	sum.has_teleop = 1;
	for (int c = n1 - 1; c < nt - 1; c++) {
		assert_int_equal(tele[c].source, POPC_SWEEP_CELL_TELEOP);
		assert_memory_equal(tele[c].name, "tele_", 5);
		popc_sweep_teleop_value v;
		assert_int_not_equal(popc_sweep_teleop_cell(tele[c].name, &sum, 0, &v), -1);
	}
	popc_sweep_teleop_value v;
	assert_int_equal(popc_sweep_teleop_cell("pc_rms", &sum, 0, &v), -1);
	char *h1 = popc_sweep_columns_header_of(NULL, 0, 0), *ht = popc_sweep_columns_header_of(NULL, 0, 1);
	char *h0 = popc_sweep_columns_header(NULL, 0);
	assert_string_equal(h0, h1);
	assert_null(strstr(h1, "tele_"));
	assert_non_null(strstr(ht, ",limit_cycle,tele_violations,"));
	assert_int_equal(popc_sweep_columns_count_of(2, 1), popc_sweep_columns_count(2) + nt - n1);
	free(h0);
	free(h1);
	free(ht);
}

/* The tele_* cells, table-driven: a count, a margin, the late peak to peak
 * and the verdict, and when each is empty. */
static void test_teleop_cells(void **state)
{
	(void)state;
	popc_run_summary done, short_run, one_port;
	memset(&done, 0, sizeof done);
	done.has_teleop = 1;
	done.tele_violations = 7;
	done.tele_margin_min_J[1] = -0.25;
	done.tele_xs_late_min_m = 0.001;
	done.tele_xs_late_max_m = 0.0015; /* 0.5 mm: settled */
	short_run = done;
	short_run.tele_xs_late_min_m = (double)INFINITY; /* stopped before its last second */
	short_run.tele_xs_late_max_m = -(double)INFINITY;
	memset(&one_port, 0, sizeof one_port);
	popc_run_summary wide = done;
	wide.tele_xs_late_max_m = 0.0031; /* 2.1 mm: oscillating */
	static const struct {
		const char *name;
		int which, exit_status, has, whole;
		double value;
	} cases[] = {
		{"tele_violations", 0, 0, 1, 1, 7},
		{"tele_margin_min_s", 0, 0, 1, 0, -0.25},
		{"tele_xs_late_pp", 0, 0, 1, 0, 0.0005},
		{"tele_oscillating", 0, 0, 1, 1, 0},
		{"tele_oscillating", 3, 0, 1, 1, 1},
		{"tele_oscillating", 1, 6, 1, 1, 1},  /* diverged: oscillating */
		{"tele_xs_late_pp", 1, 6, 0, 0, 0},   /* no last second */
		{"tele_oscillating", 1, 1, 0, 0, 0},  /* stopped otherwise: no verdict */
		{"tele_oscillating", 0, 1, 0, 0, 0},
		{"tele_violations", 2, 0, 0, 0, 0},   /* a one-port summary */
		{"tele_violations", -1, 0, 0, 0, 0},  /* no summary */
	};
	const popc_run_summary *sums[] = {&done, &short_run, &one_port, &wide};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_sweep_teleop_value v;
		const popc_run_summary *sum = cases[i].which < 0 ? NULL : sums[cases[i].which];
		int has = popc_sweep_teleop_cell(cases[i].name, sum, cases[i].exit_status, &v);
		if (has != cases[i].has)
			fail_msg("case %zu (%s): has %d, expected %d", i, cases[i].name, has, cases[i].has);
		if (!has)
			continue;
		assert_int_equal(v.is_whole, cases[i].whole);
		if (v.is_whole)
			assert_int_equal(v.whole, (long long)cases[i].value);
		else
			assert_true(fabs(v.real - cases[i].value) <= 1e-15);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_header_follows_table),
		cmocka_unit_test(test_metrics_in_run_summary),
		cmocka_unit_test(test_rows_have_header_cells),
		cmocka_unit_test(test_run_csv_cells),
		cmocka_unit_test(test_row_of_run_is_row_of_text),
		cmocka_unit_test(test_teleop_table),
		cmocka_unit_test(test_teleop_cells),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
