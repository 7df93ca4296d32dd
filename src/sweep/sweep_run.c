/* One run of a sweep in this process (sweep_run.h): the same steps as `popc run`
 * (cmd_run.c) on the simulated axis, then the run's summary file. */
#include "popc/sweep/sweep_run.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "popc/axes/axis.h"
#include "popc/core/controller.h"
#include "popc/log/log.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"
#include "popc/sweep/sweep_chatter.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_row.h"
#include "popc/util/atomic_file.h"
#include "popc/util/clock.h"

/* ---- the chatter detector ----------------------------------------------------- *
 *
 * The chatter detector sees every tick through popc_run's on_tick hook. */

static void feed_chatter(void *user, const popc_tick *tick)
{
	popc_chatter_add(user, tick);
}

/* snprintf(buf, cap, "%s", text) without stdio's setup (every run) */
static void copy_text(char *buf, size_t cap, const char *text)
{
	size_t n = strnlen(text, cap - 1);
	memcpy(buf, text, n);
	buf[n] = '\0';
}

static int write_scene(const char *path, const popc_scene *s, popc_error *err)
{
	char *text;
	size_t len;
	int st = popc_scene_to_text(s, &text, &len, err);
	if (st)
		return st;
	st = popc_write_file_atomic(path, text, len, err);
	free(text);
	return st;
}

int popc_sweep_run_one(const popc_sweep_plan *p, long long i, const char *dir, int keep_log,
		       popc_sweep_rows_batch *rows, volatile sig_atomic_t *stop_flag,
		       popc_sweep_result *res, popc_error *err)
{
	/* not memset: the reason (600 bytes) is written for a failed run only,
	 * so a worker's held results touch a page, not five */
	res->exit_status = res->interrupted = res->recorded = 0;
	res->wall_time_s = 0.0;
	res->reason[0] = '\0';
	double t0 = popc_now_s();
	char rdir[POPC_PATH_MAX], path[POPC_PATH_MAX + 32];
	/* summaries only: no directory per run (a mkdir costs about as much
	 * as a tenth of a paper-scene run), so no name for it either */
	if (keep_log && popc_sweep_run_dir(p, dir, i, rdir, sizeof rdir) != 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: path too long", dir);
	if (keep_log && mkdir(rdir, 0777) != 0 && errno != EEXIST)
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", rdir, strerror(errno));

	popc_scene s;
	popc_error rerr;
	popc_axis *axis = NULL;
	popc_log_writer log;
	int log_open = 0, have_sum = 0;
	popc_run_summary sum;
	int st = popc_sweep_run_scene(p, i, &s, &rerr);
	if (!st && keep_log) {
		snprintf(path, sizeof path, "%s/scene.ini", rdir);
		st = write_scene(path, &s, &rerr);
	}
	if (!st) {
		if (popc_axis_is_simulated(&s))
			st = popc_axis_create(&axis, &s, NULL, &rerr);
		else
			st = popc_error_set(&rerr, POPC_ERR_INVALID,
					    "axis = %s: a sweep runs the simulated axis only", s.axis);
	}
	if (!st && keep_log) {
		snprintf(path, sizeof path, "%s/log.csv", rdir);
		st = popc_log_open(&log, path, popc_run_log_columns(&s, axis), &rerr);
		if (!st) {
			log_open = 1;
			st = popc_log_write_header(&log, axis->ops->name, &s, NULL, &rerr);
		}
	}
	popc_chatter det;
	popc_chatter_result chat;
	int have_chat = 0;
	if (!st) {
		popc_controller_config ccfg;
		popc_controller_config_from_scene(&ccfg, &s);
		st = popc_sweep_chatter_init(&det, &s, &ccfg, &rerr);
	}
	if (!st) {
		popc_run_options ro = {.log = log_open ? &log : NULL, .stop_flag = stop_flag,
				       .on_tick = feed_chatter, .tick_user = &det};
		st = popc_run(&s, axis, &ro, &sum, &rerr);
		have_sum = 1;
		popc_chatter_finish(&det, &chat);
		have_chat = 1;
	}
	if (log_open) {
		popc_error cerr;
		int cst = popc_log_close(&log, &cerr);
		if (cst && !st) {
			st = cst;
			rerr = cerr;
		}
	}
	popc_axis_destroy(&axis);
	res->wall_time_s = popc_now_s() - t0;
	res->exit_status = popc_status_exit_code(st);
	/* the reason a failed run stopped (said, and put before its row);
	 * a run that ended well has none to keep */
	if (res->exit_status != 0)
		copy_text(res->reason, sizeof res->reason, have_sum ? sum.stop_reason : rerr.msg);
	if (st == POPC_ERR_INTERRUPTED || (stop_flag && *stop_flag && st)) {
		res->interrupted = 1;
		return 0;
	}

	char row[POPC_SWEEP_ROW_MAX];
	int n = popc_sweep_row_of_run(p, i, res->exit_status, have_sum ? &sum : NULL, &s,
				      have_chat ? &chat : NULL, res->wall_time_s, row, sizeof row, err);
	if (n < 0)
		return n;
	/* the sweep's record first: a run whose row is in the rows file is
	 * finished whatever happens to the copy below */
	int st2 = popc_sweep_rows_batch_add(rows, p, i, row, res->exit_status, res->reason, err);
	/* with a log, the row is written before the run's own summary.csv */
	if (!st2 && keep_log)
		st2 = popc_sweep_rows_flush(rows, err);
	if (st2)
		return st2;
	res->recorded = 1;
	if (keep_log) {
		/* the run's own copy, next to its log: header and row. A failure
		 * here is reported (the directory lacks a file it should have), but
		 * the run keeps its result in the sweep. */
		char text[POPC_SWEEP_ROW_MAX * 2];
		size_t lc = strlen(p->columns);
		if (lc + (size_t)n < sizeof text) {
			memcpy(text, p->columns, lc);
			memcpy(text + lc, row, (size_t)n);
			snprintf(path, sizeof path, "%s/summary.csv", rdir);
			popc_error cerr;
			if (popc_write_file_atomic(path, text, lc + (size_t)n, &cerr) != 0)
				return popc_error_set(err, POPC_ERR_IO,
						      "%s (the run's copy of its row; the row itself is "
						      "recorded in the sweep)",
						      cerr.msg);
		}
	}
	return 0;
}
