/* Stability maps (sweep_map.h): the criteria, the log-K grid and the
 * search of one line (a scan, then bisection of its first failure and of
 * the band's top), replayed from the verdicts known so far. */
#include "popc/sweep/sweep_map.h"

#include <math.h>
#include <string.h>

#include "popc/sweep/sweep_row.h"
#include "popc/util/parse.h"

static const char *const criterion_names[POPC_MAP_N_CRITERIA] = {
	[POPC_MAP_DIVERGED] = "diverged",
	[POPC_MAP_LIMIT_CYCLE] = "limit-cycle",
	[POPC_MAP_CHATTER] = "chatter",
	[POPC_MAP_PASSIVE] = "passive",
	[POPC_MAP_DEVICE_PASSIVE] = "device-passive",
	[POPC_MAP_STABLE] = "stable",
};

const char *popc_map_criterion_name(popc_map_criterion c)
{
	return c >= 0 && c < POPC_MAP_N_CRITERIA ? criterion_names[c] : "?";
}

int popc_map_criteria_parse(const char *text, unsigned *set, popc_error *err)
{
	*set = 0;
	const char *p = text;
	for (;;) {
		size_t l = strcspn(p, ",");
		int found = -1;
		for (int c = 0; c < POPC_MAP_N_CRITERIA; c++)
			if (strlen(criterion_names[c]) == l && memcmp(p, criterion_names[c], l) == 0)
				found = c;
		if (found < 0)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "--criterion '%.*s': not a criterion (allowed: diverged, "
					      "limit-cycle, chatter, passive, device-passive, "
					      "stable, comma-separated)",
					      (int)l, p);
		*set |= 1u << found;
		if (p[l] != ',')
			break;
		p += l + 1;
	}
	return 0;
}

/* ---- a row's facts ------------------------------------------------------------ */

enum { MAX_CELLS = 512 };

static int header_index(const popc_sweep_plan *p, const char *name)
{
	const char *cell[MAX_CELLS];
	size_t len[MAX_CELLS];
	int n = popc_sweep_split_cells(p->columns, cell, len, MAX_CELLS);
	size_t nl = strlen(name);
	for (int c = 0; c < n && c < MAX_CELLS; c++)
		if (len[c] == nl && memcmp(cell[c], name, nl) == 0)
			return c;
	return -1;
}

int popc_map_facts_from_row(const popc_sweep_plan *p, const char *row, popc_map_facts *f,
			    popc_error *err)
{
	memset(f, 0, sizeof *f);
	const char *cell[MAX_CELLS];
	size_t len[MAX_CELLS];
	int n = popc_sweep_split_cells(row, cell, len, MAX_CELLS);
	int c_exit = header_index(p, "exit_status"), c_lc = header_index(p, "limit_cycle");
	int c_ch = header_index(p, "chatter_s"), c_port = header_index(p, "port_energy_min");
	int c_dev = header_index(p, "device_energy_min");
	if (c_exit < 0 || c_lc < 0 || c_ch < 0 || c_port < 0 || c_dev < 0 || n > MAX_CELLS)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "the sweep's columns lack exit_status, limit_cycle, chatter_s, "
				      "port_energy_min or device_energy_min (a directory of an older "
				      "popc)");
	long long v;
	if (n <= c_exit || popc_parse_ll_span(cell[c_exit], cell[c_exit] + len[c_exit], 0, 999, 0, &v) != 0)
		return popc_error_set(err, POPC_ERR_INVALID, "a row without an exit status");
	f->exit_status = (int)v;
	if (n > c_lc && len[c_lc] > 0 &&
	    popc_parse_ll_span(cell[c_lc], cell[c_lc] + len[c_lc], 0, 1, 0, &v) == 0) {
		f->has_limit_cycle = 1;
		f->limit_cycle = (int)v;
	}
	double d;
	if (n > c_ch && len[c_ch] > 0 &&
	    popc_parse_double_span(cell[c_ch], cell[c_ch] + len[c_ch], &d) == POPC_PARSE_OK) {
		f->has_chatter = 1;
		f->chatter_s = d;
	}
	if (n > c_port && len[c_port] > 0 &&
	    popc_parse_double_span(cell[c_port], cell[c_port] + len[c_port], &d) == POPC_PARSE_OK) {
		f->has_port_energy_min = 1;
		f->port_energy_min_J = d;
	}
	if (n > c_dev && len[c_dev] > 0 &&
	    popc_parse_double_span(cell[c_dev], cell[c_dev] + len[c_dev], &d) == POPC_PARSE_OK) {
		f->has_device_energy_min = 1;
		f->device_energy_min_J = d;
	}
	/* a teleoperation sweep's verdict (no such column in a one-port sweep:
	 * stable is undecided there) */
	int c_osc = header_index(p, "tele_oscillating");
	if (c_osc >= 0 && n > c_osc && len[c_osc] > 0 &&
	    popc_parse_ll_span(cell[c_osc], cell[c_osc] + len[c_osc], 0, 1, 0, &v) == 0) {
		f->has_tele_oscillating = 1;
		f->tele_oscillating = (int)v;
	}
	return 0;
}

int popc_map_row_cell(const popc_sweep_plan *p, const char *row, const char *name,
		      const char **cell_out, size_t *len_out)
{
	const char *cell[MAX_CELLS];
	size_t len[MAX_CELLS];
	int n = popc_sweep_split_cells(row, cell, len, MAX_CELLS);
	int c = header_index(p, name);
	if (c < 0 || c >= n || c >= MAX_CELLS)
		return -1;
	*cell_out = cell[c];
	*len_out = len[c];
	return 0;
}

popc_map_verdict popc_map_verdict_of(popc_map_criterion c, const popc_map_facts *f,
				     double port_tol_J)
{
	if (f->exit_status == 6) /* POPC_EXIT_UNSTABLE: diverged */
		return POPC_MAP_BAD;
	if (f->exit_status != 0)
		return POPC_MAP_UNDECIDED;
	switch (c) {
	case POPC_MAP_DIVERGED:
		return POPC_MAP_OK;
	case POPC_MAP_LIMIT_CYCLE:
		if (!f->has_limit_cycle)
			return POPC_MAP_UNDECIDED;
		return f->limit_cycle ? POPC_MAP_BAD : POPC_MAP_OK;
	case POPC_MAP_CHATTER:
		if (!f->has_chatter)
			return POPC_MAP_UNDECIDED;
		return f->chatter_s > 0 ? POPC_MAP_BAD : POPC_MAP_OK;
	case POPC_MAP_PASSIVE:
		if (!f->has_port_energy_min)
			return POPC_MAP_UNDECIDED;
		return f->port_energy_min_J < -port_tol_J ? POPC_MAP_BAD : POPC_MAP_OK;
	case POPC_MAP_DEVICE_PASSIVE:
		if (!f->has_device_energy_min)
			return POPC_MAP_UNDECIDED;
		return f->device_energy_min_J < -port_tol_J ? POPC_MAP_BAD : POPC_MAP_OK;
	case POPC_MAP_STABLE:
		if (!f->has_tele_oscillating)
			return POPC_MAP_UNDECIDED;
		return f->tele_oscillating ? POPC_MAP_BAD : POPC_MAP_OK;
	default:
		return POPC_MAP_UNDECIDED;
	}
}

/* ---- the grid ---------------------------------------------------------------- */

long popc_map_grid_points(double k_lo, double k_hi, double tol)
{
	/* log(k_hi) - log(k_lo), not log(k_hi / k_lo): the ratio of 1e9 and
	 * 1e-300 overflows a double, the difference of the logs does not */
	double span = log(k_hi) - log(k_lo);
	if (!(k_lo > 0) || !(span > 0) || !isfinite(span) || !(tol > 0) || !isfinite(tol))
		return -1;
	double steps = ceil(span / log1p(tol));
	if (!(steps < (double)POPC_MAP_GRID_MAX)) /* also NaN */
		return -1;
	return steps < 1 ? 2 : (long)steps + 1;
}

long popc_map_scan_points(long n_k, long scan_steps)
{
	long last = n_k - 1;
	if (last < 1)
		return 1;
	if (scan_steps < 1)
		scan_steps = 1;
	return (last + scan_steps - 1) / scan_steps + 1;
}

/* ---- the search ---------------------------------------------------------------- */

static void need(popc_map_search *out, long i)
{
	out->outcome = POPC_MAP_NEEDS_RUNS;
	out->need[out->n_need++] = i;
}

/* Scan point number j of a line (the last is n_k - 1). */
static long scan_at(long j, long n_scan, long n_k, long scan_steps)
{
	return j == n_scan - 1 ? n_k - 1 : j * scan_steps;
}

/* Bisection in index between a (acceptable) and b (not), replayed from the
 * known verdicts: returns 1 with *a, *b adjacent, 0 when it needs a run
 * (asked for in out), -1 at a run without a verdict (out->culprit). */
static int bisect(const unsigned char *v, long *a, long *b, popc_map_search *out)
{
	while (*b - *a > 1) {
		long m = *a + (*b - *a) / 2;
		if (v[m] == POPC_MAP_UNKNOWN) {
			need(out, m);
			return 0;
		}
		out->runs++;
		if (v[m] == POPC_MAP_UNDECIDED) {
			out->culprit = m;
			return -1;
		}
		if (v[m] == POPC_MAP_OK)
			*a = m;
		else
			*b = m;
	}
	return 1;
}

void popc_map_search_line(const unsigned char *v, long n_k, long scan_steps, long *need_buf,
			  popc_map_search *out)
{
	memset(out, 0, sizeof *out);
	out->need = need_buf;
	out->ok_index = out->bad_index = out->last_ok_index = out->last_bad_index = -1;
	out->culprit = -1;
	if (scan_steps < 1)
		scan_steps = 1;
	const long n_scan = popc_map_scan_points(n_k, scan_steps);
	/* the scan, one batch */
	for (long j = 0; j < n_scan; j++) {
		long i = scan_at(j, n_scan, n_k, scan_steps);
		if (v[i] == POPC_MAP_UNKNOWN)
			need(out, i);
		else
			out->runs++;
	}
	if (out->n_need)
		return;
	long first_bad = -1, last_ok = -1; /* scan numbers */
	for (long j = 0; j < n_scan; j++) {
		long i = scan_at(j, n_scan, n_k, scan_steps);
		if (v[i] == POPC_MAP_UNDECIDED) {
			out->outcome = POPC_MAP_UNDECIDED_RUN;
			out->culprit = i;
			return;
		}
		if (v[i] == POPC_MAP_BAD && first_bad < 0)
			first_bad = j;
		if (v[i] == POPC_MAP_OK)
			last_ok = j;
	}
	if (first_bad < 0) {
		out->outcome = POPC_MAP_ALL_OK;
		out->ok_index = n_k - 1;
		return;
	}
	/* the first failure: between the scan point below the first
	 * unacceptable one and it; and, where the line is acceptable again
	 * above it, the band's top: between the highest acceptable scan point
	 * and the next. Both bisections step in the same batch. */
	int done_first = 1, done_top = 1;
	long a = -1, b = scan_at(first_bad, n_scan, n_k, scan_steps);
	if (first_bad > 0) {
		a = scan_at(first_bad - 1, n_scan, n_k, scan_steps);
		done_first = bisect(v, &a, &b, out);
	}
	long ta = -1, tb = -1;
	if (done_first >= 0 && last_ok > first_bad) {
		ta = scan_at(last_ok, n_scan, n_k, scan_steps);
		if (last_ok < n_scan - 1) {
			tb = scan_at(last_ok + 1, n_scan, n_k, scan_steps);
			done_top = bisect(v, &ta, &tb, out);
		}
	}
	if (done_first < 0 || done_top < 0) {
		out->outcome = POPC_MAP_UNDECIDED_RUN;
		return;
	}
	if (out->n_need)
		return;
	out->bad_index = b;
	out->ok_index = a;
	if (ta >= 0) {
		out->outcome = POPC_MAP_NOT_MONOTONIC;
		out->last_ok_index = ta;
		out->last_bad_index = tb;
	} else
		out->outcome = a < 0 ? POPC_MAP_NONE_OK : POPC_MAP_BRACKET;
}
