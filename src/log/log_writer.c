/* CSV log writer (log.h): own buffer and the shortest round-trip number
 * formatter, since formatting, not the plant, is the cost of a logged run. */
#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "popc/log/log.h"
#include "popc/util/numfmt.h"
#include "popc_config.h"

#define LOG_BUFFER_BYTES (1u << 16)
/* every column as a double of at most POPC_DOUBLE_TEXT_MAX characters (a
 * count or flags has at most 20) and its separator */
#define ROW_MAX_BYTES (POPC_LOG_N_COLUMNS * (POPC_DOUBLE_TEXT_MAX + 1))

int popc_log_open(popc_log_writer *w, const char *path, unsigned columns, popc_error *err)
{
	memset(w, 0, sizeof *w);
	w->columns = columns;
	snprintf(w->path, sizeof w->path, "%s", path);
	if (strcmp(path, "-") == 0) {
		w->f = stdout;
	} else {
		w->f = fopen(path, "w");
		if (!w->f)
			return popc_error_set(err, POPC_ERR_IO, "%s: cannot open for writing: %s", path,
					      strerror(errno));
		w->owns_file = 1;
	}
	w->cap = LOG_BUFFER_BYTES;
	w->buf = malloc(w->cap);
	if (!w->buf) {
		if (w->owns_file)
			fclose(w->f);
		w->f = NULL;
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	}
	return 0;
}

static int drain(popc_log_writer *w, popc_error *err)
{
	if (w->len && fwrite(w->buf, 1, w->len, w->f) != w->len)
		return popc_error_set(err, POPC_ERR_IO, "%s: write failed: %s", w->path,
				      strerror(errno));
	w->len = 0;
	return 0;
}

int popc_log_write_header(popc_log_writer *w, const char *source, const popc_scene *s,
			  const char *extra, popc_error *err)
{
	int st = drain(w, err);
	if (st)
		return st;
	fprintf(w->f, "# popc log\n# format = %d\n# popc_version = %s\n# source = %s\n# variant = %s\n",
		POPC_LOG_FORMAT_VERSION, POPC_VERSION, source, popc_variant_name(s->variant));
	if (extra && extra[0])
		fputs(extra, w->f);
	popc_scene_write(s, w->f, "# ");
	char names[POPC_LOG_NAMES_LINE_MAX];
	popc_log_column_names(w->columns, names, sizeof names);
	fprintf(w->f, "%s\n", names);
	if (ferror(w->f))
		return popc_error_set(err, POPC_ERR_IO, "%s: write failed", w->path);
	return 0;
}

static inline char *put_num(char *p, double v)
{
	p += popc_format_double(v, p);
	*p++ = ',';
	return p;
}

static inline char *put_int(char *p, long long v)
{
	char tmp[24];
	int n = 0;
	unsigned long long u = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
	do {
		tmp[n++] = (char)('0' + u % 10);
		u /= 10;
	} while (u);
	if (v < 0)
		*p++ = '-';
	while (n)
		*p++ = tmp[--n];
	*p++ = ',';
	return p;
}

int popc_log_write_row(popc_log_writer *w, const popc_log_row *r, popc_error *err)
{
	if (w->cap - w->len < ROW_MAX_BYTES) {
		int st = drain(w, err);
		if (st)
			return st;
	}
	char *p = w->buf + w->len;
	/* one put per column of the table, inlined: the test of a column that
	 * is always written folds away, the others test the log's column set
	 * (w->columns, not a local copy: the copy takes a register the puts
	 * need, 6 more instructions a row; callgrind, popc bench log) */
#define PUT_DOUBLE put_num
#define PUT_COUNT put_int
#define PUT_FLAGS put_int
#define PUT_CELL(ID, name, unit, fill, format, field, meaning)                                       \
	if (popc_log_column_written(POPC_LOG_COL_##fill, w->columns))                               \
		p = PUT_##format(p, r->field);
	POPC_LOG_COLUMN_TABLE(PUT_CELL)
#undef PUT_CELL
	p[-1] = '\n';
	w->len = (size_t)(p - w->buf);
	return 0;
}

int popc_log_write_comment(popc_log_writer *w, const char *key, const char *value,
			   popc_error *err)
{
	int st = drain(w, err);
	if (st)
		return st;
	fprintf(w->f, "# %s = %s\n", key, value);
	return 0;
}

int popc_log_flush(popc_log_writer *w, popc_error *err)
{
	if (!w->f)
		return 0;
	int st = drain(w, err);
	if (st)
		return st;
	if (fflush(w->f) != 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: flush failed: %s", w->path,
				      strerror(errno));
	return 0;
}

int popc_log_close(popc_log_writer *w, popc_error *err)
{
	int st = popc_log_flush(w, err);
	if (w->f && w->owns_file && fclose(w->f) != 0 && !st)
		st = popc_error_set(err, POPC_ERR_IO, "%s: close failed: %s", w->path, strerror(errno));
	w->f = NULL;
	free(w->buf);
	w->buf = NULL;
	return st;
}
