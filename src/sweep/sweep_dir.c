/* The sweep directory (sweep_dir.h): the plan file, run directories, rows
 * files. */
#include "popc/sweep/sweep_dir.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_files.h"
#include "popc/sweep/sweep_lock.h"
#include "popc/util/atomic_file.h"
#include "popc/util/parse.h"

/* ---- the plan file ---------------------------------------------------------- */

/* The plan's last line, "digest = <16 hex digits>": FNV-1a 64 of every byte
 * before it. A plan read back is what popc wrote (an edited vary line would
 * resume a sweep whose summary disagrees with its plan); not a defence
 * against someone who recomputes it, a check against edits and damage. */
#define PLAN_DIGEST_KEY "digest = "

static uint64_t plan_digest(const char *text, size_t len)
{
	return popc_sweep_fnv1a(POPC_SWEEP_FNV_OFFSET, text, len);
}

/* The start of the digest line of text (its last line), or len if none. */
static size_t digest_line_at(const char *text, size_t len)
{
	size_t end = len;
	if (end > 0 && text[end - 1] == '\n')
		end--;
	size_t start = end;
	while (start > 0 && text[start - 1] != '\n')
		start--;
	size_t kl = strlen(PLAN_DIGEST_KEY);
	return end - start > kl && strncmp(text + start, PLAN_DIGEST_KEY, kl) == 0 ? start : len;
}

/* Appends the digest line to text[0..len) (room for PLAN_DIGEST_LINE_MAX
 * more bytes); returns the new length. */
enum { PLAN_DIGEST_LINE_MAX = 32 };
static size_t append_digest(char *text, size_t len)
{
	uint64_t h = plan_digest(text, len);
	return len + (size_t)snprintf(text + len, PLAN_DIGEST_LINE_MAX, PLAN_DIGEST_KEY "%016" PRIx64 "\n",
				      h);
}

/* Checks a plan's digest line against its text; a plan without one (written
 * by popc before digests) passes, its vary lines checked against the plan
 * resumed (popc_sweep_dir_prepare). */
static int check_digest(const char *path, const char *text, size_t len, popc_error *err)
{
	size_t at = digest_line_at(text, len);
	if (at == len)
		return 0;
	int lineno = 1;
	for (size_t k = 0; k < at; k++)
		lineno += text[k] == '\n';
	const char *v = text + at + strlen(PLAN_DIGEST_KEY);
	const char *e = memchr(v, '\n', len - (size_t)(v - text));
	uint64_t stored;
	if (popc_parse_u64_span(v, e ? e : text + len, UINT64_MAX, POPC_PARSE_BASE16, &stored) != 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s:%d: digest: 16 hexadecimal digits",
				      path, lineno);
	if (stored != plan_digest(text, at))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%d: the digest does not match the plan's lines above it: the "
				      "plan was edited or damaged after popc wrote it, and its runs and "
				      "rows can no longer be trusted to agree. Run the sweep into a new "
				      "-o DIR (or restore the plan)",
				      path, lineno);
	return 0;
}

/* Adds "also_built_by = popc V (build B)" to DIR/sweep.plan, unless the plan
 * names that build already (as its maker or in such a line). */
int popc_sweep_dir_note_build(const popc_sweep_plan *p, const char *dir, popc_error *err)
{
	char path[POPC_PATH_MAX + 32], line[POPC_SWEEP_BUILD_MAX + 128], who[POPC_SWEEP_BUILD_MAX + 96];
	snprintf(path, sizeof path, "%s/sweep.plan", dir);
	popc_sweep_plan old;
	int st = popc_sweep_plan_from_dir(&old, dir, err);
	if (st)
		return st;
	int same = popc_sweep_plan_same_build(&old, p);
	popc_sweep_plan_free(&old);
	if (same)
		return 0;
	char *text;
	size_t len;
	st = popc_sweep_read_file(path, &text, &len, err);
	if (st <= 0)
		return st ? st : popc_error_set(err, POPC_ERR_IO, "%s: gone", path);
	popc_sweep_plan_describe_build(p, who, sizeof who);
	int n = snprintf(line, sizeof line, "also_built_by = %s\n", who);
	/* the line at the start of a line of the file: already noted */
	int noted = 0;
	for (const char *at = strstr(text, line); at && !noted; at = strstr(at + 1, line))
		noted = at == text || at[-1] == '\n';
	if (noted) {
		free(text);
		return 0;
	}
	char *grown = realloc(text, len + (size_t)n + 2 + PLAN_DIGEST_LINE_MAX);
	if (!grown) {
		free(text);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	text = grown;
	/* the line goes before the digest, which then covers it too (a plan
	 * without a digest, from popc before them, gets one) */
	len = digest_line_at(text, len);
	if (len && text[len - 1] != '\n')
		text[len++] = '\n';
	memcpy(text + len, line, (size_t)n + 1);
	len = append_digest(text, len + (size_t)n);
	st = popc_write_file_atomic(path, text, len, err);
	free(text);
	return st;
}

int popc_sweep_dir_prepare(const popc_sweep_plan *p, const char *dir, const char *scene_path,
			   int allow_other_build, popc_error *err)
{
	char path[POPC_PATH_MAX + 32];
	int st = popc_mkdir_p(dir, err);
	if (st)
		return st;
	struct stat sb;
	snprintf(path, sizeof path, "%s/sweep.plan", dir);
	int have_plan = lstat(path, &sb) == 0;
	if (have_plan && !S_ISREG(sb.st_mode))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: not a plan file (a %s stands there): is %s a popc sweep "
				      "directory? Choose another -o DIR",
				      path, S_ISDIR(sb.st_mode) ? "directory" : "non-regular file", dir);
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
	if (have_plan) {
		popc_sweep_plan old;
		st = popc_sweep_plan_from_dir(&old, dir, err);
		if (st)
			return st;
		uint64_t old_id = old.plan_id;
		/* the plan id is a hash the plan file stores, not one of its
		 * lines: a vary line edited (in a plan without a digest) would
		 * keep it, and the runs made now would disagree with the plan */
		for (int a = 0; a < old.n_axes && a < p->n_axes && old_id == p->plan_id; a++)
			if (strcmp(old.axes[a].section, p->axes[a].section) != 0 ||
			    strcmp(old.axes[a].key, p->axes[a].key) != 0 ||
			    strcmp(old.axes[a].spec, p->axes[a].spec) != 0) {
				st = popc_error_set(err, POPC_ERR_INVALID,
						    "%s: vary = %s.%s=%s, but this sweep's --vary %d is "
						    "%s.%s=%s under the same plan id: the plan was "
						    "edited; choose another -o DIR",
						    path, old.axes[a].section, old.axes[a].key,
						    old.axes[a].spec, a + 1, p->axes[a].section,
						    p->axes[a].key, p->axes[a].spec);
				popc_sweep_plan_free(&old);
				return st;
			}
		if (old.n_axes != p->n_axes && old_id == p->plan_id) {
			popc_sweep_plan_free(&old);
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %d vary lines, this sweep has %d under the same plan "
					      "id: the plan was edited; choose another -o DIR",
					      path, old.n_axes, p->n_axes);
		}
		int same_build = popc_sweep_plan_same_build(&old, p);
		char old_build[POPC_SWEEP_BUILD_MAX + 96], this_build[POPC_SWEEP_BUILD_MAX + 96];
		popc_sweep_plan_describe_build(&old, old_build, sizeof old_build);
		popc_sweep_plan_describe_build(p, this_build, sizeof this_build);
		popc_sweep_plan_free(&old);
		if (old_id != p->plan_id)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s holds another sweep (plan %016" PRIx64 "; this one is "
					      "%016" PRIx64 ": a different scene, --vary list or summary "
					      "columns): choose another -o DIR",
					      path, old_id, p->plan_id);
		/* the same runs by another build: its rows would sit next to the
		 * first build's in one summary, which then belongs to neither */
		if (!same_build && !allow_other_build)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: this sweep was made by %s; this is %s: a resume would "
					      "mix the results of two builds in one summary. Resume with "
					      "the first build, choose another -o DIR, or give "
					      "--allow-other-build (the plan then records both)",
					      path, old_build, this_build);
		if (same_build)
			return 0;
		st = popc_sweep_dir_note_build(p, dir, err);
		return st ? st : 1;
	}

	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	if (!f)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	fprintf(f, "# popc sweep plan: written by popc sweep, read when the sweep resumes and by\n"
		   "# popc sweep merge. Runs are DIR/runs/<id>; summary.csv has one row per run.\n");
	fprintf(f, "format = 1\nplan_id = %016" PRIx64 "\npopc_version = %s\npopc_build = %s\n"
		   "runs = %lld\nscene = %s\n",
		p->plan_id, p->popc_version, p->popc_build, p->n_runs, scene_path);
	for (int a = 0; a < p->n_axes; a++)
		fprintf(f, "vary = %s.%s=%s\n", p->axes[a].section, p->axes[a].key, p->axes[a].spec);
	fprintf(f, "columns = %s", p->columns);
	fprintf(f, "%*s", PLAN_DIGEST_LINE_MAX, ""); /* room for the digest line */
	if (fclose(f) != 0) {
		free(text);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	len = append_digest(text, len - PLAN_DIGEST_LINE_MAX);
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

int popc_sweep_dir_open(const popc_sweep_plan *p, const char *dir, const char *scene_path,
			int allow_other_build, const popc_sweep_shard *shard, popc_error *err)
{
	/* nothing has run yet: a directory that cannot be made is an unusable
	 * -o (exit 2), as popc_sweep_output_dir_check would have said */
	int st = popc_mkdir_p(dir, err);
	if (st)
		return st == POPC_ERR_NOMEM ? st : POPC_ERR_INVALID;
	/* the lock before the plan is read or written: two sweeps started at
	 * once must not both find the directory free and both write it */
	st = popc_sweep_lock_take(dir, shard, err);
	if (st)
		return st;
	return popc_sweep_dir_prepare(p, dir, scene_path, allow_other_build, err);
}

int popc_sweep_plan_from_dir(popc_sweep_plan *p, const char *dir, popc_error *err)
{
	memset(p, 0, sizeof *p);
	char path[POPC_PATH_MAX + 32];
	snprintf(path, sizeof path, "%s/sweep.plan", dir);
	struct stat sb;
	if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: not a plan file (a %s stands there): is %s a popc sweep "
				      "directory?",
				      path, S_ISDIR(sb.st_mode) ? "directory" : "non-regular file", dir);
	if (stat(path, &sb) != 0 && errno == ENOENT)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: no such file: is %s a popc sweep directory?",
				      path, dir);
	return popc_sweep_plan_read(p, path, err);
}

int popc_sweep_plan_read(popc_sweep_plan *p, const char *path, popc_error *err)
{
	memset(p, 0, sizeof *p);
	char *text;
	size_t len;
	int st = popc_sweep_read_file(path, &text, &len, err);
	if (st == 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: no such file", path);
	if (st < 0)
		return st;
	if ((st = check_digest(path, text, len, err)) != 0) {
		free(text);
		return st;
	}
	popc_sweep_axis *axes = NULL;
	int n_axes = 0, have_id = 0, format = 0;
	long long runs = -1;
	uint64_t plan_id = 0;
	char version[sizeof p->popc_version] = "", build[sizeof p->popc_build] = "";
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
		} else if (strcmp(key, "popc_version") == 0) {
			snprintf(version, sizeof version, "%s", value);
		} else if (strcmp(key, "popc_build") == 0) {
			snprintf(build, sizeof build, "%s", value);
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
	popc_sweep_plan_set_build(p, version, build);
	/* a teleoperation sweep's plan names the tele_* columns (sweep_columns.h) */
	char *teleop_columns = popc_sweep_columns_header_of(axes, n_axes, 1);
	p->teleop = teleop_columns && strncmp(teleop_columns, columns, strlen(columns)) == 0 &&
		    strlen(teleop_columns) == strlen(columns) + 1;
	free(teleop_columns);
	p->columns = popc_sweep_columns_header_of(axes, n_axes, p->teleop);
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
	 * would make the whole file unreadable. Close-on-exec: not inherited by
	 * the popc that a crash of -j 1's runs starts again (it opens its own). */
	int fd = -1;
	for (int n = 0; n < ROWS_NAMES_MAX && fd < 0; n++) {
		if (n == 0)
			snprintf(path, sizeof path, "%s/rows/%s.%ld.csv", dir, host, name_pid);
		else
			snprintf(path, sizeof path, "%s/rows/%s.%ld.%d.csv", dir, host, name_pid, n);
		fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0666);
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

/* Run i's entry in a rows file into buf (POPC_SWEEP_ROWS_ENTRY_MAX bytes):
 * for a failed run with a reason, "# <id> stop = <reason>" on a line first,
 * then the row. Returns its length, or -1 when the row is too long. */
static long rows_entry(const popc_sweep_plan *p, long long i, const char *row, int exit_status,
		       const char *reason, char *buf)
{
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
	if (len + lr > POPC_SWEEP_ROWS_ENTRY_MAX)
		return -1;
	memcpy(buf + len, row, lr);
	return (long)(len + lr);
}

/* One write(): the rows are whole in the file or (killed mid-write) the
 * incomplete tail is the file's last line, which readers skip. */
static int write_rows(int fd, const char *buf, size_t len, popc_error *err)
{
	ssize_t w;
	do
		w = write(fd, buf, len);
	while (w < 0 && errno == EINTR);
	if (w != (ssize_t)len)
		return popc_error_set(err, POPC_ERR_IO, "summary rows: %s",
				      w < 0 ? strerror(errno) : "short write");
	return 0;
}

int popc_sweep_rows_append(const popc_sweep_plan *p, int fd, long long i, const char *row,
			   int exit_status, const char *reason, popc_error *err)
{
	char buf[POPC_SWEEP_ROWS_ENTRY_MAX];
	long len = rows_entry(p, i, row, exit_status, reason, buf);
	if (len < 0)
		return popc_error_set(err, POPC_ERR_INVALID, "summary row too long");
	return write_rows(fd, buf, (size_t)len, err);
}

/* The batch's buffer: room for a few rows of the longest kind, and for a few
 * dozen of the usual few hundred bytes. Written whenever less than one
 * longest row would fit (not sized for max_rows longest rows: a buffer
 * that large is a fresh mapping, and its pages' first touches cost more
 * than the writes saved). */
enum { ROWS_BATCH_BYTES = 1 << 16 };

int popc_sweep_rows_batch_init(popc_sweep_rows_batch *b, int fd, int max_rows, popc_error *err)
{
	*b = (popc_sweep_rows_batch){.fd = fd, .max_rows = max_rows > 1 ? max_rows : 1};
	b->buf = malloc(ROWS_BATCH_BYTES);
	return b->buf ? 0 : popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
}

void popc_sweep_rows_batch_free(popc_sweep_rows_batch *b)
{
	free(b->buf);
	b->buf = NULL;
}

int popc_sweep_rows_batch_add(popc_sweep_rows_batch *b, const popc_sweep_plan *p, long long i,
			      const char *row, int exit_status, const char *reason, popc_error *err)
{
	if (b->n_rows >= b->max_rows)
		return popc_error_set(err, POPC_ERR_INVALID, "summary rows: the batch is full");
	long len = rows_entry(p, i, row, exit_status, reason, b->buf + b->len);
	if (len < 0)
		return popc_error_set(err, POPC_ERR_INVALID, "summary row too long");
	b->len += (size_t)len;
	b->n_rows++;
	int full = b->n_rows >= b->max_rows || ROWS_BATCH_BYTES - b->len < POPC_SWEEP_ROWS_ENTRY_MAX;
	return full ? popc_sweep_rows_flush(b, err) : 0;
}

int popc_sweep_rows_flush(popc_sweep_rows_batch *b, popc_error *err)
{
	if (b->len == 0)
		return 0;
	size_t len = b->len;
	b->len = 0;
	b->n_rows = 0;
	return write_rows(b->fd, b->buf, len, err);
}
