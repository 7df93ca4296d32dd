/* CSV log writer (log.h): own buffer and the shortest round-trip number
 * formatter, since formatting, not the plant, is the cost of a logged run;
 * write(2) of whole lines, so that a failed write leaves whole lines only.
 * A floating-point cell always has a decimal point ("0.0", not "0";
 * popc_format_double_point) so that CSV sniffers type its column as floating
 * point even where the cells they sample are all integral (docs/READING.md). */
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popc/log/log.h"
#include "popc/scene/delay_trace.h"
#include "popc/util/numfmt.h"
#include "popc_config.h"

#define LOG_BUFFER_BYTES (1u << 16)
/* every column as a double of at most POPC_DOUBLE_TEXT_MAX characters (a
 * count or flags has at most 20) and its separator */
#define ROW_MAX_BYTES (POPC_LOG_N_COLUMNS * (POPC_DOUBLE_TEXT_MAX + 1))

/* A double cell, through a small cache of each column's recent texts: a
 * direct-mapped table of CACHE_SLOTS values per column, by a hash of the
 * value's bits. A device at rest and the controller's quantized outputs
 * repeat a few values: on the paper scene's one-hour log 57 % of the double
 * cells hit 64 slots (x, f_e, f_c and E_ref nearly always; the last value
 * alone: 33 %), and a hit is a compare and two 16-byte moves against about
 * 250 instructions of formatting. Equal bits are the same text, so the log
 * is the same bytes. Every slot starts as +0.0's "0.0": +0.0 hashes to slot
 * 0, and no other slot is ever asked for the bits 0. */
#define CACHE_SLOTS_LOG2 6
#define CACHE_SLOTS (1u << CACHE_SLOTS_LOG2)

typedef struct cache_slot {
	uint64_t bits;
	char text[POPC_DOUBLE_TEXT_MAX + 8]; /* the formatter's 33 bytes; the length in the last */
} cache_slot;

struct popc_log_cell_cache {
	cache_slot slot[POPC_LOG_N_COLUMNS][CACHE_SLOTS];
};

/* The slots of the double columns the log writes (the others are never
 * read: a sweep's run opens a log, and a run that writes 12 columns need
 * not touch the 19 columns' 58 kB). */
static struct popc_log_cell_cache *cache_new(unsigned columns)
{
	struct popc_log_cell_cache *c = malloc(sizeof *c);
	if (!c)
		return NULL;
	for (int col = 0; col < POPC_LOG_N_COLUMNS; col++)
		for (unsigned i = 0; i < CACHE_SLOTS; i++) {
			if (popc_log_columns[col].format != POPC_LOG_CELL_DOUBLE ||
			    !popc_log_column_written(popc_log_columns[col].fill, columns))
				break;
			cache_slot *s = &c->slot[col][i];
			memset(s, 0, sizeof *s);
			memcpy(s->text, "0.0", 3);
			s->text[sizeof s->text - 1] = 3;
		}
	return c;
}

int popc_log_open(popc_log_writer *w, const char *path, unsigned columns, popc_error *err)
{
	memset(w, 0, sizeof *w);
	w->fd = -1;
	w->columns = columns;
	w->at_line_start = 1;
	snprintf(w->path, sizeof w->path, "%s", path);
	if (strcmp(path, "-") == 0) {
		/* rows go out with write(2): anything stdio holds goes first */
		fflush(stdout);
		w->fd = STDOUT_FILENO;
	} else {
		w->fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
		if (w->fd < 0)
			return popc_error_set(err, POPC_ERR_IO, "%s: cannot open for writing: %s", path,
					      strerror(errno));
		w->owns_file = 1;
		struct stat st;
		w->can_cut = fstat(w->fd, &st) == 0 && S_ISREG(st.st_mode);
	}
	w->cap = LOG_BUFFER_BYTES;
	w->buf = malloc(w->cap);
	w->cells = cache_new(columns);
	if (!w->buf || !w->cells) {
		free(w->buf);
		free(w->cells);
		w->buf = NULL;
		w->cells = NULL;
		if (w->owns_file)
			close(w->fd);
		w->fd = -1;
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	}
	return 0;
}

/* write(2) of all n bytes, again after EINTR and after a short write (which
 * the next write turns into the error: ENOSPC, EFBIG). Returns the bytes
 * written; errno says why when fewer than n. */
static size_t write_all(int fd, const char *p, size_t n)
{
	size_t done = 0;
	while (done < n) {
		ssize_t k = write(fd, p + done, n - done);
		if (k > 0) {
			done += (size_t)k;
		} else if (k == 0) {
			errno = ENOSPC; /* a write of nothing: no room (never seen on Linux) */
			return done;
		} else if (errno != EINTR) {
			return done;
		}
	}
	return done;
}

/* After a failed write: the file back to its whole lines, where it can be
 * cut (a regular file popc opened); the next write goes there. */
static void cut_back(popc_log_writer *w)
{
	if (w->can_cut && ftruncate(w->fd, (off_t)w->whole_bytes) == 0 &&
	    lseek(w->fd, (off_t)w->whole_bytes, SEEK_SET) == (off_t)w->whole_bytes)
		w->at_line_start = 1;
}

static int failed(const popc_log_writer *w, popc_error *err)
{
	/* short: it is also the log's stop line, which must fit where the
	 * disk just refused a row */
	return popc_error_set(err, POPC_ERR_IO, "%s: write failed: %s", w->path,
			      strerror(w->failed_errno));
}

/* Writes the buffer out (whole lines). On a failure, the whole lines among
 * the bytes that went out stay, the rest of the file is cut away (cut_back),
 * the buffer is dropped and every later write fails at once. */
static int drain(popc_log_writer *w, popc_error *err)
{
	if (w->failed_errno) {
		w->len = 0;
		return failed(w, err);
	}
	if (!w->len)
		return 0;
	size_t done = write_all(w->fd, w->buf, w->len);
	if (done == w->len) {
		w->whole_bytes += (long long)done;
		w->len = 0;
		return 0;
	}
	w->failed_errno = errno ? errno : EIO;
	size_t whole = done; /* up to the last line end that went out */
	while (whole > 0 && w->buf[whole - 1] != '\n')
		whole--;
	w->whole_bytes += (long long)whole;
	w->at_line_start = whole == done;
	cut_back(w);
	w->len = 0;
	return failed(w, err);
}

/* Room for n more bytes in the buffer (which then may grow: a header). */
static int reserve(popc_log_writer *w, size_t n, popc_error *err)
{
	if (w->cap - w->len >= n)
		return 0;
	int st = drain(w, err);
	if (st || w->cap - w->len >= n)
		return st;
	char *grown = realloc(w->buf, n);
	if (!grown)
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", w->path);
	w->buf = grown;
	w->cap = n;
	return 0;
}

static int append(popc_log_writer *w, const char *text, size_t n, popc_error *err)
{
	int st = reserve(w, n, err);
	if (st)
		return st;
	memcpy(w->buf + w->len, text, n);
	w->len += n;
	return 0;
}

int popc_log_write_header(popc_log_writer *w, const char *source, const popc_scene *s,
			  const char *extra, popc_error *err)
{
	char *text = NULL;
	size_t n = 0;
	FILE *m = open_memstream(&text, &n);
	if (!m)
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", w->path);
	fprintf(m, "# popc log\n# format = %d\n# popc_version = %s\n# source = %s\n# variant = %s\n",
		POPC_LOG_FORMAT_VERSION, POPC_VERSION, source,
		s->tele_arch != POPC_TELEOP_OFF ? popc_teleop_variant_name(s->tele_tdpa, s->tele_drift)
		: s->causality == POPC_CAUSALITY_ADMITTANCE ? popc_admittance_variant_name(s->adm_variant)
							    : popc_variant_name(s->variant));
	if (extra && extra[0])
		fputs(extra, m);
	/* a teleoperation channel's trace: its content's digest beside the path
	 * the scene names, so that a run is reproducible (delay_trace.h) */
	const popc_scene_channel *dir[2] = {&s->fwd, &s->bwd};
	for (int i = 0; s->tele_arch != POPC_TELEOP_OFF && i < 2; i++) {
		popc_delay_trace tr;
		popc_error terr;
		if (dir[i]->trace[0] && popc_delay_trace_load(dir[i]->trace, s->rate_Hz, &tr, &terr) == 0) {
			fprintf(m, "# %s_trace = fnv1a-%016" PRIx64 " (%d delays)\n",
				i ? "backward" : "forward", tr.fnv1a, tr.n);
			popc_delay_trace_free(&tr);
		}
	}
	popc_scene_write(s, m, "# ");
	char names[POPC_LOG_NAMES_LINE_MAX];
	popc_log_column_names(w->columns, names, sizeof names);
	fprintf(m, "%s\n", names);
	int st = fclose(m) != 0 || !text ? popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", w->path)
					 : append(w, text, n, err);
	free(text);
	/* out now: a log that cannot be written stops the run before its first
	 * tick, not 64 KiB of rows later */
	return st ? st : drain(w, err);
}

/* A double cell: see the cache above. */
static inline char *put_num(popc_log_writer *w, int column, char *p, double v)
{
	uint64_t bits;
	memcpy(&bits, &v, sizeof bits);
	cache_slot *s = &w->cells->slot[column][(bits * UINT64_C(0x9e3779b97f4a7c15)) >>
						(64 - CACHE_SLOTS_LOG2)];
	if (s->bits != bits) {
		s->bits = bits;
		s->text[sizeof s->text - 1] = (char)popc_format_double_point(v, s->text);
	}
	/* 32 bytes: the text and what follows it, which the next cells write
	 * over (the row has ROW_MAX_BYTES of room) */
	memcpy(p, s->text, 32);
	p += (unsigned char)s->text[sizeof s->text - 1];
	*p++ = ',';
	return p;
}

static inline char *put_int(popc_log_writer *w, int column, char *p, long long v)
{
	(void)w;
	(void)column;
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
		p = PUT_##format(w, POPC_LOG_COLUMN_##ID, p, r->field);
	POPC_LOG_COLUMN_TABLE(PUT_CELL)
#undef PUT_CELL
	p[-1] = '\n';
	w->len = (size_t)(p - w->buf);
	return 0;
}

int popc_log_write_comment(popc_log_writer *w, const char *key, const char *value,
			   popc_error *err)
{
	char line[POPC_ERROR_MSG_MAX + 64];
	int n = snprintf(line, sizeof line, "# %s = %s\n", key, value);
	if (n < 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: bad comment", w->path);
	if ((size_t)n >= sizeof line) { /* a line end, whatever was cut */
		n = (int)sizeof line - 1;
		line[n - 1] = '\n';
	}
	if (!w->failed_errno)
		return append(w, line, (size_t)n, err);
	/* the log ended in a failed write: the stop line alone, where the whole
	 * lines end (not after a part of a row that could not be cut away), and
	 * away again unless it fits whole */
	if (!w->at_line_start)
		return failed(w, err);
	size_t done = write_all(w->fd, line, (size_t)n);
	if (done == (size_t)n)
		w->whole_bytes += n;
	else
		cut_back(w);
	return failed(w, err);
}

int popc_log_flush(popc_log_writer *w, popc_error *err)
{
	if (w->fd < 0)
		return 0;
	return drain(w, err);
}

int popc_log_close(popc_log_writer *w, popc_error *err)
{
	int st = popc_log_flush(w, err);
	if (w->fd >= 0 && w->owns_file && close(w->fd) != 0 && !st)
		st = popc_error_set(err, POPC_ERR_IO, "%s: close failed: %s", w->path, strerror(errno));
	w->fd = -1;
	free(w->buf);
	w->buf = NULL;
	free(w->cells);
	w->cells = NULL;
	return st;
}
