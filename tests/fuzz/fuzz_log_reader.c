/* Log reader harness: a log read as popc-analyze reads it (analysis/common.c:
 * --delimiter, --decimal, --comment, --column options, only popc's columns
 * parsed, a popc log's header turned into its scene), with the properties of
 * log_reader.h: a row holds finite numbers in every parsed column and
 * increasing time, every error of a row names the file and that row's line.
 *
 * Input: byte 0 picks the options, byte 1 bit 0 says that the next line holds
 * --column mappings (NAME=HEADER separated by blanks, HEADER "#N" a position),
 * bit 1 --no-header; the rest is the log. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "popc/log/log_reader.h"
#include "popc/scene/scene.h"

/* as popc-analyze accepts them: one character, not a digit, '.', '+' or '-' */
static const char delimiters[8] = {0, ',', ';', '\t', ' ', '|', 0, ';'};
static const char decimals[4] = {0, '.', ',', 0};
static const char comments[4] = {0, '#', '%', '!'};

/* popc-analyze's columns (analysis/common.c) */
static const char *const popc_columns[] = {"t",   "x",     "count", "x_true", "v",
					   "f_e", "f_pc",  "f_c",   "W",      "E_ref",
					   "flags", "dt", "rtt"};

int popc_fuzz_log_reader(const uint8_t *data, size_t size)
{
	if (size < 2)
		return 0;
	popc_log_reader_options opt;
	memset(&opt, 0, sizeof opt);
	opt.delimiter = delimiters[data[0] & 7];
	opt.decimal = decimals[(data[0] >> 3) & 3];
	opt.comment = comments[(data[0] >> 5) & 3];
	const int all_columns = (data[0] >> 7) & 1; /* else popc-analyze's choice */
	opt.no_header = (data[1] >> 1) & 1;
	const uint8_t *file = data + 2;
	size_t file_size = size - 2;
	char maps[512] = "";
	if (data[1] & 1) {
		const uint8_t *nl = memchr(file, '\n', file_size);
		if (!nl)
			return 0;
		size_t n = (size_t)(nl - file);
		if (n >= sizeof maps || memchr(file, '\0', n))
			return 0;
		memcpy(maps, file, n);
		maps[n] = '\0';
		file = nl + 1;
		file_size -= n + 1;
		popc_error err;
		for (char *tok = strtok(maps, " "); tok; tok = strtok(NULL, " "))
			if (popc_log_reader_add_mapping(&opt, tok, &err) != 0)
				return 0; /* popc-analyze stops at a bad --column */
	}
	char path[64];
	int fd = popc_fuzz_file(file, file_size, path, sizeof path);
	if (fd < 0)
		return 0;
	const long long lines = popc_fuzz_count_lines(file, file_size);
	popc_log_reader r;
	popc_error err;
	err.msg[0] = '\0';
	int st = popc_log_reader_open(&r, path, &opt, &err);
	if (st != 0) {
		/* the file, and where there is a line, one of its lines */
		if (strncmp(err.msg, path, strlen(path)) != 0)
			popc_fuzz_fail(data, size, "open error without the path: %s", err.msg);
		const char *p = err.msg + strlen(path);
		if (p[0] == ':' && p[1] >= '0' && p[1] <= '9' &&
		    !popc_fuzz_names_line(err.msg, path, lines, NULL))
			popc_fuzz_fail(data, size, "open error naming a line not in the file (%lld lines): %s",
				       lines, err.msg);
		popc_fuzz_file_close(fd);
		return 0;
	}
	if (r.n_cols < 1 || r.n_cols > POPC_LOG_MAX_COLUMNS)
		popc_fuzz_fail(data, size, "%d columns", r.n_cols);
	/* a comment mark that is the delimiter would drop rows with an empty
	 * first cell (issue 28) */
	if (r.comment == r.delimiter)
		popc_fuzz_fail(data, size, "comment mark and delimiter both '%c'", r.comment);
	/* a first line of numbers taken for names when every mapping is a
	 * position would lose that row without a word (issue 28) */
	if (r.names_numeric && opt.n_map > 0) {
		int by_name = 0;
		for (int i = 0; i < opt.n_map; i++)
			by_name |= popc_log_reader_position(opt.map_header[i]) == 0;
		if (!by_name)
			popc_fuzz_fail(data, size, "a names line of numbers taken, every column by position");
	}
	if (!all_columns) {
		int used[sizeof popc_columns / sizeof popc_columns[0]], n_used = 0;
		for (size_t i = 0; i < sizeof popc_columns / sizeof popc_columns[0]; i++) {
			int c = popc_log_reader_column(&r, popc_columns[i]);
			if (c >= r.n_cols)
				popc_fuzz_fail(data, size, "column %s at %d of %d", popc_columns[i], c,
					       r.n_cols);
			if (c >= 0)
				used[n_used++] = c;
		}
		if (popc_log_reader_use_columns(&r, used, n_used) != 0)
			popc_fuzz_fail(data, size, "use_columns refused valid columns");
	}
	if (popc_log_reader_header(&r, "format") && popc_log_reader_header(&r, "source")) {
		/* a popc log: popc-analyze rebuilds its scene from the header */
		popc_scene s;
		popc_scene_defaults(&s);
		popc_error serr;
		if (popc_log_reader_scene(&r, &s, &serr) == 0)
			(void)popc_scene_validate(&s, &serr);
	}
	double row[POPC_LOG_MAX_COLUMNS];
	long long rows = 0;
	double t_prev = 0.0;
	for (;;) {
		int got = popc_log_reader_next(&r, row, &err);
		if (got == 0)
			break;
		if (got < 0) {
			long long line;
			/* the row's line, or the next one when it could not be read
			 * as one (too long, a NUL byte) */
			if (!popc_fuzz_names_line(err.msg, path, lines, &line) ||
			    (line != r.lineno && line != r.lineno + 1))
				popc_fuzz_fail(data, size,
					       "row error not naming its line (%lld, file of %lld lines): %s",
					       r.lineno, lines, err.msg);
			break;
		}
		if (got != 1)
			popc_fuzz_fail(data, size, "next returned %d", got);
		/* under a tab delimiter a row has one cell per column, an empty
		 * one too (issue 28: "\t\t" was skipped as padding) */
		if (r.delimiter == '\t' && r.lineno >= 1) {
			const uint8_t *p = file, *end = file + file_size;
			for (long long i = 1; p && i < r.lineno; i++) {
				p = memchr(p, '\n', (size_t)(end - p));
				p = p ? p + 1 : NULL;
			}
			const uint8_t *e = p ? memchr(p, '\n', (size_t)(end - p)) : NULL;
			if (p && !e)
				e = end;
			if (p && !memchr(p, '"', (size_t)(e - p))) {
				int tabs = 0;
				for (const uint8_t *q = p; q < e; q++)
					tabs += *q == '\t';
				if (tabs != r.n_cols - 1)
					popc_fuzz_fail(data, size, "line %lld: %d tabs read as %d columns",
						       r.lineno, tabs, r.n_cols);
			}
		}
		for (int i = 0; i < r.n_cols; i++)
			if (r.parse[i] && !isfinite(row[i]))
				popc_fuzz_fail(data, size, "line %lld column %d: %g without an error",
					       r.lineno, i + 1, row[i]);
		if (r.t_col >= 0) {
			if (rows > 0 && !(row[r.t_col] > t_prev))
				popc_fuzz_fail(data, size, "line %lld: time %.17g after %.17g", r.lineno,
					       row[r.t_col], t_prev);
			t_prev = row[r.t_col];
		}
		rows++;
	}
	popc_log_reader_close(&r);
	popc_fuzz_file_close(fd);
	return 0;
}
