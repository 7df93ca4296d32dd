/* Stability maps (sweep_map.h): the criteria, the log-K grid and the
 * bisection of one line, replayed from the verdicts known so far. */
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
					      "comma-separated)",
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
	default:
		return POPC_MAP_UNDECIDED;
	}
}

/* ---- the grid ---------------------------------------------------------------- */

long popc_map_grid_points(double k_lo, double k_hi, double tol)
{
	double steps = ceil(log(k_hi / k_lo) / log1p(tol));
	return steps < 1 ? 2 : (long)steps + 1;
}

long popc_map_check_steps(double k_lo, double k_hi, long n_k)
{
	double step = log(k_hi / k_lo) / (double)(n_k - 1);
	long s = lround(log(2.0) / step);
	return s < 1 ? 1 : s;
}

/* ---- the search ---------------------------------------------------------------- */

static void need(popc_map_search *out, long i)
{
	out->outcome = POPC_MAP_NEEDS_RUNS;
	out->need[out->n_need++] = i;
}

/* Counts the known points and, given the edge between ok_below (the highest
 * index that must be acceptable) and bad_above (the lowest that must not
 * be), finds a known point on the wrong side. Returns 1 when one is found. */
static int wrong_side(const unsigned char *v, long n_k, long ok_below, long bad_above,
		      popc_map_search *out)
{
	for (long i = 0; i < n_k; i++) {
		if (v[i] == POPC_MAP_OK && i >= bad_above) {
			/* the lowest bad point below it names the fold */
			long b = bad_above;
			for (long j = 0; j < i; j++)
				if (v[j] == POPC_MAP_BAD) {
					b = j;
					break;
				}
			out->outcome = POPC_MAP_NOT_MONOTONIC;
			out->culprit_ok = i;
			out->culprit_bad = b;
			return 1;
		}
		if (v[i] == POPC_MAP_BAD && i <= ok_below) {
			out->outcome = POPC_MAP_NOT_MONOTONIC;
			out->culprit_bad = i;
			out->culprit_ok = ok_below;
			for (long j = n_k - 1; j > i; j--)
				if (v[j] == POPC_MAP_OK) {
					out->culprit_ok = j;
					break;
				}
			return 1;
		}
	}
	return 0;
}

void popc_map_search_line(const unsigned char *v, long n_k, long check_steps,
			  popc_map_search *out)
{
	memset(out, 0, sizeof *out);
	out->ok_index = out->bad_index = out->check_low = out->check_high = -1;
	out->culprit_ok = out->culprit_bad = -1;
	long last = n_k - 1;
	/* the two ends, one batch */
	if (v[0] == POPC_MAP_UNKNOWN)
		need(out, 0);
	if (v[last] == POPC_MAP_UNKNOWN)
		need(out, last);
	out->runs = (v[0] != POPC_MAP_UNKNOWN) + (v[last] != POPC_MAP_UNKNOWN);
	if (out->n_need)
		return;
	for (long e = 0; e <= last; e += last)
		if (v[e] == POPC_MAP_UNDECIDED) {
			out->outcome = POPC_MAP_UNDECIDED_RUN;
			out->culprit_ok = e;
			return;
		}
	if (v[0] == POPC_MAP_BAD) {
		/* every known point must be unacceptable */
		out->outcome = POPC_MAP_NONE_OK;
		wrong_side(v, n_k, -1, 0, out);
		return;
	}
	if (v[last] == POPC_MAP_OK) {
		out->outcome = POPC_MAP_ALL_OK;
		wrong_side(v, n_k, last, n_k, out);
		return;
	}
	/* bisection in index, i.e. in log K: a acceptable, b not */
	long a = 0, b = last;
	while (b - a > 1) {
		long m = a + (b - a) / 2;
		if (v[m] == POPC_MAP_UNKNOWN) {
			need(out, m);
			return;
		}
		out->runs++;
		if (v[m] == POPC_MAP_UNDECIDED) {
			out->outcome = POPC_MAP_UNDECIDED_RUN;
			out->culprit_ok = m;
			return;
		}
		if (v[m] == POPC_MAP_OK)
			a = m;
		else
			b = m;
	}
	/* the checks: a factor of two inside and outside the bracket, one batch */
	long lo = a - check_steps < 0 ? 0 : a - check_steps;
	long hi = b + check_steps > last ? last : b + check_steps;
	out->check_low = lo;
	out->check_high = hi;
	if (v[lo] == POPC_MAP_UNKNOWN)
		need(out, lo);
	if (v[hi] == POPC_MAP_UNKNOWN && hi != lo)
		need(out, hi);
	if (out->n_need)
		return;
	/* the checks count when they are new points (not an end or a
	 * bisection point already run) */
	for (long e = lo; ; e = hi) {
		int seen = e == 0 || e == last;
		for (long x = 0, y = last; !seen && y - x > 1;) {
			long m = x + (y - x) / 2;
			seen = m == e;
			if (v[m] == POPC_MAP_OK)
				x = m;
			else
				y = m;
		}
		out->runs += !seen;
		if (e == hi || hi == lo)
			break;
	}
	for (long e = lo; ; e = hi) {
		if (v[e] == POPC_MAP_UNDECIDED) {
			out->outcome = POPC_MAP_UNDECIDED_RUN;
			out->culprit_ok = e;
			return;
		}
		if (e == hi)
			break;
	}
	out->outcome = POPC_MAP_BRACKET;
	out->ok_index = a;
	out->bad_index = b;
	wrong_side(v, n_k, a, b, out);
	if (out->outcome != POPC_MAP_BRACKET)
		out->ok_index = out->bad_index = -1;
}
