/* The results of a sweep (sweep_results.h): the best row of every run, from
 * rows files and --list runs' run.csv files; summary.csv in id order. */
#include "popc/sweep/sweep_results.h"

#include <dirent.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/uio.h>
#include <unistd.h>

#include "popc/sweep/sweep_chatter.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_files.h"
#include "popc/sweep/sweep_row.h"
#include "popc/util/atomic_file.h"
#include "popc/util/json.h"

void popc_sweep_results_free(popc_sweep_results *r)
{
	for (int k = 0; k < r->n_texts; k++)
		popc_sweep_file_view_free(&r->texts[k]);
	free(r->texts);
	free(r->run);
	memset(r, 0, sizeof *r);
}

/* Keeps v (the rows point into it) until the results are freed. */
static int keep_text(popc_sweep_results *r, popc_sweep_file_view *v, popc_error *err)
{
	popc_sweep_file_view *grown = realloc(r->texts, (size_t)(r->n_texts + 1) * sizeof *grown);
	if (!grown) {
		popc_sweep_file_view_free(v);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	r->texts = grown;
	r->texts[r->n_texts++] = *v;
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
	popc_sweep_file_view view;
	int st = popc_sweep_view_file(path, &view, err);
	if (st <= 0)
		return st;
	const char *text = view.text, *end = view.text + view.len;
	size_t len = view.len;
	st = keep_text(r, &view, err);
	if (st)
		return st;
	size_t lc = strlen(p->columns);
	const char *body = text + lc;
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
	int want_cells = popc_sweep_columns_count_of(p->n_axes, p->teleop);
	long lineno = 1; /* of the line at body */
	for (const char *c = text; c < body; c++)
		lineno += *c == '\n';
	const char *reason = NULL;
	int reason_len = 0;
	long long reason_id = -1;
	/* within [text, end): a mapped file has no NUL after it */
	for (const char *line = body; line < end;) {
		const char *nl = memchr(line, '\n', (size_t)(end - line));
		if (!nl)
			break; /* an incomplete last line: a writer was stopped mid-write */
		/* a NUL in a line ends what is read, as when the text was read
		 * NUL-terminated and searched with strchr */
		if (memchr(line, '\0', (size_t)(nl - line)))
			break;
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
			size_t il = 0;
			while (il < (size_t)ll && line[il] != ',')
				il++;
			long long i = -1;
			if (il < sizeof id) {
				memcpy(id, line, il);
				id[il] = '\0';
				i = popc_sweep_id_parse(p, id);
			}
			int ex = cells == want_cells && i >= 0 ? popc_sweep_row_exit_status(p, line) : -1;
			/* a whole row of a run (a line of another shape is what a
			 * kill cut, skipped): what it holds must be what a run can
			 * have made, or the file was edited */
			popc_error e;
			if (ex >= 0 && popc_sweep_row_check(p, i, line, (size_t)ll, &e) != 0)
				return popc_error_set(err, POPC_ERR_INVALID, "%s:%ld: run %s: %s", path, lineno,
						      id, e.msg);
			if (ex >= 0) {
				int has_reason = reason_id == i;
				offer(r, i, line, ll + 1, ex, has_reason ? reason : NULL,
				      has_reason ? reason_len : 0);
			}
			reason_id = -1;
		}
		line = nl + 1;
		lineno++;
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
	int st = popc_sweep_read_file(path, &text, &len, err);
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
	long row_line = 1;
	for (const char *c = text; c < row; c++)
		row_line += *c == '\n';
	double wall = popc_sweep_run_csv_wall_time_s(text, row);
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
	/* the run summary's cells, as the run wrote them (or an edit) */
	if (popc_sweep_row_check(p, i, out, (size_t)n - 1, &e) != 0) {
		free(out);
		strcpy(path + strlen(path) - strlen("log.csv"), "run.csv");
		return popc_error_set(err, POPC_ERR_INVALID, "%s:%ld: %s", path, row_line, e.msg);
	}
	popc_sweep_file_view kept = {.text = out, .len = (size_t)n, .buf = out};
	st = keep_text(r, &kept, err);
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

int popc_sweep_results_load_rows(popc_sweep_results *r, const popc_sweep_plan *p, const char *path,
				 popc_error *err)
{
	memset(r, 0, sizeof *r);
	r->n = p->n_runs;
	r->run = calloc((size_t)p->n_runs, sizeof *r->run);
	if (!r->run)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	int st = load_rows_file(r, p, path, err);
	if (st)
		popc_sweep_results_free(r);
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

/* Bytes gathered for writev(): GATHER_MAX pieces a call. */
enum { GATHER_MAX = 256 };
typedef struct gather {
	int fd;
	int n;
	int err;                      /* errno of a failed write, 0 none */
	struct iovec v[GATHER_MAX];
} gather;

static void gather_flush(gather *g)
{
	struct iovec *v = g->v;
	int n = g->n;
	g->n = 0;
	while (n > 0 && !g->err) {
		ssize_t w = writev(g->fd, v, n);
		if (w < 0) {
			if (errno != EINTR)
				g->err = errno;
			continue;
		}
		/* a short write: on from the first byte not written */
		while (n > 0 && (size_t)w >= v->iov_len) {
			w -= (ssize_t)v->iov_len;
			v++;
			n--;
		}
		if (n > 0) {
			v->iov_base = (char *)v->iov_base + w;
			v->iov_len -= (size_t)w;
		}
	}
}

static void gather_add(gather *g, const void *bytes, size_t len)
{
	if (len == 0)
		return;
	g->v[g->n++] = (struct iovec){.iov_base = (void *)bytes, .iov_len = len};
	if (g->n == GATHER_MAX)
		gather_flush(g);
}

int popc_sweep_results_write(const popc_sweep_results *r, const popc_sweep_plan *p,
			     const popc_sweep_shard *shard, const char *out_path,
			     popc_sweep_tally *t, popc_sweep_visit visit, void *user,
			     popc_error *err)
{
	memset(t, 0, sizeof *t);
	/* the same rows as JSON Lines beside it: summary.csv -> summary.jsonl */
	char json_path[POPC_PATH_MAX + 8];
	size_t pl = strlen(out_path);
	if (pl < 4 || strcmp(out_path + pl - 4, ".csv") != 0 || pl - 4 + 7 > sizeof json_path)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: a summary's name ends in .csv", out_path);
	snprintf(json_path, sizeof json_path, "%.*s.jsonl", (int)(pl - 4), out_path);
	int n_cells = popc_sweep_columns_count_of(p->n_axes, p->teleop);
	char *names_line = strdup(p->columns);
	const char **names = malloc((size_t)n_cells * sizeof *names);
	popc_json_kind *kinds = malloc((size_t)n_cells * sizeof *kinds);
	if (!names_line || !names || !kinds) {
		free(names_line);
		free(names);
		free(kinds);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	int n_names = popc_json_csv_names(names_line, names, n_cells);
	popc_sweep_columns_json_kinds_of(p->n_axes, p->teleop, kinds);
	/* the names escaped once as keys, not once a row */
	char *keys = popc_json_csv_keys(n_names, names);
	free(names_line);
	free(names);
	if (!keys) {
		free(kinds);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	popc_atomic_file out, json;
	int st = popc_atomic_file_open(&out, out_path, err);
	if (!st && (st = popc_atomic_file_open(&json, json_path, err)) != 0)
		popc_atomic_file_abort(&out);
	if (st) {
		free(keys);
		free(kinds);
		return st;
	}
	/* summary.jsonl: a stdio buffer as large as the summary (to 64 kB), not
	 * the file system's 4 kB blocks: a write() costs tens of microseconds
	 * of system time on this VM, and 300 runs' summaries (about 100 and
	 * 230 kB) took 80 of them; 10,000 runs' (about 10 MB) take 150, not
	 * 2,400. A summary of a few kB keeps stdio's own buffer (a new one's
	 * page faults, 10 to 20 us each here, would cost more than its writes). */
	enum { SUMMARY_BUFFER = 1 << 16, SMALL_SUMMARY = 1 << 13 };
	size_t csv_bytes = strlen(p->columns);
	for (long long i = 0; i < p->n_runs; i++)
		csv_bytes += r->run[i].row ? (size_t)r->run[i].len : 0;
	/* a JSON line is about twice its CSV row: the names repeated as keys */
	size_t json_size = 2 * csv_bytes < SUMMARY_BUFFER ? 2 * csv_bytes : SUMMARY_BUFFER;
	char *json_buf = json_size > SMALL_SUMMARY ? malloc(json_size) : NULL;
	if (json_buf)
		setvbuf(json.f, json_buf, _IOFBF, json_size);
	/* summary.csv: the header and the rows where they are, gathered into
	 * writev()s: no buffer to fault in, no copy (out.f is never written) */
	gather g = {.fd = fileno(out.f)};
	gather_add(&g, p->columns, strlen(p->columns));
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
		gather_add(&g, e->row, (size_t)e->len);
		popc_json_csv_object_keyed(json.f, n_names, keys, kinds, e->row, (size_t)e->len);
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
	gather_flush(&g);
	free(keys);
	free(kinds);
	if (g.err) {
		popc_atomic_file_abort(&out);
		popc_atomic_file_abort(&json);
		free(json_buf);
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", out_path, strerror(g.err));
	}
	/* the buffer outlives its stream: freed once it is closed */
	st = popc_atomic_file_commit(&out, err);
	if (st)
		popc_atomic_file_abort(&json);
	else
		st = popc_atomic_file_commit(&json, err);
	free(json_buf);
	return st;
}
