/* A run's summary row (sweep_row.h): made by walking the column table
 * (sweep_columns.h), and read back. */
#include "popc/sweep/sweep_row.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/run/run.h"
#include "popc/sweep/sweep_teleop.h"
#include "popc/util/numfmt.h"
#include "popc/util/parse.h"
#include "popc/util/text_builder.h"

int popc_sweep_split_cells(const char *line, const char **cell, size_t *len, int max)
{
	int n = 0;
	const char *p = line;
	for (;;) {
		/* a loop, not strcspn: cells are a few bytes, and strcspn's setup
		 * was most of the split (twice a run in a sweep) */
		size_t l = 0;
		while (p[l] && p[l] != ',' && p[l] != '\r' && p[l] != '\n')
			l++;
		if (n < max) {
			cell[n] = p;
			len[n] = l;
		}
		n++;
		if (p[l] != ',')
			break;
		p += l + 1;
	}
	return n;
}

static int find_cell(const char *const *cell, const size_t *len, int n, const char *name)
{
	size_t nl = strlen(name);
	for (int c = 0; c < n; c++)
		if (len[c] == nl && memcmp(cell[c], name, nl) == 0)
			return c;
	return -1;
}

#define RUN_CSV_MAX_COLUMNS 64

/* What a row is made from: run i of the plan and what its run gave. */
typedef struct row_input {
	const char *id;
	int exit_status;
	/* the run summary: its CSV text split into cells (run_row, hcell,
	 * rcell), or the summary itself (sum, scene); neither: none */
	const char *run_row;
	const popc_run_summary *sum;
	const popc_scene *scene;
	const char *const *hcell, *const *rcell;
	const size_t *hlen, *rlen;
	int n_cells;
	int *cell_of_column; /* kept header cells by sweep column, or NULL */
	int column;          /* the index of the column being made (make_row): the
			      * one-port columns have the same in both tables */
	const popc_chatter_result *chatter; /* NULL: no detector result */
	double wall_time_s;
} row_input;

/* A cell's value: text, a whole number or a double, as its source gives it. */
typedef struct cell_value {
	popc_sweep_cell_format kind;
	const char *text;
	size_t len;
	int whole;
	double real;
} cell_value;

static int cell_is_empty(popc_sweep_cell_empty rule, const row_input *in)
{
	switch (rule) {
	case POPC_SWEEP_EMPTY_NEVER: return 0;
	case POPC_SWEEP_EMPTY_WITHOUT_SUMMARY: return !in->run_row && !in->sum;
	case POPC_SWEEP_EMPTY_CHATTER_UNCHECKED:
		return !(in->chatter && popc_chatter_checked(in->chatter));
	case POPC_SWEEP_EMPTY_LC_UNCHECKED:
		return !(in->chatter && popc_chatter_lc_checked(in->chatter));
	}
	return 1;
}

/* An admittance run's pc_* cells are its parallel PC's (docs/SWEEPS.md,
 * "Admittance scenes"): pc_active, pc_rms, pc_max, pc_rms_late read the run
 * summary's v_pc_active, v_pc_rms, v_pc_max, v_pc_rms_late (m/s), whose
 * series PC cells are 0. Returns that summary column's name, or NULL. */
static const char *admittance_pc_column(const char *name)
{
	static const char *const map[][2] = {
		{"pc_active", "v_pc_active"},
		{"pc_rms", "v_pc_rms"},
		{"pc_max", "v_pc_max"},
		{"pc_rms_late", "v_pc_rms_late"},
	};
	for (size_t i = 0; name && i < sizeof map / sizeof map[0]; i++)
		if (strcmp(name, map[i][0]) == 0)
			return map[i][1];
	return NULL;
}

/* The same from the summary itself; 1 when name is one of them. */
static int admittance_pc_value(const popc_run_summary *sum, const char *name, double *v)
{
	const char *adm = sum->has_admittance ? admittance_pc_column(name) : NULL;
	if (!adm)
		return 0;
	*v = strcmp(adm, "v_pc_active") == 0 ? sum->adm_active
	     : strcmp(adm, "v_pc_rms") == 0  ? sum->adm_v_pc_rms_mps
	     : strcmp(adm, "v_pc_max") == 0  ? sum->adm_v_pc_max_mps
					     : sum->adm_v_pc_rms_late_mps;
	return 1;
}

/* The value of a one-cell column (every source but the axes). */
static int cell_get(const popc_sweep_column *col, const row_input *in, cell_value *v,
		    popc_error *err)
{
	memset(v, 0, sizeof *v);
	v->kind = POPC_SWEEP_FORMAT_INT;
	switch (col->source) {
	case POPC_SWEEP_CELL_RUN_ID:
		v->kind = POPC_SWEEP_FORMAT_TEXT;
		v->text = in->id;
		v->len = strlen(in->id);
		return 0;
	case POPC_SWEEP_CELL_EXIT_STATUS: v->whole = in->exit_status; return 0;
	case POPC_SWEEP_CELL_RUN_SUMMARY: {
		int *known = in->cell_of_column ? &in->cell_of_column[in->column] : NULL;
		/* found by name once per header kept (split_header) */
		int c = known && *known >= 0 ? *known : -1;
		if (c < 0 && admittance_pc_column(col->name)) /* an admittance run's summary */
			c = find_cell(in->hcell, in->hlen, in->n_cells, admittance_pc_column(col->name));
		if (c < 0)
			c = find_cell(in->hcell, in->hlen, in->n_cells, col->name);
		if (c >= 0 && known)
			*known = c;
		if (c < 0)
			return popc_error_set(err, POPC_ERR_INVALID, "run summary: no column '%s'",
					      col->name);
		v->kind = POPC_SWEEP_FORMAT_TEXT;
		v->text = in->rcell[c];
		v->len = in->rlen[c];
		return 0;
	}
	case POPC_SWEEP_CELL_CHATTER_S:
		v->kind = POPC_SWEEP_FORMAT_DOUBLE;
		v->real = in->chatter->chatter_s;
		return 0;
	case POPC_SWEEP_CELL_CHATTER_INTERVALS: v->whole = in->chatter->n_intervals; return 0;
	case POPC_SWEEP_CELL_LIMIT_CYCLE: v->whole = in->chatter->limit_cycle; return 0;
	case POPC_SWEEP_CELL_WALL_TIME_S:
		v->kind = POPC_SWEEP_FORMAT_DOUBLE;
		v->real = in->wall_time_s;
		return 0;
	case POPC_SWEEP_CELL_AXES:
	case POPC_SWEEP_CELL_TELEOP: break;
	}
	return popc_error_set(err, POPC_ERR_INVALID, "summary column %s: no single value",
			      col->name ? col->name : "(axes)");
}

/* The run summary's header split into cells, kept: every run of a sweep has
 * the same header (the summary's fields), and splitting it for every row was
 * a twentieth of a sweep's own CPU. Checked against the header given by its
 * text (one strcmp), so any other header is split anew; per thread. */
enum { HEADER_TEXT_MAX = 2048, SWEEP_COLUMNS_MAX = 64 };
typedef struct header_cells {
	char text[HEADER_TEXT_MAX];
	const char *cell[RUN_CSV_MAX_COLUMNS];
	size_t len[RUN_CSV_MAX_COLUMNS];
	int n; /* 0: nothing kept */
	/* the header cell of sweep column c (popc_sweep_columns[c]), found
	 * by name once: -1 not yet */
	int cell_of_column[SWEEP_COLUMNS_MAX];
} header_cells;

/* The cells of header: kept ones when it is the header kept, else split
 * into (cell, len), and kept when it fits. Returns the count of cells. */
static int split_header(const char *header, const char *const **cell, const size_t **len,
			int **cell_of_column, const char **own_cell, size_t *own_len)
{
	static _Thread_local header_cells kept;
	*cell_of_column = NULL;
	if (kept.n > 0 && strcmp(kept.text, header) == 0) {
		*cell = kept.cell;
		*len = kept.len;
		*cell_of_column = popc_sweep_n_columns <= SWEEP_COLUMNS_MAX ? kept.cell_of_column : NULL;
		return kept.n;
	}
	size_t hl = strlen(header);
	int n;
	if (hl < sizeof kept.text) {
		memcpy(kept.text, header, hl + 1);
		n = popc_sweep_split_cells(kept.text, kept.cell, kept.len, RUN_CSV_MAX_COLUMNS);
		kept.n = n <= RUN_CSV_MAX_COLUMNS ? n : 0;
		for (int c = 0; c < SWEEP_COLUMNS_MAX; c++)
			kept.cell_of_column[c] = -1;
		*cell = kept.cell;
		*len = kept.len;
		if (kept.n > 0 && popc_sweep_n_columns <= SWEEP_COLUMNS_MAX)
			*cell_of_column = kept.cell_of_column;
		return n;
	}
	n = popc_sweep_split_cells(header, own_cell, own_len, RUN_CSV_MAX_COLUMNS);
	*cell = own_cell;
	*len = own_len;
	return n;
}

/* The summary field of sweep column c (a RUN_SUMMARY column), found by name
 * once per thread; -1: the summary has no such field. */
static int summary_field_of_column(int c)
{
	static _Thread_local signed char field[SWEEP_COLUMNS_MAX];
	static _Thread_local int known;
	if (popc_sweep_n_columns > SWEEP_COLUMNS_MAX)
		return popc_run_summary_field(popc_sweep_columns[c].name);
	if (!known) {
		for (int k = 0; k < popc_sweep_n_columns; k++)
			field[k] = (signed char)(popc_sweep_columns[k].source == POPC_SWEEP_CELL_RUN_SUMMARY
							 ? popc_run_summary_field(popc_sweep_columns[k].name)
							 : -1);
		known = 1;
	}
	return field[c];
}

/* The row of in's run (in->id is set here) into buf, by the column table. */
static int make_row(const popc_sweep_plan *p, long long i, row_input *in, char *buf, size_t cap,
		    popc_error *err)
{
	char id[POPC_SWEEP_ID_MAX];
	popc_sweep_run_id(p, i, id);
	in->id = id;
	int idx[POPC_SWEEP_AXES_MAX];
	popc_sweep_run_values(p, i, idx);
	popc_text_builder t = {.buf = buf, .cap = cap, .len = 0};
	int cells = 0, n_columns;
	const popc_sweep_column *columns = popc_sweep_columns_of(p->teleop, &n_columns);
	for (int c = 0; c < n_columns; c++) {
		const popc_sweep_column *col = &columns[c];
		if (col->source == POPC_SWEEP_CELL_AXES) {
			for (int a = 0; a < p->n_axes; a++) {
				if (cells++)
					popc_text_put(&t, ",", 1);
				const char *v = p->axes[a].values[idx[a]];
				popc_text_put(&t, v, strlen(v));
			}
			continue;
		}
		if (cells++)
			popc_text_put(&t, ",", 1);
		if (cell_is_empty(col->empty, in))
			continue;
		if (col->source == POPC_SWEEP_CELL_TELEOP) {
			/* from the summary itself: popc run's CSV row has no
			 * tele_* cells (a teleoperation sweep refuses --list) */
			if (!in->sum)
				return popc_error_set(err, POPC_ERR_INVALID,
						      "summary column %s: a teleoperation run's "
						      "figures come from its summary in this process",
						      col->name);
			popc_sweep_teleop_value v;
			int has = popc_sweep_teleop_cell(col->name, in->sum, in->exit_status, &v);
			if (has < 0)
				return popc_error_set(err, POPC_ERR_INVALID, "summary column %s: no such "
						      "teleoperation figure", col->name);
			if (has && v.is_whole)
				popc_text_put_integer(&t, v.whole);
			else if (has)
				popc_text_put_double_point(&t, v.real);
			continue;
		}
		if (col->source == POPC_SWEEP_CELL_RUN_SUMMARY && in->sum) {
			/* the summary's own cell text, not its whole row made
			 * and split again */
			double adm;
			if (admittance_pc_value(in->sum, col->name, &adm)) {
				popc_text_put_double_point(&t, adm);
				continue;
			}
			int f = summary_field_of_column(c);
			if (f < 0)
				return popc_error_set(err, POPC_ERR_INVALID, "run summary: no column '%s'",
						      col->name);
			popc_run_summary_put_cell(&t, in->sum, in->scene, f);
			continue;
		}
		cell_value v;
		in->column = c;
		int st = cell_get(col, in, &v, err);
		if (st)
			return st;
		/* a format that does not fit the source's value is a mistake in
		 * the table, not a cell to guess */
		if (v.kind != col->format && !(v.kind == POPC_SWEEP_FORMAT_INT &&
					       col->format == POPC_SWEEP_FORMAT_DOUBLE))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "summary column %s: its format does not fit its source",
					      col->name);
		switch (col->format) {
		case POPC_SWEEP_FORMAT_TEXT: popc_text_put(&t, v.text, v.len); break;
		case POPC_SWEEP_FORMAT_INT: popc_text_put_integer(&t, v.whole); break;
		case POPC_SWEEP_FORMAT_DOUBLE:
			/* with a point ("0.0"): readers type the column floating point */
			popc_text_put_double_point(&t, v.kind == POPC_SWEEP_FORMAT_INT ? (double)v.whole
										   : v.real);
			break;
		}
	}
	popc_text_put(&t, "\n", 1);
	size_t len = t.len;
	if (len >= cap) {
		if (cap > 0)
			buf[cap - 1] = '\0'; /* as snprintf leaves it */
		return popc_error_set(err, POPC_ERR_INVALID, "summary row of run %s longer than %zu bytes",
				      id, cap);
	}
	buf[len] = '\0';
	return (int)len;
}

int popc_sweep_row(const popc_sweep_plan *p, long long i, int exit_status, const char *run_header,
		   const char *run_row, const popc_chatter_result *chatter, double wall_time_s,
		   char *buf, size_t cap, popc_error *err)
{
	const char *own_hcell[RUN_CSV_MAX_COLUMNS], *rcell[RUN_CSV_MAX_COLUMNS];
	size_t own_hlen[RUN_CSV_MAX_COLUMNS], rlen[RUN_CSV_MAX_COLUMNS];
	const char *const *hcell = own_hcell;
	const size_t *hlen = own_hlen;
	int *cell_of_column = NULL;
	int nh = 0, nr = 0;
	if (run_row) {
		nh = split_header(run_header, &hcell, &hlen, &cell_of_column, own_hcell, own_hlen);
		nr = popc_sweep_split_cells(run_row, rcell, rlen, RUN_CSV_MAX_COLUMNS);
		if (nh > RUN_CSV_MAX_COLUMNS || nr != nh)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "run summary: %d cells in the row, %d in the header", nr, nh);
	}
	row_input in = {.exit_status = exit_status, .run_row = run_row, .hcell = hcell,
			.rcell = rcell, .hlen = hlen, .rlen = rlen, .n_cells = nh,
			.cell_of_column = cell_of_column, .chatter = chatter,
			.wall_time_s = wall_time_s};
	return make_row(p, i, &in, buf, cap, err);
}

int popc_sweep_row_of_run(const popc_sweep_plan *p, long long i, int exit_status,
			  const popc_run_summary *sum, const popc_scene *s,
			  const popc_chatter_result *chatter, double wall_time_s, char *buf, size_t cap,
			  popc_error *err)
{
	row_input in = {.exit_status = exit_status, .sum = sum, .scene = s, .chatter = chatter,
			.wall_time_s = wall_time_s};
	return make_row(p, i, &in, buf, cap, err);
}

int popc_sweep_row_check(const popc_sweep_plan *p, long long i, const char *row, size_t len,
			 popc_error *err)
{
	int idx[POPC_SWEEP_AXES_MAX];
	popc_sweep_run_values(p, i, idx);
	const char *cell = row, *end = row + len;
	int c = 0, n_columns;
	const popc_sweep_column *columns = popc_sweep_columns_of(p->teleop, &n_columns);
	for (int k = 0; k < n_columns; k++) {
		const popc_sweep_column *col = &columns[k];
		int n = col->source == POPC_SWEEP_CELL_AXES ? p->n_axes : 1;
		for (int a = 0; a < n; a++, c++) {
			if (cell > end)
				return popc_error_set(err, POPC_ERR_INVALID, "%d cells, a row has %d", c,
						      popc_sweep_columns_count_of(p->n_axes, p->teleop));
			const char *stop = memchr(cell, ',', (size_t)(end - cell));
			if (!stop)
				stop = end;
			size_t cl = (size_t)(stop - cell);
			if (col->source == POPC_SWEEP_CELL_AXES) {
				const char *v = p->axes[a].values[idx[a]];
				if (strlen(v) != cl || memcmp(v, cell, cl) != 0)
					return popc_error_set(err, POPC_ERR_INVALID,
							      "column %s.%s: '%.*s', but the plan's value "
							      "of this run is '%s'",
							      p->axes[a].section, p->axes[a].key,
							      (int)(cl > 64 ? 64 : cl), cell, v);
			} else if (col->source != POPC_SWEEP_CELL_RUN_ID && cl > 0) {
				double v;
				if (popc_parse_double_exact(cell, stop, &v) != POPC_PARSE_OK)
					return popc_error_set(err, POPC_ERR_INVALID,
							      "column %s: '%.*s' is not a finite number "
							      "(decimal, no nan or inf)",
							      col->name, (int)(cl > 64 ? 64 : cl), cell);
			}
			cell = stop + 1;
		}
	}
	if (cell <= end)
		return popc_error_set(err, POPC_ERR_INVALID, "more cells than a row's %d",
				      popc_sweep_columns_count_of(p->n_axes, p->teleop));
	return 0;
}

int popc_sweep_row_exit_status(const popc_sweep_plan *p, const char *row)
{
	/* cell c found by its commas, the row not split: the parent reads
	 * every run's row this way, twice a sweep */
	int c = popc_sweep_column_index(p->n_axes, POPC_SWEEP_CELL_EXIT_STATUS);
	if (c < 0 || c >= RUN_CSV_MAX_COLUMNS + 64)
		return -1;
	const char *cell = row;
	for (int k = 0; k < c; k++) {
		while (*cell && *cell != ',' && *cell != '\r' && *cell != '\n')
			cell++;
		if (*cell != ',')
			return -1; /* fewer cells than c + 1 */
		cell++;
	}
	const char *end = cell;
	while (*end && *end != ',' && *end != '\r' && *end != '\n')
		end++;
	long long v;
	if (popc_parse_ll_span(cell, end, 0, 999, 0, &v) != 0)
		return -1;
	return (int)v;
}

int popc_sweep_run_csv_status(const char *run_header, const char *run_row, int *status)
{
	const char *hcell[RUN_CSV_MAX_COLUMNS], *rcell[RUN_CSV_MAX_COLUMNS];
	size_t hlen[RUN_CSV_MAX_COLUMNS], rlen[RUN_CSV_MAX_COLUMNS];
	int nh = popc_sweep_split_cells(run_header, hcell, hlen, RUN_CSV_MAX_COLUMNS);
	int nr = popc_sweep_split_cells(run_row, rcell, rlen, RUN_CSV_MAX_COLUMNS);
	if (nh > RUN_CSV_MAX_COLUMNS || nr != nh)
		return -1;
	int c = find_cell(hcell, hlen, nh, "status");
	long long v;
	if (c < 0 || popc_parse_ll_span(rcell[c], rcell[c] + rlen[c], INT_MIN, INT_MAX, 0, &v) != 0)
		return -1;
	*status = (int)v;
	return 0;
}

double popc_sweep_run_csv_wall_time_s(const char *run_header, const char *run_row)
{
	const char *hcell[RUN_CSV_MAX_COLUMNS], *rcell[RUN_CSV_MAX_COLUMNS];
	size_t hlen[RUN_CSV_MAX_COLUMNS], rlen[RUN_CSV_MAX_COLUMNS];
	int nh = popc_sweep_split_cells(run_header, hcell, hlen, RUN_CSV_MAX_COLUMNS);
	int nr = popc_sweep_split_cells(run_row, rcell, rlen, RUN_CSV_MAX_COLUMNS);
	int c = find_cell(hcell, hlen, nh < RUN_CSV_MAX_COLUMNS ? nh : RUN_CSV_MAX_COLUMNS,
			  "wall_time_s");
	double wall_s = 0.0;
	if (c >= 0 && c < nr)
		popc_parse_double_span(rcell[c], rcell[c] + rlen[c], &wall_s);
	return wall_s;
}
