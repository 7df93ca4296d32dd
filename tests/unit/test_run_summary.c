/* The run summary's CSV header and row (src/run/run.c, one field table):
 * the same number of cells for every kind of axis and way a run ends, each
 * cell of the row a name or a finite number, the header as popc has always
 * written it. */
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
#include "popc/run/run.h"
#include "popc/util/numfmt.h"

/* A drive-like axis: no simulated plant (x_true NaN, integrator error
 * unknown to it), measured period and round trip, a count that steps; it
 * fails with fail_status at exchange fail_at (never when fail_at < 0), or
 * already at start when fail_at == 0. */
typedef struct drive {
	long long count;
	int exchanges, fail_at, fail_status;
} drive;

static int drive_start(popc_axis *a, popc_error *err)
{
	drive *d = a->priv;
	if (d->fail_at == 0)
		return popc_error_set(err, d->fail_status, "drive: no answer at start");
	return 0;
}

static int drive_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	(void)err;
	drive *d = a->priv;
	out->count = d->count;
	out->x_true_m = (double)NAN;
	out->dt_s = 1e-3;
	out->rtt_s = 2.5e-4;
	return 0;
}

static int drive_exchange(popc_axis *a, double f_c_N, popc_axis_sample *next, popc_error *err)
{
	(void)f_c_N;
	drive *d = a->priv;
	if (++d->exchanges == d->fail_at)
		return popc_error_set(err, d->fail_status, "drive: lost at exchange %d", d->exchanges);
	d->count += (d->exchanges / 50) % 2 ? -1 : 1; /* back and forth: the PC has work */
	return drive_sample(a, next, err);
}

static int drive_stop(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

static const popc_axis_ops drive_ops = {
	.name = "modbus",
	.log_columns = POPC_LOG_COL_TIMING,
	.start = drive_start,
	.sample = drive_sample,
	.exchange = drive_exchange,
	.stop = drive_stop,
};

/* Splits a line (newline included) at commas into cells; returns their count. */
static int split_cells(char *line, char **cells, int max)
{
	size_t len = strlen(line);
	assert_true(len > 0 && line[len - 1] == '\n');
	line[len - 1] = '\0';
	int n = 0;
	for (char *p = line;; p++) {
		assert_true(n < max);
		cells[n++] = p;
		p = strchr(p, ',');
		if (!p)
			return n;
		*p = '\0';
	}
}

/* The summary's header and row for a run; checks them against each other. */
static void check_summary(const char *what, const popc_run_summary *sum, const popc_scene *s)
{
	char *header = NULL, *row = NULL;
	size_t header_len, row_len;
	FILE *f = open_memstream(&header, &header_len);
	assert_non_null(f);
	popc_run_summary_csv_header(f);
	assert_int_equal(fclose(f), 0);
	f = open_memstream(&row, &row_len);
	assert_non_null(f);
	popc_run_summary_csv_row(sum, s, f);
	assert_int_equal(fclose(f), 0);

	/* the column order of every summary file written so far */
	assert_string_equal(header,
			    "variant,integrator,substeps,status,ticks,sim_time_s,wall_time_s,"
			    "realtime_factor,ns_per_tick,integrator_error_m,pc_active,pc_rms,pc_max,"
			    "pc_rms_late,pc_energy,w_minus_eref_min,w_minus_eref_end,vsign_rate,"
			    "vsign_rate_late,port_energy_end,port_energy_min,po_error_end,po_error_max,"
			    "device_energy_end,device_energy_min,rendered_stiffness\n");
	enum { MAX_CELLS = 64 };
	char *names[MAX_CELLS], *cells[MAX_CELLS];
	const int n_names = split_cells(header, names, MAX_CELLS);
	const int n_cells = split_cells(row, cells, MAX_CELLS);
	if (n_cells != n_names)
		fail_msg("%s: %d header names, %d row cells", what, n_names, n_cells);
	assert_string_equal(cells[0], popc_variant_name(s->variant));
	assert_string_equal(cells[1], popc_integrator_name(sum->integrator));
	for (int i = 2; i < n_cells; i++) {
		double v;
		const char *end = cells[i] + strlen(cells[i]);
		/* the true port energy: a number with a true position, else an
		 * empty cell (never NaN, never a 0 that reads as "no error") */
		if (strncmp(names[i], "port_energy", 11) == 0 || strncmp(names[i], "po_error", 8) == 0) {
			if (!sum->has_port_energy) {
				if (cells[i][0] != '\0')
					fail_msg("%s: %s = '%s' without a true position", what, names[i],
						 cells[i]);
				continue;
			}
		}
		/* the device port's energy: a number where the axis gave the
		 * plant's dissipation, else an empty cell */
		if (strncmp(names[i], "device_energy", 13) == 0 && !sum->has_device_energy) {
			if (cells[i][0] != '\0')
				fail_msg("%s: %s = '%s' without a dissipation", what, names[i], cells[i]);
			continue;
		}
		if (popc_parse_double(cells[i], end, &v) != (size_t)(end - cells[i]) || !isfinite(v))
			fail_msg("%s: %s = '%s' is no finite number", what, names[i], cells[i]);
	}
	assert_int_equal(strtoll(cells[3], NULL, 10), sum->status);
	assert_int_equal(strtoll(cells[4], NULL, 10), sum->ticks);
	free(header);
	free(row);

	/* the human summary names the same run */
	char *human = NULL;
	size_t human_len;
	f = open_memstream(&human, &human_len);
	assert_non_null(f);
	popc_run_summary_print(sum, s, f);
	assert_int_equal(fclose(f), 0);
	char want[128];
	snprintf(want, sizeof want, "variant %s, %lld ticks", popc_variant_name(s->variant),
		 sum->ticks);
	if (!strstr(human, want))
		fail_msg("%s: the human summary lacks '%s':\n%s", what, want, human);
	free(human);
}

static void paper_scene(popc_scene *s, popc_integrator method)
{
	popc_scene_defaults(s);
	s->duration_s = 0.5;
	s->integrator = method;
	if (method != POPC_INTEGRATOR_EXACT)
		s->substeps = 10;
}

/* The simulated axis, exact and with a fixed-step integrator (an integrator
 * error cell of its own), and a zero-length run. */
static void test_sim_axis(void **state)
{
	(void)state;
	const popc_integrator methods[] = {POPC_INTEGRATOR_EXACT, POPC_INTEGRATOR_RK4};
	for (int k = 0; k < 2; k++)
		for (int zero = 0; zero < 2; zero++) {
			popc_scene s;
			paper_scene(&s, methods[k]);
			if (zero)
				s.duration_s = 0.0;
			popc_axis *axis;
			popc_error err;
			if (popc_sim_axis_create(&axis, &s, &err) != 0)
				fail_msg("%s", err.msg);
			popc_run_summary sum;
			assert_int_equal(popc_run(&s, axis, NULL, &sum, &err), 0);
			popc_axis_destroy(&axis);
			assert_int_equal(sum.ticks, zero ? 1 : 501);
			char what[64];
			snprintf(what, sizeof what, "sim %s%s", popc_integrator_name(methods[k]),
				 zero ? " 0 s" : "");
			check_summary(what, &sum, &s);
			assert_true(sum.has_port_energy);
			/* W(0) = E_port(0) = 0: a zero-length run has no error */
			if (zero)
				assert_true(sum.po_error_max_J == 0.0 && sum.port_energy_J == 0.0);
			else
				assert_true(sum.po_error_max_J >= fabs(sum.po_error_end_J));
		}
}

/* A drive-like axis: a whole run, one lost at the 100th exchange (status
 * set, fewer ticks) and one whose start fails (no tick). */
static void test_drive_axis(void **state)
{
	(void)state;
	const int fail_at[] = {-1, 100, 0};
	for (int k = 0; k < 3; k++) {
		popc_scene s;
		paper_scene(&s, POPC_INTEGRATOR_EXACT);
		drive d = {.fail_at = fail_at[k], .fail_status = POPC_ERR_COMM};
		popc_axis axis = {.ops = &drive_ops, .priv = &d};
		popc_run_summary sum;
		popc_error err;
		const int st = popc_run(&s, &axis, NULL, &sum, &err);
		assert_int_equal(st, fail_at[k] < 0 ? 0 : POPC_ERR_COMM);
		assert_int_equal(sum.status, st);
		assert_int_equal(sum.ticks, fail_at[k] < 0 ? 501 : fail_at[k]);
		char what[64];
		snprintf(what, sizeof what, "drive failing at %d", fail_at[k]);
		assert_false(sum.has_port_energy);
		check_summary(what, &sum, &s);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_sim_axis),
		cmocka_unit_test(test_drive_axis),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
