/* summary.csv's columns (sweep_columns.h): the table, and what derives from it
 * without a plan (the header, the cell count, where a column is). */
#include "popc/sweep/sweep_columns.h"

#include <stdio.h>
#include <stdlib.h>

#include "popc/run/run.h"

#define RUN_METRIC(name)                                                                           \
	{ name, POPC_SWEEP_CELL_RUN_SUMMARY, POPC_SWEEP_FORMAT_TEXT, POPC_SWEEP_EMPTY_WITHOUT_SUMMARY }

/* The metrics are the compare metrics of a run, by their names in the popc run
 * summary (run_summary.c: popc_run_summary_csv_header); the figures of merit
 * of README, "popc-analyze" (compare). */
#define ONE_PORT_COLUMNS                                                                           \
	{"run", POPC_SWEEP_CELL_RUN_ID, POPC_SWEEP_FORMAT_TEXT, POPC_SWEEP_EMPTY_NEVER},           \
	{NULL, POPC_SWEEP_CELL_AXES, POPC_SWEEP_FORMAT_TEXT, POPC_SWEEP_EMPTY_NEVER},              \
	{"exit_status", POPC_SWEEP_CELL_EXIT_STATUS, POPC_SWEEP_FORMAT_INT, POPC_SWEEP_EMPTY_NEVER}, \
	RUN_METRIC("ticks"),                                                                       \
	RUN_METRIC("pc_rms"),                                                                      \
	RUN_METRIC("pc_max"),                                                                      \
	RUN_METRIC("pc_active"),                                                                   \
	RUN_METRIC("pc_energy"),                                                                   \
	RUN_METRIC("w_minus_eref_min"),                                                            \
	RUN_METRIC("w_minus_eref_end"),                                                            \
	RUN_METRIC("vsign_rate"),                                                                  \
	RUN_METRIC("pc_rms_late"),                                                                 \
	RUN_METRIC("vsign_rate_late"),                                                             \
	RUN_METRIC("integrator_error_m"),                                                          \
	/* the true port energy: empty for an axis without a true position, as                     \
	 * in the run summary */                                                                   \
	RUN_METRIC("port_energy_end"),                                                             \
	RUN_METRIC("port_energy_min"),                                                             \
	RUN_METRIC("po_error_end"),                                                                \
	RUN_METRIC("po_error_max"),                                                                \
	/* the device port's energy: empty where the axis gives no dissipation */                  \
	RUN_METRIC("device_energy_end"),                                                           \
	RUN_METRIC("device_energy_min"),                                                           \
	RUN_METRIC("rendered_stiffness"),                                                          \
	{"chatter_s", POPC_SWEEP_CELL_CHATTER_S, POPC_SWEEP_FORMAT_DOUBLE,                         \
	 POPC_SWEEP_EMPTY_CHATTER_UNCHECKED},                                                      \
	{"chatter_intervals", POPC_SWEEP_CELL_CHATTER_INTERVALS, POPC_SWEEP_FORMAT_INT,            \
	 POPC_SWEEP_EMPTY_CHATTER_UNCHECKED},                                                      \
	{"limit_cycle", POPC_SWEEP_CELL_LIMIT_CYCLE, POPC_SWEEP_FORMAT_INT,                        \
	 POPC_SWEEP_EMPTY_LC_UNCHECKED}

#define WALL_TIME_COLUMN                                                                           \
	{"wall_time_s", POPC_SWEEP_CELL_WALL_TIME_S, POPC_SWEEP_FORMAT_DOUBLE, POPC_SWEEP_EMPTY_NEVER}

const popc_sweep_column popc_sweep_columns[] = {ONE_PORT_COLUMNS, WALL_TIME_COLUMN};
const int popc_sweep_n_columns = (int)(sizeof popc_sweep_columns / sizeof popc_sweep_columns[0]);

#define TELEOP_COLUMN(name, format)                                                                \
	{ name, POPC_SWEEP_CELL_TELEOP, format, POPC_SWEEP_EMPTY_WITHOUT_SUMMARY }

/* A teleoperation sweep's: the one-port columns (the master's, as its log's),
 * then the run summary's two-port figures (sweep_teleop.h, docs/SWEEPS.md),
 * then the wall time, last as in every sweep. */
static const popc_sweep_column teleop_columns[] = {
	ONE_PORT_COLUMNS,
	TELEOP_COLUMN("tele_violations", POPC_SWEEP_FORMAT_INT),
	TELEOP_COLUMN("tele_margin_min_m", POPC_SWEEP_FORMAT_DOUBLE),
	TELEOP_COLUMN("tele_margin_min_s", POPC_SWEEP_FORMAT_DOUBLE),
	TELEOP_COLUMN("tele_active_m", POPC_SWEEP_FORMAT_INT),
	TELEOP_COLUMN("tele_active_s", POPC_SWEEP_FORMAT_INT),
	TELEOP_COLUMN("tele_clamped_m", POPC_SWEEP_FORMAT_INT),
	TELEOP_COLUMN("tele_clamped_s", POPC_SWEEP_FORMAT_INT),
	TELEOP_COLUMN("tele_f_c_max", POPC_SWEEP_FORMAT_DOUBLE),
	TELEOP_COLUMN("tele_v_c_max", POPC_SWEEP_FORMAT_DOUBLE),
	TELEOP_COLUMN("tele_drift_end", POPC_SWEEP_FORMAT_DOUBLE),
	TELEOP_COLUMN("tele_xs_late_pp", POPC_SWEEP_FORMAT_DOUBLE),
	TELEOP_COLUMN("tele_oscillating", POPC_SWEEP_FORMAT_INT),
	WALL_TIME_COLUMN,
};

const popc_sweep_column *popc_sweep_columns_of(int teleop, int *n)
{
	if (teleop) {
		*n = (int)(sizeof teleop_columns / sizeof teleop_columns[0]);
		return teleop_columns;
	}
	*n = popc_sweep_n_columns;
	return popc_sweep_columns;
}

char *popc_sweep_columns_header(const popc_sweep_axis *axes, int n_axes)
{
	return popc_sweep_columns_header_of(axes, n_axes, 0);
}

char *popc_sweep_columns_header_of(const popc_sweep_axis *axes, int n_axes, int teleop)
{
	int n_columns;
	const popc_sweep_column *columns = popc_sweep_columns_of(teleop, &n_columns);
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	if (!f)
		return NULL;
	int cells = 0;
	for (int c = 0; c < n_columns; c++) {
		const popc_sweep_column *col = &columns[c];
		if (col->source != POPC_SWEEP_CELL_AXES) {
			fprintf(f, "%s%s", cells++ ? "," : "", col->name);
			continue;
		}
		for (int a = 0; a < n_axes; a++)
			fprintf(f, "%s%s.%s", cells++ ? "," : "", axes[a].section, axes[a].key);
	}
	fputc('\n', f);
	if (fclose(f) != 0) {
		free(text);
		return NULL;
	}
	return text;
}

int popc_sweep_columns_count(int n_axes)
{
	return popc_sweep_columns_count_of(n_axes, 0);
}

int popc_sweep_columns_count_of(int n_axes, int teleop)
{
	int n_columns;
	const popc_sweep_column *columns = popc_sweep_columns_of(teleop, &n_columns);
	int n = 0;
	for (int c = 0; c < n_columns; c++)
		n += columns[c].source == POPC_SWEEP_CELL_AXES ? n_axes : 1;
	return n;
}

int popc_sweep_column_index(int n_axes, popc_sweep_cell_source source)
{
	int cell = 0;
	for (int c = 0; c < popc_sweep_n_columns; c++) {
		if (popc_sweep_columns[c].source == source)
			return cell;
		cell += popc_sweep_columns[c].source == POPC_SWEEP_CELL_AXES ? n_axes : 1;
	}
	return -1;
}

void popc_sweep_columns_json_kinds(int n_axes, popc_json_kind *kinds)
{
	popc_sweep_columns_json_kinds_of(n_axes, 0, kinds);
}

void popc_sweep_columns_json_kinds_of(int n_axes, int teleop, popc_json_kind *kinds)
{
	int n_columns;
	const popc_sweep_column *columns = popc_sweep_columns_of(teleop, &n_columns);
	int cell = 0;
	for (int c = 0; c < n_columns; c++) {
		const popc_sweep_column *col = &columns[c];
		switch (col->source) {
		case POPC_SWEEP_CELL_AXES:
			for (int a = 0; a < n_axes; a++)
				kinds[cell++] = POPC_JSON_AUTO;
			continue;
		case POPC_SWEEP_CELL_RUN_SUMMARY: kinds[cell] = popc_run_summary_json_kind(col->name); break;
		default:
			kinds[cell] = col->format == POPC_SWEEP_FORMAT_TEXT ? POPC_JSON_TEXT : POPC_JSON_NUMBER;
		}
		cell++;
	}
}
