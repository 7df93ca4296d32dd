/* Recorded-log harness: a log read as popc-analyze reads it, through its own
 * option parsing and log layer (analysis/common.c: ana_input_option,
 * ana_log_open, ana_log_next), under the input options a user combines for a
 * recorded device log (--delimiter, --comment, --decimal, --no-header,
 * --column, --scale, --set, --jitter; a MAT file's --variable, --names and
 * --lever: an input whose log starts with a MAT header, "MATLAB ", is read
 * through libmatio as popc-analyze reads one, docs/ANALYSIS.md; the corpus
 * holds MAT v5 seeds, plain and compressed, made by tests/analyze/make_mat:
 * mat-v5*-names, -columns, -swt, and what libFuzzer found from them: damaged
 * nested headers libmatio crashed on or allocated gigabytes for, now refused
 * by analysis/read_mat_check.c). Properties:
 *   - an option popc-analyze refuses stops the run (exit 2), as it does;
 *   - an error names the log (and, for a row, a line of the file);
 *   - every row handed out is finite (no NaN or infinity reaches a force,
 *     an energy, a position) and its time increases;
 *   - the rules of issue 28: the comment mark is not the delimiter; a first
 *     line of numbers is not taken for names when every --column is a
 *     position; a row read under a tab delimiter without quotes has one cell
 *     per column (an empty cell is a cell); a popc run log's time steps are
 *     its header's period within 1 % (ANA_PERIOD_REL_TOL).
 *
 * Input: the first line holds popc-analyze's option words separated by
 * blanks ("--delimiter tab --comment % --no-header --column x=#1"); the rest
 * is the log. */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "analyze.h"
#include "fuzz.h"

static const struct {
	const char *name;
	int opt, has_arg;
} options[] = {
	{"--column", ANA_OPT_COLUMN, 1},     {"--delimiter", ANA_OPT_DELIMITER, 1},
	{"--comment", ANA_OPT_COMMENT, 1},   {"--set", ANA_OPT_SET, 1},
	{"--scale", ANA_OPT_SCALE, 1},       {"--decimal", ANA_OPT_DECIMAL, 1},
	{"--no-header", ANA_OPT_NO_HEADER, 0}, {"--jitter", ANA_OPT_JITTER, 1},
	{"--variable", ANA_OPT_VARIABLE, 1}, {"--names", ANA_OPT_NAMES, 1},
	{"--lever", ANA_OPT_LEVER, 1},
};

/* popc-analyze prints a refused option on stderr: not on every fuzz input */
static int quiet_stderr(void)
{
	static int null_fd = -2;
	if (null_fd == -2)
		null_fd = open("/dev/null", O_WRONLY);
	if (null_fd < 0)
		return -1;
	fflush(stderr);
	int saved = dup(2);
	if (saved >= 0)
		dup2(null_fd, 2);
	return saved;
}

static void restore_stderr(int saved)
{
	if (saved < 0)
		return;
	fflush(stderr);
	dup2(saved, 2);
	close(saved);
}

/* Parses the option words; 0, or 1 when an option is refused or unknown (the
 * run stops, as popc-analyze exits 2). The words stay in words[], which the
 * options point into. */
static int parse_options(char *words, ana_input_options *o)
{
	char *save = NULL;
	for (char *w = strtok_r(words, " \t", &save); w; w = strtok_r(NULL, " \t", &save)) {
		size_t i = 0;
		while (i < sizeof options / sizeof options[0] && strcmp(options[i].name, w) != 0)
			i++;
		if (i == sizeof options / sizeof options[0])
			return 1;
		char *arg = NULL;
		if (options[i].has_arg && (arg = strtok_r(NULL, " \t", &save)) == NULL)
			return 1;
		const int saved = quiet_stderr();
		const int rc = ana_input_option(o, options[i].opt, arg, "fuzz");
		restore_stderr(saved);
		if (rc != 0)
			return 1;
	}
	return 0;
}

/* The text of line n (1-based) of file[0 .. size-1], without its end of
 * line; NULL past the end. */
static const uint8_t *line_at(const uint8_t *file, size_t size, long long n, size_t *len)
{
	const uint8_t *p = file, *end = file + size;
	for (long long i = 1; i < n; i++) {
		const uint8_t *nl = memchr(p, '\n', (size_t)(end - p));
		if (!nl)
			return NULL;
		p = nl + 1;
	}
	const uint8_t *nl = memchr(p, '\n', (size_t)(end - p));
	*len = (size_t)((nl ? nl : end) - p);
	if (*len && p[*len - 1] == '\r')
		(*len)--;
	return p;
}

/* a broken property: stderr back first, for the report */
#define FAIL(...)                                                                                  \
	do {                                                                                       \
		restore_stderr(saved);                                                             \
		popc_fuzz_fail(data, size, __VA_ARGS__);                                           \
	} while (0)

int popc_fuzz_analyze_input(const uint8_t *data, size_t size)
{
	const uint8_t *nl = memchr(data, '\n', size);
	if (!nl || nl - data >= 400 || memchr(data, '\0', (size_t)(nl - data)))
		return 0;
	char words[400];
	memcpy(words, data, (size_t)(nl - data));
	words[nl - data] = '\0';
	const uint8_t *file = nl + 1;
	const size_t file_size = size - (size_t)(nl + 1 - data);

	ana_input_options o;
	memset(&o, 0, sizeof o);
	o.verb = "fuzz";
	o.quiet = 1;
	if (parse_options(words, &o) != 0) {
		ana_input_free(&o);
		return 0;
	}
	/* what the options refuse, the parse refused */
	if (o.reader.comment && o.reader.comment == o.reader.delimiter)
		popc_fuzz_fail(data, size, "--comment '%c' and --delimiter '%c' accepted together",
			       o.reader.comment, o.reader.delimiter);

	/* the notes of an unfinished log, silenced for every input (not -q's) */
	int saved = quiet_stderr();
	char path[64];
	int fd = popc_fuzz_file(file, file_size, path, sizeof path);
	if (fd < 0) {
		restore_stderr(saved);
		ana_input_free(&o);
		return 0;
	}
	const long long lines = popc_fuzz_count_lines(file, file_size);
	/* a MAT file is read as the CSV it is converted to (read_foreign.h): its
	 * row errors name a line of that text, not of these bytes, so for it
	 * only the file's name is checked */
	const int is_mat = file_size >= 7 && memcmp(file, "MATLAB ", 7) == 0;
	ana_log l;
	popc_error err;
	err.msg[0] = '\0';
	int st = ana_log_open(&l, path, &o, &err);
	if (st != 0) {
		if (strncmp(err.msg, path, strlen(path)) != 0 && strncmp(err.msg, "--set", 5) != 0)
			FAIL("open error without the path: %s", err.msg);
		const char *p = err.msg + strlen(path);
		if (!is_mat && strncmp(err.msg, path, strlen(path)) == 0 && p[0] == ':' && p[1] >= '0' &&
		    p[1] <= '9' && !popc_fuzz_names_line(err.msg, path, lines, NULL))
			FAIL("open error naming a line not in the file (%lld lines): %s",
				       lines, err.msg);
		goto out;
	}
	const popc_log_reader *r = &l.r;
	if (r->comment == r->delimiter)
		FAIL("comment mark and delimiter both '%c'", r->comment);
	if (r->names_numeric && !o.reader.no_header && o.reader.n_map > 0) {
		int by_name = 0;
		for (int i = 0; i < o.reader.n_map; i++)
			by_name |= popc_log_reader_position(o.reader.map_header[i]) == 0;
		if (!by_name)
			FAIL("a names line of numbers taken with every column by position");
	}
	/* a popc run log whose time column reads unscaled is checked against its
	 * rate (a replay log's stamps by their mean, after the last row) */
	const char *source = popc_log_reader_header(r, "source");
	const int run_log = l.is_popc && source && strcmp(source, "replay") != 0 && l.c_t >= 0 &&
			    l.scale[l.c_t] == 1.0 && !l.period_from_time;
	ana_row row;
	double t_prev = 0.0;
	long long k = 0;
	while ((st = ana_log_next(&l, &row, &err)) == 1) {
		const popc_tick *t = &row.tick;
		const double v[] = {t->t_s, t->x_m, t->v_mps, t->f_e_N, t->f_pc_N, t->f_c_N, t->W_J,
				    t->E_ref_J, row.step_s};
		for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
			if (!isfinite(v[i]))
				FAIL("line %lld: value %zu is %g without an error",
					       row.line, i, v[i]);
		if (k > 0 && !(t->t_s > t_prev))
			FAIL("line %lld: time %.17g after %.17g", row.line, t->t_s,
				       t_prev);
		if (run_log && k > 0 &&
		    !(fabs(t->t_s - t_prev - l.period_s) <= ANA_PERIOD_REL_TOL * l.period_s))
			FAIL("line %lld: a step of %.17g s in a log of period %.17g s",
				       row.line, t->t_s - t_prev, l.period_s);
		/* under a tab delimiter, a row without quotes has one cell per
		 * column: n - 1 tabs (an empty cell is one of them) */
		size_t len;
		const uint8_t *text = line_at(file, file_size, row.line, &len);
		if (!is_mat && r->delimiter == '\t' && text && !memchr(text, '"', len)) {
			int tabs = 0;
			for (size_t i = 0; i < len; i++)
				tabs += text[i] == '\t';
			if (tabs != r->n_cols - 1)
				FAIL("line %lld: %d tabs read as %d columns", row.line,
					       tabs, r->n_cols);
		}
		t_prev = t->t_s;
		k++;
	}
	if (st < 0 && is_mat) {
		if (strncmp(err.msg, path, strlen(path)) != 0)
			FAIL("row error of a MAT file without its name: %s", err.msg);
	} else if (st < 0) {
		long long line;
		if (!popc_fuzz_names_line(err.msg, path, lines, &line))
			FAIL("row error not naming a line of the file (%lld lines): %s",
				       lines, err.msg);
	}
	ana_log_close(&l);
out:
	restore_stderr(saved);
	popc_fuzz_file_close(fd);
	ana_input_free(&o);
	return 0;
}
