/* popc sweep stats DIR --by KEY,...: the distribution of a sweep's metrics
 * per group of runs (median, quartiles, range), read from DIR/summary.csv.
 * A sweep over sub-count start offsets (operator.x0 + i delta / N) grouped by
 * the variant and the duration turns single runs into the distributions the
 * science claims rest on (docs/SWEEPS.md, "Statistics"). The metric names are
 * checked against the sweep's own column table (popc_sweep_columns[]). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/programs/table_out.h"
#include "popc/util/numfmt.h"

#define STATS_MAX_BY 8
#define STATS_MAX_METRICS 32
#define STATS_DEFAULT_METRICS "pc_rms_late,w_minus_eref_end,vsign_rate_late,chatter_s,limit_cycle"

static void usage(FILE *f)
{
	fputs("usage: popc sweep stats DIR --by KEY[,KEY...] [--metrics NAME[,NAME...]]\n"
	      "                        [--format text|csv|markdown|json]\n"
	      "\n"
	      "Reads DIR/summary.csv and prints, for each group of runs that share the\n"
	      "values of the --by keys (varied keys, as the summary's columns name them,\n"
	      "e.g. controller.variant,run.duration), the distribution of each metric over\n"
	      "the group's runs: n, median, min, max and the quartiles q1, q3 (linear\n"
	      "interpolation between order statistics: q(p) at rank (n - 1) p). Runs that\n"
	      "failed (exit_status != 0) are left out and counted; an empty cell (chatter\n"
	      "not checked) is left out of its metric's n.\n"
	      "\n"
	      "  --by KEY,...             the grouping columns (required)\n"
	      "  --metrics NAME,...       metric columns (default " STATS_DEFAULT_METRICS ";\n"
	      "                           any numeric column of summary.csv: pc_rms, pc_max,\n"
	      "                           pc_active, pc_energy, w_minus_eref_min, vsign_rate,\n"
	      "                           chatter_intervals, ...)\n"
	      "  --format text|csv|markdown|json  text (default) and markdown: one row per\n"
	      "                           group, each cell 'median [min, max]'; csv: one row\n"
	      "                           per group and metric: KEYS...,metric,n,median,min,\n"
	      "                           q1,q3,max (a cell with ',' or '\"' quoted, RFC 4180);\n"
	      "                           json: the csv's rows as one object each on one line,\n"
	      "                           the same names and digits, null for an empty cell\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0, 2 bad usage or a summary without the columns asked for.\n",
	      f);
}

/* Splits a CSV line in place into cells (RFC 4180 quotes: a quoted cell may
 * hold ',' and doubled quotes). Returns the cell count, or -1 past max. */
static int split_csv(char *line, char **cells, int max)
{
	int n = 0;
	char *p = line;
	line[strcspn(line, "\r\n")] = '\0';
	for (;;) {
		if (n == max)
			return -1;
		if (*p == '"') {
			char *w = ++p;
			cells[n++] = w;
			while (*p) {
				if (*p == '"' && p[1] == '"') {
					*w++ = '"';
					p += 2;
				} else if (*p == '"') {
					p++;
					break;
				} else {
					*w++ = *p++;
				}
			}
			char *rest = p;
			*w = '\0';
			p = rest + strcspn(rest, ",");
		} else {
			cells[n++] = p;
			p += strcspn(p, ",");
		}
		if (*p != ',') {
			*p = '\0';
			return n;
		}
		*p++ = '\0';
	}
}

/* A metric must be one of the table's numeric columns: a run metric, the
 * chatter columns; not the id, the exit status or the wall time (no science). */
static int metric_known(const char *name)
{
	/* the teleoperation table: the one-port columns and the tele_* ones */
	int n_columns;
	const popc_sweep_column *columns = popc_sweep_columns_of(1, &n_columns);
	for (int c = 0; c < n_columns; c++) {
		const popc_sweep_column *col = &columns[c];
		if (!col->name || strcmp(col->name, name) != 0)
			continue;
		return col->source != POPC_SWEEP_CELL_RUN_ID &&
		       col->source != POPC_SWEEP_CELL_EXIT_STATUS &&
		       col->source != POPC_SWEEP_CELL_WALL_TIME_S;
	}
	return 0;
}

typedef struct group {
	char *key;               /* the --by cells joined by '\x1f' */
	int n_runs;
	double *v[STATS_MAX_METRICS];
	int n[STATS_MAX_METRICS], cap[STATS_MAX_METRICS];
} group;

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* q(p) of sorted x[0..n-1]: rank h = (n - 1) p, interpolated linearly.
 * x[lo] + f (x[lo+1] - x[lo]) overflows when the two lie more than the
 * largest double apart (1.7e308 and -1.7e308: inf, and 0 times it at f = 0
 * is nan); then the weighted mean (1 - f) x[lo] + f x[lo+1], whose terms
 * and sum are bounded by the larger magnitude, is taken instead. Every other
 * case keeps the first form, bit for bit as before. */
static double quantile(const double *x, int n, double p)
{
	double h = (n - 1) * p;
	int lo = (int)floor(h);
	if (lo >= n - 1)
		return x[n - 1];
	double f = h - lo, d = x[lo + 1] - x[lo];
	if (f == 0.0)
		return x[lo];
	if (isfinite(d))
		return x[lo] + f * d;
	return (1.0 - f) * x[lo] + f * x[lo + 1];
}

/* Splits a NAME,NAME... option in place; an empty item (',,', a ',' at
 * either end) or a name given twice is refused, naming it. */
static int split_list(char *text, char **out, int max, const char *opt)
{
	int n = 0;
	char *all = strdup(text);
	for (char *tok = text, *next; tok; tok = next) {
		next = strchr(tok, ',');
		if (next)
			*next++ = '\0';
		if (!tok[0]) {
			fprintf(stderr, "popc sweep stats: %s %s: item %d is empty\n", opt,
				all ? all : "", n + 1);
			free(all);
			return -1;
		}
		for (int k = 0; k < n; k++)
			if (strcmp(out[k], tok) == 0) {
				fprintf(stderr, "popc sweep stats: %s %s: '%s' given twice (items %d and "
						"%d)\n", opt, all ? all : "", tok, k + 1, n + 1);
				free(all);
				return -1;
			}
		if (n == max) {
			fprintf(stderr, "popc sweep stats: %s: at most %d names\n", opt, max);
			free(all);
			return -1;
		}
		out[n++] = tok;
	}
	free(all);
	return n;
}

/* A group's value in a markdown table cell: '|' would end the cell. */
static void put_markdown_cell(const char *v)
{
	for (; *v; v++) {
		if (*v == '|' || *v == '\\')
			putchar('\\');
		putchar(*v);
	}
}

static void put_number(FILE *f, double v, int shortest)
{
	if (shortest) {
		char b[POPC_DOUBLE_TEXT_MAX + 1];
		popc_format_double(v, b);
		fputs(b, f);
	} else {
		fprintf(f, "%.3g", v);
	}
}

/* A CSV cell, quoted (RFC 4180) where it holds ',', '"' or a line break: a
 * group's value is a --vary value as summary.csv holds it, and a table
 * intent's path may hold a comma. */
static void put_csv_cell(FILE *f, const char *cell)
{
	if (!strpbrk(cell, ",\"\r\n")) {
		fputs(cell, f);
		return;
	}
	fputc('"', f);
	for (const char *p = cell; *p; p++) {
		if (*p == '"')
			fputc('"', f);
		fputc(*p, f);
	}
	fputc('"', f);
}

static const popc_option stats_options[] = {
	{"by", 0, 'b', "KEY[,KEY...]"},
	{"metrics", 0, 'm', "NAME[,NAME...]"},
	{"format", 0, 'f', "text|csv|markdown|json"},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const popc_cli_sweep_stats_opts[] = {stats_options, NULL};

int popc_cmd_sweep_stats(int argc, char **argv)
{
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_sweep_stats_opts, opts, shorts);
	char *by_text = NULL, *metrics_text = NULL;
	char default_metrics[] = STATS_DEFAULT_METRICS;
	int format = 0; /* 0 text, 1 csv, 2 markdown, 3 json (csv's rows as objects) */
	int c;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case 'b': by_text = optarg; break;
		case 'm': metrics_text = optarg; break;
		case 'f':
			if (strcmp(optarg, "text") == 0)
				format = 0;
			else if (strcmp(optarg, "csv") == 0)
				format = 1;
			else if (strcmp(optarg, "markdown") == 0 || strcmp(optarg, "md") == 0)
				format = 2;
			else if (strcmp(optarg, "json") == 0)
				format = 3;
			else {
				fprintf(stderr, "popc sweep stats: --format '%s': text, csv, markdown or "
						"json\n", optarg);
				return POPC_EXIT_USAGE;
			}
			break;
		case 'h': usage(stdout); return 0;
		default: usage(stderr); return POPC_EXIT_USAGE;
		}
	}
	if (optind + 1 != argc || !by_text) {
		fprintf(stderr, "popc sweep stats: %s\n",
			optind >= argc ? "missing DIR" : optind + 1 != argc ? "more than one DIR"
									 : "missing --by KEY[,KEY...]");
		usage(stderr);
		return POPC_EXIT_USAGE;
	}
	const char *dir = argv[optind];
	char *by[STATS_MAX_BY], *metric[STATS_MAX_METRICS];
	int n_by = split_list(by_text, by, STATS_MAX_BY, "--by");
	int n_m = split_list(metrics_text ? metrics_text : default_metrics, metric, STATS_MAX_METRICS,
			     "--metrics");
	if (n_by < 0 || n_m < 0)
		return POPC_EXIT_USAGE;
	for (int m = 0; m < n_m; m++)
		if (!metric_known(metric[m])) {
			fprintf(stderr, "popc sweep stats: --metrics: '%s' is not a metric column of a "
					"sweep summary (see --help)\n", metric[m]);
			return POPC_EXIT_USAGE;
		}

	char path[4096];
	snprintf(path, sizeof path, "%s/summary.csv", dir);
	FILE *f = fopen(path, "r");
	if (!f) {
		fprintf(stderr, "popc sweep stats: %s: %s\n", path, strerror(errno));
		return POPC_EXIT_USAGE;
	}
	char *line = NULL;
	size_t cap = 0;
	enum { MAX_CELLS = 256 };
	char *cells[MAX_CELLS];
	int rc = 2, n_header, by_col[STATS_MAX_BY], m_col[STATS_MAX_METRICS], status_col = -1;
	group *groups = NULL;
	int n_groups = 0, n_failed = 0;
	long long lineno = 1;
	if (getline(&line, &cap, f) < 0 || (n_header = split_csv(line, cells, MAX_CELLS)) < 1) {
		fprintf(stderr, "popc sweep stats: %s: no header line\n", path);
		goto out;
	}
	for (int i = 0; i < n_by; i++)
		by_col[i] = -1;
	for (int i = 0; i < n_m; i++)
		m_col[i] = -1;
	for (int j = 0; j < n_header; j++) {
		if (strcmp(cells[j], "exit_status") == 0)
			status_col = j;
		for (int i = 0; i < n_by; i++)
			if (strcmp(cells[j], by[i]) == 0)
				by_col[i] = j;
		for (int i = 0; i < n_m; i++)
			if (strcmp(cells[j], metric[i]) == 0)
				m_col[i] = j;
	}
	if (status_col < 0) {
		fprintf(stderr, "popc sweep stats: %s: no exit_status column: not a sweep summary\n",
			path);
		goto out;
	}
	for (int i = 0; i < n_by; i++)
		if (by_col[i] < 0 || by_col[i] == 0 || by_col[i] >= status_col) {
			fprintf(stderr, "popc sweep stats: --by %s: %s %s (the varied keys are its "
					"columns between 'run' and 'exit_status')\n", by[i], path,
				by_col[i] < 0 ? "has no such column" : "names no varied key there");
			goto out;
		}
	for (int i = 0; i < n_m; i++)
		if (m_col[i] < 0) {
			fprintf(stderr, "popc sweep stats: --metrics %s: %s has no such column\n",
				metric[i], path);
			goto out;
		}
	while (getline(&line, &cap, f) >= 0) {
		lineno++;
		int n = split_csv(line, cells, MAX_CELLS);
		if (n == 1 && cells[0][0] == '\0')
			continue;
		if (n != n_header) {
			fprintf(stderr, "popc sweep stats: %s:%lld: %d cells, the header has %d\n", path,
				lineno, n, n_header);
			goto out;
		}
		if (strcmp(cells[status_col], "0") != 0) {
			n_failed++;
			continue;
		}
		char key[1024];
		size_t len = 0;
		for (int i = 0; i < n_by; i++)
			len += (size_t)snprintf(key + len, len < sizeof key ? sizeof key - len : 0,
						"%s%s", i ? "\x1f" : "", cells[by_col[i]]);
		int g = 0;
		while (g < n_groups && strcmp(groups[g].key, key) != 0)
			g++;
		if (g == n_groups) {
			group *ng = realloc(groups, (size_t)(n_groups + 1) * sizeof *groups);
			if (!ng)
				goto oom;
			groups = ng;
			memset(&groups[g], 0, sizeof groups[g]);
			if (!(groups[g].key = strdup(key)))
				goto oom;
			n_groups++;
		}
		group *gr = &groups[g];
		gr->n_runs++;
		for (int i = 0; i < n_m; i++) {
			const char *cell = cells[m_col[i]];
			if (!cell[0])
				continue; /* not checked: no value, not a zero */
			double v;
			if (popc_parse_double_text(cell, &v) != POPC_PARSE_OK || !isfinite(v)) {
				fprintf(stderr, "popc sweep stats: %s:%lld: column %s: not a finite number "
						"'%s'\n", path, lineno, metric[i], cell);
				goto out;
			}
			if (gr->n[i] == gr->cap[i]) {
				int nc = gr->cap[i] ? 2 * gr->cap[i] : 16;
				double *nv = realloc(gr->v[i], (size_t)nc * sizeof *nv);
				if (!nv)
					goto oom;
				gr->v[i] = nv;
				gr->cap[i] = nc;
			}
			gr->v[i][gr->n[i]++] = v;
		}
	}

	/* header; csv and json go through the table writer (json: the csv's rows
	 * as objects, the same cells; a group's value as the summary.jsonl types
	 * it, a number where it reads as one) */
	popc_table_out table;
	int tabled = format == 1 || format == 3;
	if (tabled) {
		char header[STATS_MAX_BY * 160 + 64];
		size_t hl = 0;
		for (int i = 0; i < n_by; i++)
			hl += (size_t)snprintf(header + hl, sizeof header - hl, "%s,", by[i]);
		snprintf(header + hl, sizeof header - hl, "metric,n,median,min,q1,q3,max");
		static const char *const text_columns[] = {"metric", NULL};
		if (popc_table_out_begin(&table, stdout, format == 3, header, text_columns) != 0)
			goto oom;
		for (int i = 0; i < n_by && format == 3; i++)
			table.kinds[i] = POPC_JSON_AUTO;
	} else {
		const char *sep = format == 2 ? " | " : "  ";
		printf("%s", format == 2 ? "| " : "");
		for (int i = 0; i < n_by; i++)
			printf("%s%s", by[i], sep);
		printf("runs");
		for (int i = 0; i < n_m; i++)
			printf("%s%s", sep, metric[i]);
		puts(format == 2 ? " |" : "");
		if (format == 2) {
			printf("|");
			for (int i = 0; i < n_by + 1 + n_m; i++)
				printf("---|");
			putchar('\n');
		}
	}
	for (int g = 0; g < n_groups; g++) {
		group *gr = &groups[g];
		char *kv[STATS_MAX_BY];
		char *save = gr->key;
		for (int i = 0; i < n_by; i++) {
			kv[i] = save;
			save += strcspn(save, "\x1f");
			if (*save)
				*save++ = '\0';
		}
		if (format == 2)
			printf("| ");
		for (int i = 0; i < n_by && !tabled; i++) {
			if (format == 2)
				put_markdown_cell(kv[i]);
			else
				fputs(kv[i], stdout);
			fputs(format == 2 ? " | " : "  ", stdout);
		}
		if (!tabled)
			printf("%d", gr->n_runs);
		for (int i = 0; i < n_m; i++) {
			int n = gr->n[i];
			if (n)
				qsort(gr->v[i], (size_t)n, sizeof(double), cmp_double);
			if (tabled) {
				FILE *o = popc_table_out_row(&table);
				for (int j = 0; j < n_by; j++) {
					put_csv_cell(o, kv[j]);
					fputc(',', o);
				}
				fprintf(o, "%s,%d", metric[i], n);
				const double p[] = {0.5, 0.0, 0.25, 0.75, 1.0};
				for (int j = 0; j < 5; j++) {
					fputc(',', o);
					if (n)
						put_number(o, quantile(gr->v[i], n, p[j]), 1);
				}
				fputc('\n', o);
				if (popc_table_out_flush(&table) != 0)
					goto oom;
				continue;
			}
			printf("%s", format == 2 ? " | " : "  ");
			if (!n) {
				printf("n/a");
				continue;
			}
			put_number(stdout, quantile(gr->v[i], n, 0.5), 0);
			printf(" [");
			put_number(stdout, gr->v[i][0], 0);
			printf(", ");
			put_number(stdout, gr->v[i][n - 1], 0);
			printf("]");
			if (n < gr->n_runs)
				printf(" (n=%d)", n);
		}
		if (!tabled)
			puts(format == 2 ? " |" : "");
	}
	if (tabled)
		popc_table_out_end(&table);
	if (n_failed)
		fprintf(stderr, "popc sweep stats: note: %d failed run%s left out\n", n_failed,
			n_failed == 1 ? "" : "s");
	rc = 0;
	goto out;
oom:
	fprintf(stderr, "popc sweep stats: out of memory\n");
	rc = POPC_EXIT_RUN_FAILED;
out:
	for (int g = 0; g < n_groups; g++) {
		free(groups[g].key);
		for (int i = 0; i < n_m; i++)
			free(groups[g].v[i]);
	}
	free(groups);
	free(line);
	fclose(f);
	return rc;
}
