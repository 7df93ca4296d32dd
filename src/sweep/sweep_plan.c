/* The sweep planner (sweep_plan.h): value lists and ranges, the cartesian
 * product, run ids, plan ids and shards. */
#include "popc/sweep/sweep_plan.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "popc/axes/axis.h"
#include "popc/core/intent.h"
#include "popc/scene/from_scene.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/util/parse.h"
#include "popc/util/text.h"

uint64_t popc_sweep_fnv1a(uint64_t h, const void *data, size_t n)
{
	const unsigned char *b = data;
	for (size_t i = 0; i < n; i++) {
		h ^= b[i];
		h *= 0x100000001b3ULL; /* FNV-1a 64-bit prime */
	}
	return h;
}

void popc_sweep_values_free(char **values, int n_values)
{
	if (!values)
		return;
	for (int i = 0; i < n_values; i++)
		free(values[i]);
	free(values);
}

/* A number as everywhere (popc/util/parse.h), blanks around it dropped as
 * popc_scene_set drops them from the value. */
static int parse_finite(const char *text, double *out)
{
	const char *end = text + strlen(text);
	popc_trim_blanks(&text, &end);
	return popc_parse_double_span(text, end, out) == POPC_PARSE_OK ? 0 : -1;
}

static int cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

static int check_duplicates(char **values, int n, const char *spec, popc_error *err)
{
	if (n < 2)
		return 0;
	char **sorted = malloc((size_t)n * sizeof *sorted);
	if (!sorted)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	memcpy(sorted, values, (size_t)n * sizeof *sorted);
	qsort(sorted, (size_t)n, sizeof *sorted, cmp_str);
	int st = 0;
	for (int i = 1; i < n && !st; i++)
		if (strcmp(sorted[i - 1], sorted[i]) == 0)
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "'%s': value '%s' appears twice (a range too fine for 12 "
					    "significant digits gives repeated values)",
					    spec, sorted[i]);
	free(sorted);
	return st;
}

static int expand_range(const char *spec, char ***values, int *n_values, popc_error *err)
{
	char buf[POPC_SWEEP_VALUE_MAX * 2];
	if (strlen(spec) >= sizeof buf)
		return popc_error_set(err, POPC_ERR_INVALID, "'%.40s...': range too long", spec);
	strcpy(buf, spec);
	char *part[5];
	int np = 0;
	for (char *p = buf, *colon; np < 5; p = colon + 1) {
		part[np++] = p;
		colon = strchr(p, ':');
		if (!colon)
			break;
		*colon = '\0';
	}
	int is_log = np == 4 && strcmp(part[3], "log") == 0;
	if (np != 3 && !is_log)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "'%s': a range is lo:hi:n or lo:hi:n:log (a list is a,b,c)", spec);
	double lo, hi;
	long long nd;
	const char *n_text = part[2], *n_end = part[2] + strlen(part[2]);
	popc_trim_blanks(&n_text, &n_end);
	if (parse_finite(part[0], &lo) || parse_finite(part[1], &hi))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "'%s': range ends must be finite decimal numbers (lo:hi:n[:log])",
				      spec);
	if (popc_parse_ll_span(n_text, n_end, 1, POPC_SWEEP_RANGE_MAX, 0, &nd) != POPC_PARSE_OK)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "'%s': the number of points n must be a whole number in [1, %ld]",
				      spec, POPC_SWEEP_RANGE_MAX);
	/* one point is lo: hi would be dropped without a word */
	if (nd == 1 && lo != hi)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "'%s': a range of 1 point holds lo only, not hi: give n >= 2 for "
				      "both ends, or lo == hi (lo:lo:1) for one value",
				      spec);
	if (is_log && !(lo > 0 && hi > 0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "'%s': a logarithmic range needs lo > 0 and hi > 0", spec);
	int n = (int)nd;
	char **v = calloc((size_t)n, sizeof *v);
	if (!v)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	double log_lo = is_log ? log(lo) : 0.0, log_hi = is_log ? log(hi) : 0.0;
	for (int i = 0; i < n; i++) {
		double x;
		if (i == 0)
			x = lo;
		else if (i == n - 1)
			x = hi;
		else if (is_log)
			x = exp(log_lo + (log_hi - log_lo) * (double)i / (double)(n - 1));
		else
			x = lo + (hi - lo) * (double)i / (double)(n - 1);
		char text[40];
		snprintf(text, sizeof text, "%.12g", x);
		/* -0 reads as 0 and prints as "-0": one spelling of zero */
		if (strcmp(text, "-0") == 0)
			strcpy(text, "0");
		v[i] = strdup(text);
		if (!v[i]) {
			popc_sweep_values_free(v, n);
			return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
		}
	}
	int st = check_duplicates(v, n, spec, err);
	if (st) {
		popc_sweep_values_free(v, n);
		return st;
	}
	*values = v;
	*n_values = n;
	return 0;
}

static int expand_list(const char *spec, char ***values, int *n_values, popc_error *err)
{
	int n = 1;
	for (const char *p = spec; *p; p++)
		n += *p == ',';
	char **v = calloc((size_t)n, sizeof *v);
	if (!v)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	const char *p = spec;
	int st = 0;
	for (int i = 0; i < n && !st; i++) {
		const char *comma = strchr(p, ',');
		size_t len = comma ? (size_t)(comma - p) : strlen(p);
		if (len == 0)
			st = popc_error_set(err, POPC_ERR_INVALID, "'%s': empty value in the list (item %d)",
					    spec, i + 1);
		else if (len >= POPC_SWEEP_VALUE_MAX)
			st = popc_error_set(err, POPC_ERR_INVALID, "'%s': item %d longer than %d characters",
					    spec, i + 1, POPC_SWEEP_VALUE_MAX - 1);
		else if (memchr(p, '"', len) || memchr(p, '\n', len) || memchr(p, '\r', len))
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "'%s': item %d holds a quote or a line break (not allowed in "
					    "summary.csv cells)",
					    spec, i + 1);
		else if (!(v[i] = strndup(p, len)))
			st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
		p = comma ? comma + 1 : p + len;
	}
	if (!st)
		st = check_duplicates(v, n, spec, err);
	if (st) {
		popc_sweep_values_free(v, n);
		return st;
	}
	*values = v;
	*n_values = n;
	return 0;
}

int popc_sweep_expand(const char *spec, char ***values, int *n_values, popc_error *err)
{
	*values = NULL;
	*n_values = 0;
	if (!spec[0])
		return popc_error_set(err, POPC_ERR_INVALID, "empty value list");
	/* a list has commas; without commas, a colon makes it a range */
	if (!strchr(spec, ',') && strchr(spec, ':'))
		return expand_range(spec, values, n_values, err);
	return expand_list(spec, values, n_values, err);
}

int popc_sweep_axis_parse(const char *vary, popc_sweep_axis *axis, popc_error *err)
{
	memset(axis, 0, sizeof *axis);
	const char *eq = strchr(vary, '=');
	const char *dot = strchr(vary, '.');
	if (!eq || !dot || dot > eq || dot == vary || dot + 1 == eq)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--vary '%s': expected section.key=LIST (e.g. "
				      "operator.speed=0.01:0.1:10 or controller.variant=none,improved)",
				      vary);
	size_t ls = (size_t)(dot - vary), lk = (size_t)(eq - dot - 1);
	if (ls >= sizeof axis->section || lk >= sizeof axis->key)
		return popc_error_set(err, POPC_ERR_INVALID, "--vary '%s': name too long", vary);
	if (strlen(eq + 1) >= sizeof axis->spec)
		return popc_error_set(err, POPC_ERR_INVALID, "--vary '%.60s...': values too long", vary);
	memcpy(axis->section, vary, ls);
	memcpy(axis->key, dot + 1, lk);
	strcpy(axis->spec, eq + 1);
	popc_error e;
	int st = popc_sweep_expand(axis->spec, &axis->values, &axis->n_values, &e);
	if (st)
		return popc_error_set(err, st, "--vary %s.%s: %s", axis->section, axis->key, e.msg);
	return 0;
}

void popc_sweep_axis_free(popc_sweep_axis *axis)
{
	popc_sweep_values_free(axis->values, axis->n_values);
	axis->values = NULL;
	axis->n_values = 0;
}

void popc_sweep_plan_free(popc_sweep_plan *p)
{
	for (int a = 0; a < p->n_axes; a++)
		popc_sweep_axis_free(&p->axes[a]);
	free(p->axes);
	free(p->columns);
	p->axes = NULL;
	p->n_axes = 0;
	p->columns = NULL;
}

void popc_sweep_run_values(const popc_sweep_plan *p, long long i, int *value_index)
{
	/* mixed radix, last axis fastest */
	for (int a = p->n_axes - 1; a >= 0; a--) {
		long long n = p->axes[a].n_values;
		value_index[a] = (int)(i % n);
		i /= n;
	}
}

int popc_sweep_run_scene(const popc_sweep_plan *p, long long i, popc_scene *s, popc_error *err)
{
	*s = p->base;
	long long rest = i;
	for (int a = p->n_axes - 1; a >= 0; a--) {
		const popc_sweep_axis *ax = &p->axes[a];
		int st = popc_scene_set_index(s, p->axis_key[a], ax->values[rest % ax->n_values], err);
		if (st)
			return st;
		rest /= ax->n_values;
	}
	return popc_scene_validate(s, err);
}

void popc_sweep_run_id(const popc_sweep_plan *p, long long i, char *buf)
{
	/* "%0*lld" by hand, cut to POPC_SWEEP_ID_MAX - 1 characters as snprintf
	 * would: once or twice per run, where snprintf was about a thousand
	 * instructions each time */
	char text[48];
	int k = (int)sizeof text;
	unsigned long long m = i < 0 ? 0ULL - (unsigned long long)i : (unsigned long long)i;
	do
		text[--k] = (char)('0' + m % 10);
	while ((m /= 10) != 0);
	int width = p->id_width < 40 ? p->id_width : 40;
	int sign = i < 0;
	while ((int)sizeof text - k + sign < width)
		text[--k] = '0';
	if (sign)
		text[--k] = '-';
	size_t n = sizeof text - (size_t)k;
	if (n > POPC_SWEEP_ID_MAX - 1)
		n = POPC_SWEEP_ID_MAX - 1;
	memcpy(buf, text + k, n);
	buf[n] = '\0';
}

long long popc_sweep_id_parse(const popc_sweep_plan *p, const char *text)
{
	long long v = 0;
	int n = 0;
	for (; text[n]; n++) {
		if (text[n] < '0' || text[n] > '9' || n >= 12)
			return -1;
		v = v * 10 + (text[n] - '0');
	}
	if (n != p->id_width || v >= p->n_runs)
		return -1;
	return v;
}

/* A field of one line: a line break would end the plan file's line. */
static void copy_line(char *out, size_t cap, const char *text)
{
	snprintf(out, cap, "%.*s", (int)strcspn(text ? text : "", "\r\n"), text ? text : "");
}

void popc_sweep_plan_set_build(popc_sweep_plan *p, const char *version, const char *build)
{
	copy_line(p->popc_version, sizeof p->popc_version, version);
	copy_line(p->popc_build, sizeof p->popc_build, build);
}

int popc_sweep_plan_same_build(const popc_sweep_plan *a, const popc_sweep_plan *b)
{
	return strcmp(a->popc_version, b->popc_version) == 0 &&
	       strcmp(a->popc_build, b->popc_build) == 0;
}

void popc_sweep_plan_describe_build(const popc_sweep_plan *p, char *buf, size_t cap)
{
	if (!p->popc_version[0] && !p->popc_build[0])
		snprintf(buf, cap, "a popc that recorded no version or build (before build ids)");
	else
		snprintf(buf, cap, "popc %s (build %s)", p->popc_version[0] ? p->popc_version : "?",
			 p->popc_build[0] ? p->popc_build : "not recorded");
}

/* Hashes the base scene as popc_scene_write writes it. */
static int hash_scene(const popc_scene *s, uint64_t *h, popc_error *err)
{
	char *text;
	size_t len;
	int st = popc_scene_to_text(s, &text, &len, err);
	if (st)
		return st;
	*h = popc_sweep_fnv1a(*h, text, len);
	free(text);
	return 0;
}

/* A list, as opposed to a range (popc_sweep_expand's rule). */
static int axis_is_list(const popc_sweep_axis *ax)
{
	return strchr(ax->spec, ',') || !strchr(ax->spec, ':');
}

/* Two items of a list that make the same run: "0.01,0.010" or "1e-2,0.01"
 * (one double), "2,2.0" for a whole-number key, or two spellings of one enum
 * name, which the text check in popc_sweep_expand cannot see. Two values are
 * the same when they give the same resolved scene (the scene writes every
 * number so that it reads back to the same double, so equal text is equal
 * value, key by key, and an enum is written by its name), or when both are
 * zeros (-0 and 0 are one value: the scene writes them apart). Ranges need no
 * such check: their points are written canonically ("%.12g", no "-0"), and
 * distinct 12-digit decimals are distinct doubles (DBL_DIG = 15). */
static int check_same_values(const popc_scene *base, const popc_sweep_axis *ax, popc_error *err)
{
	if (ax->n_values < 2 || !axis_is_list(ax))
		return 0;
	int n = ax->n_values;
	char **text = calloc((size_t)n, sizeof *text);
	uint64_t *hash = calloc((size_t)n, sizeof *hash);
	int st = text && hash ? 0 : popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	for (int v = 0; v < n && !st; v++) {
		popc_scene s = *base;
		size_t len;
		st = popc_scene_set(&s, ax->section, ax->key, ax->values[v], err);
		if (!st)
			st = popc_scene_to_text(&s, &text[v], &len, err);
		if (!st)
			hash[v] = popc_sweep_fnv1a(POPC_SWEEP_FNV_OFFSET, text[v], len);
	}
	/* at most POPC_SWEEP_VALUE_MAX items fit in a spec: n^2 is small */
	for (int a = 0; a < n && !st; a++) {
		double xa, xb;
		int za = parse_finite(ax->values[a], &xa) == 0 && xa == 0.0;
		for (int b = a + 1; b < n && !st; b++) {
			int zb = parse_finite(ax->values[b], &xb) == 0 && xb == 0.0;
			if ((hash[a] == hash[b] && strcmp(text[a], text[b]) == 0) || (za && zb))
				st = popc_error_set(err, POPC_ERR_INVALID,
						    "--vary %s.%s=%s: items %d ('%s') and %d ('%s') are the "
						    "same value: give each value once",
						    ax->section, ax->key, ax->spec, a + 1, ax->values[a],
						    b + 1, ax->values[b]);
		}
	}
	for (int v = 0; text && v < n; v++)
		free(text[v]);
	free(text);
	free(hash);
	return st;
}

/* The operator tables that a sweep's runs read, each read once before
 * anything runs: a missing or bad table is bad input for the whole sweep
 * (exit 2), not a failure of every run that uses it. A table is read for its
 * path and quantity (the value ranges differ). Runs only ever name the base
 * scene's table or a value of an operator.table axis, so the list is short. */
typedef struct table_check {
	int n, cap;
	char **path;
	popc_table_quantity *quantity;
} table_check;

static int check_table(table_check *tc, const popc_scene *s, popc_error *err)
{
	if (s->intent != POPC_INTENT_TABLE)
		return 0;
	for (int k = 0; k < tc->n; k++)
		if (tc->quantity[k] == s->op_table_quantity && strcmp(tc->path[k], s->op_table) == 0)
			return 0;
	popc_intent in;
	int st = popc_intent_from_scene(&in, s, err);
	popc_intent_free(&in);
	if (st)
		return st;
	if (tc->n == tc->cap) {
		int cap = tc->cap ? 2 * tc->cap : 8;
		char **np = realloc(tc->path, (size_t)cap * sizeof *np);
		if (np)
			tc->path = np;
		popc_table_quantity *nq = realloc(tc->quantity, (size_t)cap * sizeof *nq);
		if (nq)
			tc->quantity = nq;
		if (!np || !nq)
			return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
		tc->cap = cap;
	}
	if (!(tc->path[tc->n] = strdup(s->op_table)))
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	tc->quantity[tc->n++] = s->op_table_quantity;
	return 0;
}

void popc_sweep_run_describe(const popc_sweep_plan *p, long long i, char *buf, size_t cap)
{
	int idx[POPC_SWEEP_AXES_MAX];
	popc_sweep_run_values(p, i, idx);
	size_t len = 0;
	buf[0] = '\0';
	for (int a = 0; a < p->n_axes && len < cap; a++)
		len += (size_t)snprintf(buf + len, cap - len, "%s%s.%s=%s", a ? " " : "",
					p->axes[a].section, p->axes[a].key,
					p->axes[a].values[idx[a]]);
}

/* Whether the plan's runs are teleoperation scenes (p->teleop): the base
 * scene's teleop.architecture, or that of every value of a --vary of it.
 * Values that make both a teleoperation and a one-port scene are refused: the
 * two have different columns (sweep_columns.h), and one table must hold every
 * row, as an admittance and an impedance run share theirs. */
static int plan_teleop(popc_sweep_plan *p, popc_error *err)
{
	p->teleop = p->base.tele_arch != POPC_TELEOP_OFF;
	for (int a = 0; a < p->n_axes; a++) {
		const popc_sweep_axis *ax = &p->axes[a];
		if (strcmp(ax->section, "teleop") != 0 || strcmp(ax->key, "architecture") != 0)
			continue;
		for (int v = 0; v < ax->n_values; v++) {
			popc_scene scratch = p->base;
			popc_error e;
			if (popc_scene_set(&scratch, ax->section, ax->key, ax->values[v], &e) != 0)
				continue; /* refused by the value checks before */
			int t = scratch.tele_arch != POPC_TELEOP_OFF;
			if (v > 0 && t != p->teleop)
				return popc_error_set(err, POPC_ERR_INVALID,
						      "--vary teleop.architecture=%s: '%s' and '%s' make "
						      "one-port and teleoperation runs, whose summaries "
						      "have different columns: make one sweep of each",
						      ax->spec, ax->values[0], ax->values[v]);
			p->teleop = t;
		}
	}
	return 0;
}

int popc_sweep_plan_init(popc_sweep_plan *p, const popc_scene *base, popc_sweep_axis *axes,
			 int n_axes, int check_every_run, popc_error *err)
{
	memset(p, 0, sizeof *p);
	p->base = *base;
	p->axes = axes;
	p->n_axes = n_axes;
	if (n_axes > POPC_SWEEP_AXES_MAX)
		return popc_error_set(err, POPC_ERR_INVALID, "more than %d --vary axes",
				      POPC_SWEEP_AXES_MAX);
	p->n_runs = 1;
	int st = 0;
	for (int a = 0; a < n_axes; a++) {
		const popc_sweep_axis *ax = &axes[a];
		for (int b = 0; b < a; b++)
			if (strcmp(axes[b].section, ax->section) == 0 && strcmp(axes[b].key, ax->key) == 0)
				return popc_error_set(err, POPC_ERR_INVALID,
						      "--vary %s.%s given twice: give all its values in "
						      "one list",
						      ax->section, ax->key);
		/* each value on its own, through the scene's own checks: the
		 * message names the key and the allowed range */
		for (int v = 0; v < ax->n_values; v++) {
			popc_scene scratch = *base;
			popc_error e;
			st = popc_scene_set(&scratch, ax->section, ax->key, ax->values[v], &e);
			if (st)
				return popc_error_set(err, st, "--vary %s.%s=%s, value %d of %d ('%s'): %s",
						      ax->section, ax->key, ax->spec, v + 1,
						      ax->n_values, ax->values[v], e.msg);
		}
		st = check_same_values(base, ax, err);
		if (st)
			return st;
		/* found once, set for every run (popc_sweep_run_scene) */
		p->axis_key[a] = popc_scene_key_index(ax->section, ax->key);
		if (p->axis_key[a] < 0)
			return popc_error_set(err, POPC_ERR_INVALID, "--vary %s.%s: no such scene key",
					      ax->section, ax->key);
		if (p->n_runs > POPC_SWEEP_RUNS_MAX / ax->n_values)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "the sweep has more than %lld runs: split it",
					      POPC_SWEEP_RUNS_MAX);
		p->n_runs *= ax->n_values;
	}
	p->id_width = 4;
	for (long long m = 10000; m < p->n_runs; m *= 10)
		p->id_width++;
	if ((st = plan_teleop(p, err)) != 0)
		return st;
	p->columns = popc_sweep_columns_header_of(axes, n_axes, p->teleop);
	if (!p->columns)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");

	uint64_t h = POPC_SWEEP_FNV_OFFSET;
	static const char magic[] = "popc sweep plan 1\n";
	h = popc_sweep_fnv1a(h, magic, sizeof magic - 1);
	st = hash_scene(base, &h, err);
	if (st)
		return st;
	for (int a = 0; a < n_axes; a++) {
		const popc_sweep_axis *ax = &axes[a];
		h = popc_sweep_fnv1a(h, ax->section, strlen(ax->section) + 1);
		h = popc_sweep_fnv1a(h, ax->key, strlen(ax->key) + 1);
		int relative = 0;
		for (int v = 0; v < ax->n_values; v++) {
			h = popc_sweep_fnv1a(h, ax->values[v], strlen(ax->values[v]) + 1);
			relative |= ax->values[v][0] != '/';
		}
		/* a relative path names a file from the working directory
		 * (scene.h): the same list given in another directory is another
		 * sweep (a resume there would mix two sets of files) */
		char cwd[POPC_PATH_MAX];
		if (relative && popc_scene_key_is_path(ax->section, ax->key) && getcwd(cwd, sizeof cwd))
			h = popc_sweep_fnv1a(h, cwd, strlen(cwd) + 1);
	}
	h = popc_sweep_fnv1a(h, p->columns, strlen(p->columns));
	p->plan_id = h;

	if (check_every_run) {
		popc_scene s;
		table_check tables = {0};
		for (long long i = 0; i < p->n_runs && !st; i++) {
			popc_error e;
			st = popc_sweep_run_scene(p, i, &s, &e);
			/* the runs share no drive: a real axis is driven by popc run,
			 * one experiment at a time (popc_sweep_run_one refuses it too) */
			if (!st && !popc_axis_is_simulated(&s))
				st = popc_error_set(&e, POPC_ERR_INVALID,
						    "axis.kind = %s: a sweep runs the simulated axis "
						    "only (drive a real axis with popc run)",
						    s.axis);
			if (!st)
				st = check_table(&tables, &s, &e);
			if (st) {
				char id[POPC_SWEEP_ID_MAX], what[1024];
				popc_sweep_run_id(p, i, id);
				popc_sweep_run_describe(p, i, what, sizeof what);
				st = popc_error_set(err, st, "run %s (%s): %s", id, what, e.msg);
			}
		}
		for (int k = 0; k < tables.n; k++)
			free(tables.path[k]);
		free(tables.path);
		free(tables.quantity);
	}
	return st;
}

/* ---- shards ---------------------------------------------------------------- */

int popc_sweep_shard_parse(const char *text, popc_sweep_shard *sh, popc_error *err)
{
	char buf[64];
	const char *slash = strchr(text, '/');
	if (!slash || strlen(text) >= sizeof buf)
		return popc_error_set(err, POPC_ERR_INVALID, "--shard '%s': expected I/N (e.g. 1/4)", text);
	memcpy(buf, text, (size_t)(slash - text));
	buf[slash - text] = '\0';
	long long i, n;
	if (popc_parse_ll_text(slash + 1, 1, POPC_SWEEP_RUNS_MAX, &n) != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--shard '%s': N must be a whole number in [1, %lld]", text,
				      POPC_SWEEP_RUNS_MAX);
	if (popc_parse_ll_text(buf, 0, 0, &i) == 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--shard '%s': shards count from 1, as in Playwright, Jest and "
				      "node --test: --shard 1/%lld ... --shard %lld/%lld make the whole sweep",
				      text, n, n, n);
	if (popc_parse_ll_text(buf, 1, n, &i) != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--shard '%s': I must be a whole number in [1, %lld]", text, n);
	sh->index = i - 1;
	sh->count = n;
	return 0;
}

int popc_sweep_shard_from_slurm(const char *task_id, const char *task_count, const char *task_min,
				const char *task_step, popc_sweep_shard *sh, popc_error *err)
{
	if (!task_id || !task_count || !task_id[0] || !task_count[0])
		return 0;
	long long id, count, min = 0, step = 1;
	if (popc_parse_ll_text(task_id, 0, 1LL << 40, &id) || popc_parse_ll_text(task_count, 1, POPC_SWEEP_RUNS_MAX, &count)
	    || (task_min && task_min[0] && popc_parse_ll_text(task_min, 0, 1LL << 40, &min))
	    || (task_step && task_step[0] && popc_parse_ll_text(task_step, 1, 1LL << 40, &step)))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "SLURM_ARRAY_TASK_ID=%s, SLURM_ARRAY_TASK_COUNT=%s: not whole numbers",
				      task_id, task_count);
	/* the array's k-th task (k from 0) is shard k + 1, whatever index the
	 * array starts at: --array=0-3, 1-4 and 10-16:2 all make shards 1/4..4/4 */
	long long off = id - min;
	if (off < 0 || off % step != 0 || off / step >= count)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "Slurm array task %lld (min %lld, step %lld, count %lld) is not one "
				      "of a regular array: submit with --array=1-%lld (any first index and "
				      "step will do; a list such as 1,7 will not), or pass --shard I/N",
				      id, min, step, count, count);
	sh->index = off / step;
	sh->count = count;
	return 1;
}
