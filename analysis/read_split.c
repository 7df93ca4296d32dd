/* Signals split across files (one file per quantity, no time column: the
 * position in one, the force in another), joined row by row into one CSV
 * stream for ana_log_open (read_foreign.h). Each file is read by the log
 * reader with the log's options (delimiter, decimal mark, --no-header), so
 * its cells are checked and named with its own line; the files must end
 * together. Memory is constant in the length of the files. */
#include <stdlib.h>
#include <string.h>

#include "read_foreign.h"
#include "popc/util/numfmt.h"

static void close_all(popc_log_reader *r, int n)
{
	for (int i = 0; i < n; i++)
		popc_log_reader_close(&r[i]);
}

int ana_join_to_csv(const char *path, const ana_foreign_options *o,
		    const popc_log_reader_options *in, FILE *out, int *wrote_names,
		    popc_error *err)
{
	const int n = 1 + o->n_join;
	popc_log_reader r[1 + ANA_MAX_JOIN];
	popc_log_reader_options each = *in;
	each.n_map = 0; /* the map is the joined log's, read later */
	int st = 0, opened = 0, total = 0;
	for (; opened < n; opened++) {
		const char *p = opened ? o->join[opened - 1] : path;
		if ((st = popc_log_reader_open(&r[opened], p, &each, err)) != 0)
			goto done;
		total += r[opened].n_cols;
	}
	if (total > POPC_LOG_MAX_COLUMNS) {
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: --join: %d columns in all, at most %d", path, total,
				    POPC_LOG_MAX_COLUMNS);
		goto done;
	}
	/* a headerless file's columns are numbered across the files (#1 of the
	 * second file is the joined log's #(n_cols of the first + 1)) */
	*wrote_names = !in->no_header;
	if (*wrote_names) {
		int first = 1;
		for (int i = 0; i < n; i++)
			for (int j = 0; j < r[i].n_cols; j++) {
				if (!first)
					fputc(',', out);
				first = 0;
				ana_foreign_put_name(out, r[i].col_name[j]);
			}
		fputc('\n', out);
	}
	double row[POPC_LOG_MAX_COLUMNS];
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	for (long long k = 1;; k++) {
		int ended = -1, going = -1;
		for (int i = 0; i < n; i++) {
			int got = popc_log_reader_next(&r[i], row, err);
			if (got < 0) {
				st = got;
				goto done;
			}
			if (got == 0) {
				ended = i;
				continue;
			}
			going = i;
			for (int j = 0; j < r[i].n_cols; j++) {
				if (i || j)
					fputc(',', out);
				popc_format_double(row[j], b);
				fputs(b, out);
			}
		}
		if (ended >= 0 && going >= 0) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s: --join: ragged files: %s ends after %lld rows (line "
					    "%lld), %s has row %lld (line %lld); split files must hold "
					    "the same rows",
					    path, r[ended].path, k - 1, r[ended].last_row_line,
					    r[going].path, k, r[going].lineno);
			goto done;
		}
		if (ended >= 0)
			break;
		fputc('\n', out);
	}
	if (ferror(out))
		st = popc_error_set(err, POPC_ERR_IO, "%s: --join: cannot write the joined rows", path);
done:
	close_all(r, opened);
	return st;
}
