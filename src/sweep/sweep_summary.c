/* Sweep summary rows and the sweep directory (sweep.h): plan file, per-run
 * summary files written atomically, summary.csv assembled in id order. */
#include "popc/sweep/sweep.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popc/util/atomic_file.h"
#include "popc/util/error.h"
#include "popc/util/numfmt.h"
#include "popc/util/parse.h"

/* The compare metrics of a run, by their names in the popc run summary
 * (run.c: popc_run_summary_csv_header); DESIGN section 4's figures of merit. */
static const char *const metric_columns[] = {
	"ticks",           "pc_rms",      "pc_max",          "pc_active",
	"pc_energy",       "w_minus_eref_min", "w_minus_eref_end", "vsign_rate",
	"pc_rms_late",     "vsign_rate_late",  "integrator_error_m",
};
#define N_METRICS (sizeof metric_columns / sizeof metric_columns[0])

char *popc_sweep_columns_header(const popc_sweep_axis *axes, int n_axes)
{
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	if (!f)
		return NULL;
	fputs("run", f);
	for (int a = 0; a < n_axes; a++)
		fprintf(f, ",%s.%s", axes[a].section, axes[a].key);
	fputs(",exit_status", f);
	for (size_t m = 0; m < N_METRICS; m++)
		fprintf(f, ",%s", metric_columns[m]);
	fputs(",chatter_s,chatter_intervals,limit_cycle,wall_time_s\n", f);
	if (fclose(f) != 0) {
		free(text);
		return NULL;
	}
	return text;
}

/* Splits one CSV line (ending at '\n', '\r' or NUL; no quoting: popc's
 * summaries hold none) into at most max cells. Returns the cell count. */
static int split_cells(const char *line, const char **cell, size_t *len, int max)
{
	int n = 0;
	const char *p = line;
	for (;;) {
		size_t l = strcspn(p, ",\r\n");
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

int popc_sweep_row(const popc_sweep_plan *p, long long i, int exit_status, const char *run_header,
		   const char *run_row, const popc_chatter_result *chatter, double wall_time_s,
		   char *buf, size_t cap, popc_error *err)
{
	const char *hcell[RUN_CSV_MAX_COLUMNS], *rcell[RUN_CSV_MAX_COLUMNS];
	size_t hlen[RUN_CSV_MAX_COLUMNS], rlen[RUN_CSV_MAX_COLUMNS];
	int nh = 0, nr = 0;
	if (run_row) {
		nh = split_cells(run_header, hcell, hlen, RUN_CSV_MAX_COLUMNS);
		nr = split_cells(run_row, rcell, rlen, RUN_CSV_MAX_COLUMNS);
		if (nh > RUN_CSV_MAX_COLUMNS || nr != nh)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "run summary: %d cells in the row, %d in the header", nr, nh);
	}
	char id[POPC_SWEEP_ID_MAX];
	popc_sweep_run_id(p, i, id);
	int idx[64];
	popc_sweep_run_values(p, i, idx);
	size_t len = 0;
#define PUT(...)                                                                                   \
	do {                                                                                       \
		int w_ = snprintf(buf + len, len < cap ? cap - len : 0, __VA_ARGS__);              \
		len += w_ > 0 ? (size_t)w_ : 0;                                                    \
	} while (0)
	PUT("%s", id);
	for (int a = 0; a < p->n_axes; a++)
		PUT(",%s", p->axes[a].values[idx[a]]);
	PUT(",%d", exit_status);
	for (size_t m = 0; m < N_METRICS; m++) {
		if (!run_row) {
			PUT(",");
			continue;
		}
		int c = find_cell(hcell, hlen, nh, metric_columns[m]);
		if (c < 0)
			return popc_error_set(err, POPC_ERR_INVALID, "run summary: no column '%s'",
					      metric_columns[m]);
		PUT(",%.*s", (int)rlen[c], rcell[c]);
	}
	/* a verdict the detector could not reach (a run shorter than one chatter
	 * window, or than half a limit-cycle window) is an empty cell, as in
	 * popc-analyze compare: a 0 would read as "no chatter" in a merge or a
	 * comparison of summaries */
	if (chatter && popc_chatter_checked(chatter)) {
		char cs[POPC_DOUBLE_TEXT_MAX + 1];
		popc_format_double(chatter->chatter_s, cs);
		PUT(",%s,%d", cs, chatter->n_intervals);
	} else {
		PUT(",,");
	}
	if (chatter && popc_chatter_lc_checked(chatter))
		PUT(",%d", chatter->limit_cycle);
	else
		PUT(",");
	char wall[POPC_DOUBLE_TEXT_MAX + 1];
	popc_format_double(wall_time_s, wall);
	PUT(",%s\n", wall);
#undef PUT
	if (len >= cap)
		return popc_error_set(err, POPC_ERR_INVALID, "summary row of run %s longer than %zu bytes",
				      id, cap);
	return (int)len;
}

int popc_sweep_row_exit_status(const popc_sweep_plan *p, const char *row)
{
	const char *cell[RUN_CSV_MAX_COLUMNS + 64];
	size_t len[RUN_CSV_MAX_COLUMNS + 64];
	int n = split_cells(row, cell, len, RUN_CSV_MAX_COLUMNS + 64);
	int c = 1 + p->n_axes;
	long long v;
	if (n <= c || popc_parse_ll_span(cell[c], cell[c] + len[c], 0, 999, 0, &v) != 0)
		return -1;
	return (int)v;
}

int popc_sweep_run_csv_status(const char *run_header, const char *run_row, int *status)
{
	const char *hcell[RUN_CSV_MAX_COLUMNS], *rcell[RUN_CSV_MAX_COLUMNS];
	size_t hlen[RUN_CSV_MAX_COLUMNS], rlen[RUN_CSV_MAX_COLUMNS];
	int nh = split_cells(run_header, hcell, hlen, RUN_CSV_MAX_COLUMNS);
	int nr = split_cells(run_row, rcell, rlen, RUN_CSV_MAX_COLUMNS);
	if (nh > RUN_CSV_MAX_COLUMNS || nr != nh)
		return -1;
	int c = find_cell(hcell, hlen, nh, "status");
	long long v;
	if (c < 0 || popc_parse_ll_span(rcell[c], rcell[c] + rlen[c], INT_MIN, INT_MAX, 0, &v) != 0)
		return -1;
	*status = (int)v;
	return 0;
}

/* ---- files ----------------------------------------------------------------- */

int popc_sweep_mkdir_p(const char *path, popc_error *err)
{
	char buf[POPC_PATH_MAX];
	if (strlen(path) >= sizeof buf)
		return popc_error_set(err, POPC_ERR_IO, "%s: path too long", path);
	strcpy(buf, path);
	for (char *p = buf + 1; *p; p++) {
		if (*p != '/')
			continue;
		*p = '\0';
		if (mkdir(buf, 0777) != 0 && errno != EEXIST)
			return popc_error_set(err, POPC_ERR_IO, "cannot create directory %s: %s", buf,
					      strerror(errno));
		*p = '/';
	}
	if (mkdir(buf, 0777) != 0 && errno != EEXIST)
		return popc_error_set(err, POPC_ERR_IO, "cannot create directory %s: %s", buf,
				      strerror(errno));
	return 0;
}

/* Reads a whole (small) file, NUL-terminated. Returns 1, 0 if it does not
 * exist, or a negative popc_status. */
static int read_file(const char *path, char **out, size_t *out_len, popc_error *err)
{
	*out = NULL;
	int fd = open(path, O_RDONLY);
	if (fd < 0) {
		if (errno == ENOENT || errno == ENOTDIR)
			return 0;
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
	}
	size_t cap = 4096, len = 0;
	char *buf = malloc(cap);
	int st = 1;
	for (;;) {
		if (!buf) {
			st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
			break;
		}
		if (len + 1 >= cap) {
			char *grown = cap > (64u << 20) ? NULL : realloc(buf, cap * 2);
			if (!grown) {
				st = popc_error_set(err, POPC_ERR_NOMEM, "%s: too large", path);
				break;
			}
			buf = grown;
			cap *= 2;
		}
		ssize_t r = read(fd, buf + len, cap - 1 - len);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			st = popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
			break;
		}
		if (r == 0)
			break;
		len += (size_t)r;
	}
	close(fd);
	if (st != 1) {
		free(buf);
		return st;
	}
	buf[len] = '\0';
	*out = buf;
	*out_len = len;
	return 1;
}

/* ---- the plan file ---------------------------------------------------------- */

int popc_sweep_dir_prepare(const popc_sweep_plan *p, const char *dir, const char *scene_path,
			   popc_error *err)
{
	char path[POPC_PATH_MAX + 32];
	int st = popc_sweep_mkdir_p(dir, err);
	if (st)
		return st;
	static const char *const sub[] = {"runs", "rows"};
	for (size_t k = 0; k < 2; k++) {
		snprintf(path, sizeof path, "%s/%s", dir, sub[k]);
		if (mkdir(path, 0777) != 0 && errno != EEXIST) {
			int e = errno;
			return popc_error_set(err, POPC_ERR_IO, "cannot create directory %s: %s%s", path,
					      strerror(e), e == ENOTDIR ? " (is -o a file?)" : "");
		}
	}

	snprintf(path, sizeof path, "%s/sweep.plan", dir);
	struct stat sb;
	if (stat(path, &sb) == 0) {
		popc_sweep_plan old;
		st = popc_sweep_plan_from_dir(&old, dir, err);
		if (st)
			return st;
		uint64_t old_id = old.plan_id;
		popc_sweep_plan_free(&old);
		if (old_id != p->plan_id)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s holds another sweep (plan %016" PRIx64 "; this one is "
					      "%016" PRIx64 ": a different scene, --vary list or popc "
					      "version): choose another -o DIR",
					      path, old_id, p->plan_id);
		return 0;
	}

	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	if (!f)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	fprintf(f, "# popc sweep plan: written by popc sweep, read when the sweep resumes and by\n"
		   "# popc sweep merge. Runs are DIR/runs/<id>; summary.csv has one row per run.\n");
	fprintf(f, "format = 1\nplan_id = %016" PRIx64 "\nruns = %lld\nscene = %s\n", p->plan_id,
		p->n_runs, scene_path);
	for (int a = 0; a < p->n_axes; a++)
		fprintf(f, "vary = %s.%s=%s\n", p->axes[a].section, p->axes[a].key, p->axes[a].spec);
	fprintf(f, "columns = %s", p->columns);
	if (fclose(f) != 0) {
		free(text);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	st = popc_write_file_atomic(path, text, len, err);
	free(text);
	if (st)
		return st;

	f = open_memstream(&text, &len);
	if (!f)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	fprintf(f, "; the base scene of the sweep in %s, resolved (every key)\n", dir);
	popc_scene_write(&p->base, f, "");
	if (fclose(f) != 0) {
		free(text);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	snprintf(path, sizeof path, "%s/scene.ini", dir);
	st = popc_write_file_atomic(path, text, len, err);
	free(text);
	return st;
}

int popc_sweep_plan_from_dir(popc_sweep_plan *p, const char *dir, popc_error *err)
{
	memset(p, 0, sizeof *p);
	char path[POPC_PATH_MAX + 32];
	snprintf(path, sizeof path, "%s/sweep.plan", dir);
	char *text;
	size_t len;
	int st = read_file(path, &text, &len, err);
	if (st == 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: no such file: is %s a popc sweep directory?",
				      path, dir);
	if (st < 0)
		return st;
	popc_sweep_axis *axes = NULL;
	int n_axes = 0, have_id = 0, format = 0;
	long long runs = -1;
	uint64_t plan_id = 0;
	char *columns = NULL;
	int lineno = 0;
	st = 0;
	for (char *line = text, *next; line && *line && !st; line = next) {
		lineno++;
		next = strchr(line, '\n');
		if (next)
			*next++ = '\0';
		if (line[0] == '#' || line[0] == '\0')
			continue;
		char *eq = strstr(line, " = ");
		if (!eq) {
			st = popc_error_set(err, POPC_ERR_INVALID, "%s:%d: expected 'key = value'", path, lineno);
			break;
		}
		*eq = '\0';
		const char *key = line, *value = eq + 3;
		if (strcmp(key, "format") == 0) {
			popc_parse_int_text(value, 0, INT_MAX, &format);
		} else if (strcmp(key, "plan_id") == 0) {
			have_id = popc_parse_u64_span(value, value + strlen(value), UINT64_MAX,
						      POPC_PARSE_BASE16, &plan_id) == 0;
		} else if (strcmp(key, "runs") == 0) {
			popc_parse_ll_text(value, 1, POPC_SWEEP_RUNS_MAX, &runs);
		} else if (strcmp(key, "vary") == 0) {
			popc_sweep_axis *grown = realloc(axes, (size_t)(n_axes + 1) * sizeof *axes);
			if (!grown) {
				st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
				break;
			}
			axes = grown;
			popc_error e;
			if (popc_sweep_axis_parse(value, &axes[n_axes], &e) != 0) {
				st = popc_error_set(err, POPC_ERR_INVALID, "%s:%d: %s", path, lineno, e.msg);
				break;
			}
			n_axes++;
		} else if (strcmp(key, "columns") == 0) {
			free(columns);
			columns = strdup(value);
		}
	}
	free(text);
	if (!st && (format != 1 || !have_id || runs < 1 || !columns))
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: not a popc sweep plan of format 1 (needs format, plan_id, runs, "
				    "columns)",
				    path);
	p->axes = axes;
	p->n_axes = n_axes;
	if (st) {
		popc_sweep_plan_free(p);
		free(columns);
		return st;
	}
	popc_scene_defaults(&p->base);
	p->n_runs = 1;
	for (int a = 0; a < n_axes; a++)
		p->n_runs *= axes[a].n_values;
	p->id_width = 4;
	for (long long m = 10000; m < p->n_runs; m *= 10)
		p->id_width++;
	p->plan_id = plan_id;
	p->columns = popc_sweep_columns_header(axes, n_axes);
	if (!p->columns)
		st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	else if (p->n_runs != runs)
		st = popc_error_set(err, POPC_ERR_INVALID, "%s: runs = %lld, but its vary lines make %lld",
				    path, runs, p->n_runs);
	else if (strncmp(p->columns, columns, strlen(columns)) != 0 ||
		 strlen(p->columns) != strlen(columns) + 1)
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: its columns are not those of this popc version's summary "
				    "(written by another version?)",
				    path);
	free(columns);
	if (st)
		popc_sweep_plan_free(p);
	return st;
}

/* ---- rows files ------------------------------------------------------------ */

int popc_sweep_run_dir(const popc_sweep_plan *p, const char *dir, long long i, char *buf, size_t cap)
{
	char id[POPC_SWEEP_ID_MAX];
	popc_sweep_run_id(p, i, id);
	return (size_t)snprintf(buf, cap, "%s/runs/%s", dir, id) < cap ? 0 : -1;
}

/* Writes all of data, or fails (EINTR retried). */
static int write_all(int fd, const char *data, size_t n)
{
	size_t done = 0;
	while (done < n) {
		ssize_t w = write(fd, data + done, n - done);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0)
			return -1;
		done += (size_t)w;
	}
	return 0;
}

/* The most names tried: HOST.PID.csv, then HOST.PID.1.csv ... .999. More
 * than a few means something else is wrong (a full directory, a loop). */
enum { ROWS_NAMES_MAX = 1000 };

int popc_sweep_rows_open(const popc_sweep_plan *p, const char *dir, long name_pid, popc_error *err)
{
	char host[256], path[POPC_PATH_MAX + 300];
	popc_host_name_for_files(host, sizeof host);
	/* A name of our own, created with O_EXCL: never append to a file an
	 * earlier process of the same pid left (pids repeat across containers,
	 * Slurm nodes and reboots). Such a file may end in a line cut by a kill,
	 * which our first row would join and lose, or in a cut header, which
	 * would make the whole file unreadable. */
	int fd = -1;
	for (int n = 0; n < ROWS_NAMES_MAX && fd < 0; n++) {
		if (n == 0)
			snprintf(path, sizeof path, "%s/rows/%s.%ld.csv", dir, host, name_pid);
		else
			snprintf(path, sizeof path, "%s/rows/%s.%ld.%d.csv", dir, host, name_pid, n);
		fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_APPEND, 0666);
		if (fd < 0 && errno != EEXIST)
			return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
	}
	if (fd < 0)
		return popc_error_set(err, POPC_ERR_IO,
				      "%s: %d rows files of %s.%ld exist already: clean DIR/rows", path,
				      ROWS_NAMES_MAX, host, name_pid);
	if (write_all(fd, p->columns, strlen(p->columns)) != 0) {
		int e = errno;
		close(fd);
		unlink(path);
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(e));
	}
	return fd;
}

int popc_sweep_rows_append(const popc_sweep_plan *p, int fd, long long i, const char *row,
			   int exit_status, const char *reason, popc_error *err)
{
	char buf[POPC_SWEEP_ROW_MAX + 640];
	size_t len = 0;
	if (exit_status != 0 && reason && reason[0]) {
		char id[POPC_SWEEP_ID_MAX];
		popc_sweep_run_id(p, i, id);
		len = (size_t)snprintf(buf, 64, "# %s stop = ", id);
		/* one line: a line break would end the comment */
		for (const char *c = reason; *c && len < 600; c++)
			buf[len++] = (*c == '\n' || *c == '\r') ? ' ' : *c;
		buf[len++] = '\n';
	}
	size_t lr = strlen(row);
	if (len + lr > sizeof buf)
		return popc_error_set(err, POPC_ERR_INVALID, "summary row too long");
	memcpy(buf + len, row, lr);
	len += lr;
	/* one write(): the row is whole in the file or (killed mid-write) its
	 * incomplete tail is the file's last line, which readers skip */
	ssize_t w;
	do
		w = write(fd, buf, len);
	while (w < 0 && errno == EINTR);
	if (w != (ssize_t)len)
		return popc_error_set(err, POPC_ERR_IO, "summary rows: %s",
				      w < 0 ? strerror(errno) : "short write");
	return 0;
}

void popc_sweep_results_free(popc_sweep_results *r)
{
	for (int k = 0; k < r->n_texts; k++)
		free(r->texts[k]);
	free(r->texts);
	free(r->run);
	memset(r, 0, sizeof *r);
}

static int keep_text(popc_sweep_results *r, char *text, popc_error *err)
{
	char **grown = realloc(r->texts, (size_t)(r->n_texts + 1) * sizeof *grown);
	if (!grown) {
		free(text);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	r->texts = grown;
	r->texts[r->n_texts++] = text;
	return 0;
}

/* A result for run i: a success sticks, a failure replaces a failure. */
static void offer(popc_sweep_results *r, long long i, const char *row, int len, int exit_status,
		  const char *reason, int reason_len)
{
	popc_sweep_result_entry *e = &r->run[i];
	if (e->row && e->exit_status == 0)
		return;
	*e = (popc_sweep_result_entry){.row = row, .len = len, .exit_status = exit_status,
				       .reason = reason, .reason_len = reason_len};
}

/* A rows file read with something to say (not an error): counted, the
 * first one kept for the caller to show. */
__attribute__((format(printf, 2, 3))) static void note(popc_sweep_results *r, const char *fmt, ...)
{
	if (r->n_notes++ == 0) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(r->note, sizeof r->note, fmt, ap);
		va_end(ap);
	}
}

static int load_rows_file(popc_sweep_results *r, const popc_sweep_plan *p, const char *path,
			  popc_error *err)
{
	char *text;
	size_t len;
	int st = read_file(path, &text, &len, err);
	if (st <= 0)
		return st;
	st = keep_text(r, text, err);
	if (st)
		return st;
	size_t lc = strlen(p->columns);
	char *body = text + lc;
	if (len < lc || memcmp(text, p->columns, lc) != 0) {
		/* a header cut by a kill: the start of ours, nothing after it */
		if (len < lc && memcmp(text, p->columns, len) == 0) {
			note(r, "%s: a rows file whose header was cut (its worker was stopped "
				"while writing it): no rows, ignored", path);
			return 0;
		}
		/* popc before rows files had names of their own appended to such a
		 * file: a cut header (k bytes of ours) and then the whole one */
		size_t k = 1;
		while (k < lc && k + lc <= len &&
		       !(memcmp(text + k, p->columns, lc) == 0 && memcmp(text, p->columns, k) == 0))
			k++;
		if (k >= lc || k + lc > len)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: not a rows file of this sweep (its header differs)",
					      path);
		note(r, "%s: a header cut by a kill and a whole one after it: rows read from "
			"the second", path);
		body = text + k + lc;
	}
	int want_cells = p->n_axes + (int)N_METRICS + 6; /* run, exit, 3 chatter, wall */
	const char *reason = NULL;
	int reason_len = 0;
	long long reason_id = -1;
	for (char *line = body; *line;) {
		char *nl = strchr(line, '\n');
		if (!nl)
			break; /* an incomplete last line: a writer was stopped mid-write */
		int ll = (int)(nl - line);
		if (line[0] == '#') {
			/* "# <id> stop = <reason>" */
			char id[POPC_SWEEP_ID_MAX];
			int k = 0;
			while (k < ll - 2 && k < POPC_SWEEP_ID_MAX - 1 && line[2 + k] != ' ') {
				id[k] = line[2 + k];
				k++;
			}
			id[k] = '\0';
			reason_id = popc_sweep_id_parse(p, id);
			if (reason_id >= 0 && ll > 2 + k + 9 && strncmp(line + 2 + k, " stop = ", 8) == 0) {
				reason = line + 2 + k + 8;
				reason_len = ll - (2 + k + 8);
			} else {
				reason_id = -1;
			}
		} else {
			int cells = 1;
			for (int k = 0; k < ll; k++)
				cells += line[k] == ',';
			char id[POPC_SWEEP_ID_MAX];
			size_t il = strcspn(line, ",\n");
			long long i = -1;
			if (il < sizeof id) {
				memcpy(id, line, il);
				id[il] = '\0';
				i = popc_sweep_id_parse(p, id);
			}
			int ex = cells == want_cells && i >= 0 ? popc_sweep_row_exit_status(p, line) : -1;
			if (ex >= 0) {
				int has_reason = reason_id == i;
				offer(r, i, line, ll + 1, ex, has_reason ? reason : NULL,
				      has_reason ? reason_len : 0);
			}
			reason_id = -1;
		}
		line = nl + 1;
	}
	return 0;
}

static int cmp_name(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

static int load_rows_dir(popc_sweep_results *r, const popc_sweep_plan *p, const char *dir,
			 popc_error *err)
{
	char path[POPC_PATH_MAX + 300];
	snprintf(path, sizeof path, "%s/rows", dir);
	DIR *d = opendir(path);
	if (!d)
		return errno == ENOENT ? 0 : popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
	char **names = NULL;
	size_t n = 0;
	int st = 0;
	for (struct dirent *e; (e = readdir(d)) != NULL;) {
		size_t l = strlen(e->d_name);
		if (l < 5 || strcmp(e->d_name + l - 4, ".csv") != 0)
			continue;
		char **grown = realloc(names, (n + 1) * sizeof *names);
		if (!grown || !(grown[n] = strdup(e->d_name))) {
			names = grown ? grown : names;
			st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
			break;
		}
		names = grown;
		n++;
	}
	closedir(d);
	if (!st && n > 1)
		qsort(names, n, sizeof *names, cmp_name);
	for (size_t k = 0; k < n; k++) {
		if (!st) {
			snprintf(path, sizeof path, "%s/rows/%s", dir, names[k]);
			st = load_rows_file(r, p, path, err);
		}
		free(names[k]);
	}
	free(names);
	return st;
}

/* Runs made by --list `popc run` lines: DIR/runs/<id>/run.csv, the last
 * complete row of a popc run summary, converted to a sweep row. */
static int load_run_csv(popc_sweep_results *r, const popc_sweep_plan *p, const char *dir, long long i,
			popc_error *err)
{
	char path[POPC_PATH_MAX + 64];
	if (popc_sweep_run_dir(p, dir, i, path, sizeof path - 16) != 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: path too long", dir);
	strcat(path, "/run.csv");
	char *text;
	size_t len;
	int st = read_file(path, &text, &len, err);
	if (st <= 0)
		return st;
	/* the last complete line that is not the header: a retried run
	 * appended a second row */
	size_t end = len;
	while (end > 0 && text[end - 1] != '\n')
		end--;
	size_t start = end > 0 ? end - 1 : 0;
	while (start > 0 && text[start - 1] != '\n')
		start--;
	int status;
	if (end == 0 || start == 0 || popc_sweep_run_csv_status(text, text + start, &status) != 0) {
		free(text);
		return 0; /* nothing complete yet */
	}
	text[end] = '\0';
	const char *row = text + start;
	double wall = 0.0;
	{
		const char *hcell[RUN_CSV_MAX_COLUMNS], *rcell[RUN_CSV_MAX_COLUMNS];
		size_t hlen[RUN_CSV_MAX_COLUMNS], rlen[RUN_CSV_MAX_COLUMNS];
		int nh = split_cells(text, hcell, hlen, RUN_CSV_MAX_COLUMNS);
		split_cells(row, rcell, rlen, RUN_CSV_MAX_COLUMNS);
		int c = find_cell(hcell, hlen, nh, "wall_time_s");
		if (c >= 0)
			popc_parse_double_span(rcell[c], rcell[c] + rlen[c], &wall);
	}
	int ex = popc_status_exit_code(status);
	/* the chatter columns: from the run's log, as the in-process run
	 * computes them online (exact: the log's numbers read back bitwise) */
	popc_chatter_result chat;
	strcpy(path + strlen(path) - strlen("run.csv"), "log.csv");
	int have_chat = popc_sweep_chatter_from_log(path, &chat, err) == 0;
	char *out = malloc(POPC_SWEEP_ROW_MAX);
	popc_error e;
	int n = out ? popc_sweep_row(p, i, ex, text, row, have_chat ? &chat : NULL, wall, out,
				     POPC_SWEEP_ROW_MAX, &e)
		    : -1;
	free(text);
	if (n < 0) {
		free(out);
		return out ? popc_error_set(err, POPC_ERR_INVALID, "%s: %s", path, e.msg)
			   : popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	st = keep_text(r, out, err);
	if (st)
		return st;
	offer(r, i, out, n, ex, NULL, 0);
	return 0;
}

static int load_run_dirs(popc_sweep_results *r, const popc_sweep_plan *p, const char *dir,
			 popc_error *err)
{
	char path[POPC_PATH_MAX + 300];
	snprintf(path, sizeof path, "%s/runs", dir);
	DIR *d = opendir(path);
	if (!d)
		return errno == ENOENT ? 0 : popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
	int st = 0;
	for (struct dirent *e; !st && (e = readdir(d)) != NULL;) {
		long long i = popc_sweep_id_parse(p, e->d_name);
		if (i >= 0 && !(r->run[i].row && r->run[i].exit_status == 0))
			st = load_run_csv(r, p, dir, i, err);
	}
	closedir(d);
	return st;
}

int popc_sweep_results_load(popc_sweep_results *r, const popc_sweep_plan *p,
			    const char *const *dirs, int n_dirs, int check_run_csv, popc_error *err)
{
	memset(r, 0, sizeof *r);
	r->n = p->n_runs;
	r->run = calloc((size_t)p->n_runs, sizeof *r->run);
	if (!r->run)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	int st = 0;
	for (int d = 0; d < n_dirs && !st; d++)
		st = load_rows_dir(r, p, dirs[d], err);
	for (int d = 0; d < n_dirs && !st && check_run_csv; d++)
		st = load_run_dirs(r, p, dirs[d], err);
	if (st)
		popc_sweep_results_free(r);
	return st;
}

int popc_sweep_results_write(const popc_sweep_results *r, const popc_sweep_plan *p,
			     const popc_sweep_shard *shard, const char *out_path,
			     popc_sweep_tally *t, popc_sweep_visit visit, void *user,
			     popc_error *err)
{
	memset(t, 0, sizeof *t);
	popc_atomic_file out;
	int st = popc_atomic_file_open(&out, out_path, err);
	if (st)
		return st;
	FILE *f = out.f;
	fputs(p->columns, f);
	char reason[640];
	for (long long i = 0; i < p->n_runs; i++) {
		if (shard && !popc_sweep_in_shard(shard, i))
			continue;
		t->planned++;
		const popc_sweep_result_entry *e = &r->run[i];
		if (!e->row) {
			t->missing++;
			if (visit)
				visit(user, i, -1, "");
			continue;
		}
		fwrite(e->row, 1, (size_t)e->len, f);
		if (e->exit_status == 0) {
			t->ok++;
			continue;
		}
		t->failed++;
		if (visit) {
			snprintf(reason, sizeof reason, "%.*s", e->reason ? e->reason_len : 0,
				 e->reason ? e->reason : "");
			visit(user, i, e->exit_status, reason);
		}
	}
	return popc_atomic_file_commit(&out, err);
}
