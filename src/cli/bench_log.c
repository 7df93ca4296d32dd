/* popc bench log: log writing against printf("%.17g"), log reading + energy
 * recompute against strtod, and the reader's memory (bench.h). */
#include "bench.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "popc/core/controller.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/log/log.h"
#include "popc/log/log_reader.h"
#include "popc/util/numfmt.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"

/* The rows of one run of the scene (its integrator, closed loop) lasting
 * n ticks. */
static popc_log_row *make_rows(const popc_scene *s0, long n, popc_error *err)
{
	popc_scene s = *s0;
	s.duration_s = (double)(n - 1) * popc_scene_period_s(&s);
	popc_log_row *rows = malloc((size_t)n * sizeof *rows);
	if (!rows) {
		popc_error_set(err, POPC_ERR_NOMEM, "bench: out of memory for %ld rows", n);
		return NULL;
	}
	popc_controller_config cc;
	popc_controller_config_from_scene(&cc, &s);
	popc_controller *ctl;
	if (popc_controller_create(&cc, &ctl, err) != 0) {
		free(rows);
		return NULL;
	}
	popc_axis *ax;
	if (popc_sim_axis_create(&ax, &s, err) != 0) {
		popc_controller_free(ctl);
		free(rows);
		return NULL;
	}
	popc_axis_sample smp;
	popc_port_energy port;
	popc_port_energy_init(&port);
	int st = ax->ops->sample(ax, &smp, err);
	for (long i = 0; !st && i < n; i++) {
		popc_log_row *r = &rows[i];
		r->tick.t_s = (double)i * popc_scene_period_s(&s);
		popc_controller_step(ctl, smp.count, popc_encoder_position(smp.count, s.enc_resolution_m),
				     &r->tick);
		r->x_true_m = smp.x_true_m;
		r->E_port_J = popc_port_energy_update(&port, smp.x_true_m);
		popc_port_energy_commit(&port, r->tick.f_c_N);
		r->dt_s = r->rtt_s = 0.0;
		if (i + 1 < n)
			st = ax->ops->exchange(ax, r->tick.f_c_N, &smp, err);
	}
	popc_axis_destroy(&ax);
	popc_controller_free(ctl);
	if (st) {
		free(rows);
		return NULL;
	}
	return rows;
}

/* A log of the scene run for `ticks` ticks, written by popc run's own loop. */
static int run_to_log(const popc_scene *s0, long long ticks, const char *path, popc_error *err)
{
	popc_scene s = *s0;
	s.duration_s = (double)(ticks - 1) * popc_scene_period_s(&s);
	popc_axis *ax;
	int st = popc_sim_axis_create(&ax, &s, err);
	if (st)
		return st;
	popc_log_writer w;
	st = popc_log_open(&w, path, ax->ops->log_columns, err);
	if (!st)
		st = popc_log_write_header(&w, "sim", &s, NULL, err);
	if (!st) {
		popc_run_options ro = {.log = &w, .stop_flag = NULL};
		popc_run_summary sum;
		st = popc_run(&s, ax, &ro, &sum, err);
	}
	popc_error e2;
	int cst = popc_log_close(&w, &e2);
	popc_axis_destroy(&ax);
	return st ? st : cst;
}

static int write_popc(const char *path, const popc_scene *s, const popc_log_row *rows, long n,
		      popc_error *err)
{
	popc_log_writer w;
	int st = popc_log_open(&w, path, POPC_LOG_COL_X_TRUE, err);
	if (!st)
		st = popc_log_write_header(&w, "sim", s, NULL, err);
	for (long i = 0; !st && i < n; i++)
		st = popc_log_write_row(&w, &rows[i], err);
	popc_error e2;
	int cst = popc_log_close(&w, &e2);
	return st ? st : cst;
}

/* The baseline writes the simulated axis' columns (POPC_LOG_COL_X_TRUE) with
 * one fprintf per row, its format and arguments pasted from the column table:
 * IN_SIM_LOG_<fill>(text) is the text for a column such a log has. */
#define IN_SIM_LOG_ALWAYS(...) __VA_ARGS__
#define IN_SIM_LOG_X_TRUE(...) __VA_ARGS__
#define IN_SIM_LOG_TIMING(...)
#define IN_SIM_LOG_ADMITTANCE(...)
#define IN_SIM_LOG_TELEOP(...)
#define IN_SIM_LOG_SLAVE_TRUE(...)
#define IN_SIM_LOG_DRIFT(...)
#define PRINTF_DOUBLE ",%.17g"
#define PRINTF_COUNT ",%lld"
#define PRINTF_FLAGS ",%u"
#define CELL_FORMAT(ID, name, unit, fill, format, field, meaning) IN_SIM_LOG_##fill(PRINTF_##format)
#define CELL_VALUE(ID, name, unit, fill, format, field, meaning) IN_SIM_LOG_##fill(, rows[i].field)

static int write_printf(const char *path, const popc_log_row *rows, long n)
{
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	char names[POPC_LOG_NAMES_LINE_MAX];
	popc_log_column_names(POPC_LOG_COL_X_TRUE, names, sizeof names);
	fprintf(f, "%s\n", names);
	for (long i = 0; i < n; i++) /* [1]: no comma before the first cell */
		fprintf(f, &POPC_LOG_COLUMN_TABLE(CELL_FORMAT) "\n"[1] POPC_LOG_COLUMN_TABLE(CELL_VALUE));
	return fclose(f);
}

static long file_bytes(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return -1;
	fseek(f, 0, SEEK_END);
	long n = ftell(f);
	fclose(f);
	return n;
}

/* The recompute loop of popc-analyze's energy verb: W and E_ref from a log's
 * x, count, v, f_e and f_c columns, with the observer that ran online. */
typedef struct recompute {
	popc_observer obs;
	double period_s;
	int ix, icount, iv, ife, ifc;
	long long rows;
} recompute;

static void recompute_row(recompute *rc, const double *v)
{
	popc_observation ob;
	popc_observer_update(&rc->obs, v[rc->ix], (long long)v[rc->icount], v[rc->iv], rc->period_s,
			     v[rc->ife], &ob);
	popc_observer_commit(&rc->obs, &ob, v[rc->ife], v[rc->ifc]);
	rc->rows++;
}

static int read_popc(const char *path, const popc_scene *s, recompute *rc, popc_error *err)
{
	popc_log_reader r;
	int st = popc_log_reader_open(&r, path, NULL, err);
	if (st)
		return st;
	popc_observer_init(&rc->obs, s->variant, s->ignore_mode);
	rc->period_s = popc_scene_period_s(s);
	rc->rows = 0;
	const popc_log_column *c = popc_log_columns;
	if (!st)
		st = popc_log_reader_require(&r, c[POPC_LOG_COLUMN_X].name, &rc->ix, err);
	if (!st)
		st = popc_log_reader_require(&r, c[POPC_LOG_COLUMN_COUNT].name, &rc->icount, err);
	if (!st)
		st = popc_log_reader_require(&r, c[POPC_LOG_COLUMN_V].name, &rc->iv, err);
	if (!st)
		st = popc_log_reader_require(&r, c[POPC_LOG_COLUMN_F_E].name, &rc->ife, err);
	if (!st)
		st = popc_log_reader_require(&r, c[POPC_LOG_COLUMN_F_C].name, &rc->ifc, err);
	double v[POPC_LOG_MAX_COLUMNS];
	while (!st && (st = popc_log_reader_next(&r, v, err)) == 1) {
		recompute_row(rc, v);
		st = 0;
	}
	popc_log_reader_close(&r);
	return st < 0 ? st : 0;
}

/* The baseline reader: fgets and strtod per cell, same recompute. */
static int read_strtod(const char *path, const popc_scene *s, recompute *rc)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	popc_observer_init(&rc->obs, s->variant, s->ignore_mode);
	rc->period_s = popc_scene_period_s(s);
	rc->rows = 0;
	/* the cells of a simulated axis' log, by their place in it */
	const unsigned cols = POPC_LOG_COL_X_TRUE;
	rc->ix = popc_log_column_index(cols, POPC_LOG_COLUMN_X);
	rc->icount = popc_log_column_index(cols, POPC_LOG_COLUMN_COUNT);
	rc->iv = popc_log_column_index(cols, POPC_LOG_COLUMN_V);
	rc->ife = popc_log_column_index(cols, POPC_LOG_COLUMN_F_E);
	rc->ifc = popc_log_column_index(cols, POPC_LOG_COLUMN_F_C);
	char line[1024];
	int header = 1;
	while (fgets(line, sizeof line, f)) {
		if (line[0] == '#')
			continue;
		if (header) {
			header = 0;
			continue;
		}
		double v[POPC_LOG_N_COLUMNS];
		char *p = line, *end;
		int n = 0;
		while (n < POPC_LOG_N_COLUMNS) {
			v[n++] = strtod(p, &end);
			if (*end != ',')
				break;
			p = end + 1;
		}
		recompute_row(rc, v);
	}
	fclose(f);
	return 0;
}

/* Peak resident memory (KiB) of a child process that reads the log. */
static long child_read_rss_kib(const char *path, const popc_scene *s)
{
	int fd[2];
	if (pipe(fd) != 0)
		return -1;
	fflush(NULL);
	pid_t pid = fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		close(fd[0]);
		recompute rc;
		popc_error err;
		long kib = -1;
		if (read_popc(path, s, &rc, &err) == 0) {
			struct rusage ru;
			getrusage(RUSAGE_SELF, &ru);
			kib = ru.ru_maxrss;
		}
		ssize_t w = write(fd[1], &kib, sizeof kib);
		_exit(w == (ssize_t)sizeof kib ? 0 : 1);
	}
	close(fd[1]);
	long kib = -1;
	if (read(fd[0], &kib, sizeof kib) != (ssize_t)sizeof kib)
		kib = -1;
	close(fd[0]);
	int status;
	waitpid(pid, &status, 0);
	return kib;
}

int bench_log(const popc_scene *s, const bench_opts *o)
{
	popc_error err;
	const char *dir = o->dir ? o->dir : getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
	char p_popc[POPC_PATH_MAX], p_printf[POPC_PATH_MAX], p_big[POPC_PATH_MAX];
	snprintf(p_popc, sizeof p_popc, "%s/popc-bench-%ld-popc.csv", dir, (long)getpid());
	snprintf(p_printf, sizeof p_printf, "%s/popc-bench-%ld-printf.csv", dir, (long)getpid());
	snprintf(p_big, sizeof p_big, "%s/popc-bench-%ld-big.csv", dir, (long)getpid());
	long n = o->rows;
	popc_log_row *rows = make_rows(s, n, &err);
	if (!rows)
		return popc_cli_fail("bench", POPC_ERR_NOMEM, &err);
	double w_popc = (double)INFINITY, w_printf = (double)INFINITY, r_popc = (double)INFINITY,
	       r_strtod = (double)INFINITY;
	int st = 0;
	recompute a, b;
	for (int r = 0; r < o->repeats && !st; r++) {
		double t0 = popc_now_s();
		st = write_popc(p_popc, s, rows, n, &err);
		double t1 = popc_now_s();
		if (!st && write_printf(p_printf, rows, n) != 0)
			st = popc_error_set(&err, POPC_ERR_IO, "%s: write failed", p_printf);
		double t2 = popc_now_s();
		if (!st)
			st = read_popc(p_popc, s, &a, &err);
		double t3 = popc_now_s();
		if (!st && read_strtod(p_popc, s, &b) != 0)
			st = popc_error_set(&err, POPC_ERR_IO, "%s: read failed", p_popc);
		double t4 = popc_now_s();
		w_popc = fmin(w_popc, t1 - t0);
		w_printf = fmin(w_printf, t2 - t1);
		r_popc = fmin(r_popc, t3 - t2);
		r_strtod = fmin(r_strtod, t4 - t3);
	}
	long bytes_popc = file_bytes(p_popc), bytes_printf = file_bytes(p_printf);
	/* exactness: the recompute from the log equals the online W and E_ref bitwise */
	int exact = !st && a.rows == n && a.obs.W_J == rows[n - 1].tick.W_J &&
		    a.obs.E_ref_J == rows[n - 1].tick.E_ref_J;
	free(rows); /* before the children fork: their peak memory is the reader's */
	rows = NULL;
	/* memory: the same reader on a log four times longer */
	long rss_small = -1, rss_big = -1;
	if (!st)
		st = run_to_log(s, 4LL * n, p_big, &err);
	if (!st) {
		rss_small = child_read_rss_kib(p_popc, s);
		rss_big = child_read_rss_kib(p_big, s);
	}
	long bytes_big = file_bytes(p_big);
	remove(p_popc);
	remove(p_printf);
	remove(p_big);
	if (st)
		return popc_cli_fail("bench", st, &err);
	double mb = 1e-6 * (double)bytes_popc;
	if (o->csv) {
		fprintf(o->out, "%s\n", "what,popc_MBps,libc_MBps,ratio");
		fprintf(o->out, "write,%.6g,%.6g,%.4g\n", mb / w_popc, 1e-6 * (double)bytes_printf / w_printf,
		       w_printf / w_popc);
		fprintf(o->out, "read_recompute,%.6g,%.6g,%.4g\n", mb / r_popc, mb / r_strtod,
		       r_strtod / r_popc);
		fprintf(o->out, "reader_peak_rss_kib,%ld,%ld,\n", rss_small, rss_big);
		fprintf(o->out, "recompute_bitwise,%d,,\n", exact);
		return exact ? POPC_EXIT_OK : POPC_EXIT_RUN_FAILED;
	}
	printf("popc bench log: %ld rows of the scene's run (%.1f MB as popc writes them), one "
	       "core, fastest of %d, files in %s\n",
	       n, mb, o->repeats, dir);
	printf("%-44s %10s %10s %7s\n", "", "popc", "C library", "ratio");
	printf("%-44s %10.1f %10.1f %7.2f\n",
	       "write MB/s (vs printf %.17g)", mb / w_popc, 1e-6 * (double)bytes_printf / w_printf,
	       w_printf / w_popc);
	printf("%-44s %10.1f %10.1f %7.2f\n",
	       "read + W/E_ref recompute MB/s (vs strtod)", mb / r_popc, mb / r_strtod,
	       r_strtod / r_popc);
	printf("write: %.1f ns per row popc, %.1f ns per row printf\n", 1e9 * w_popc / (double)n,
	       1e9 * w_printf / (double)n);
	printf("reader peak memory: %ld KiB for %.1f MB, %ld KiB for %.1f MB (whole process)\n",
	       rss_small, mb, rss_big, 1e-6 * (double)bytes_big);
	printf("recomputed W and E_ref equal the online values bitwise: %s\n", exact ? "yes" : "NO");
	return exact ? POPC_EXIT_OK : POPC_EXIT_RUN_FAILED;
}
