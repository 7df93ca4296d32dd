/* The results of a sweep (src/sweep/sweep_results.c): the best row of every
 * run found in the rows files of some sweep directories (and in --list runs'
 * run.csv files), and summary.csv written from them in id order. */
#ifndef POPC_SWEEP_RESULTS_H
#define POPC_SWEEP_RESULTS_H

#include "popc/sweep/sweep_files.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

typedef struct popc_sweep_result_entry {
	const char *row;           /* into the loaded text; NULL: no result */
	int len;
	int exit_status;
	const char *reason;        /* NULL or a "stop = " text, not NUL-ended */
	int reason_len;
} popc_sweep_result_entry;

typedef struct popc_sweep_results {
	long long n;
	popc_sweep_result_entry *run;
	int n_texts;
	popc_sweep_file_view *texts; /* loaded files (mapped or read), rows made */
	int n_notes;               /* rows files read with a note (a cut header) */
	char note[POPC_ERROR_MSG_MAX]; /* the first note, naming the file */
} popc_sweep_results;

/* Loads every rows file of dirs (in name order, dirs in order) and, for runs
 * still without a successful row, DIR/runs/<id>/run.csv. check_run_csv = 0
 * skips the latter (a sweep directory made without --list has none). A rows
 * file whose header was cut by a kill (a start of the header and nothing
 * else) is skipped and counted in n_notes, not an error; one whose header
 * differs otherwise is an error. */
int popc_sweep_results_load(popc_sweep_results *r, const popc_sweep_plan *p,
			    const char *const *dirs, int n_dirs, int check_run_csv, popc_error *err);
void popc_sweep_results_free(popc_sweep_results *r);
/* The results of one rows file, read as popc_sweep_results_load reads each
 * (the fuzz harness): every whole row checked (popc_sweep_row_check). */
int popc_sweep_results_load_rows(popc_sweep_results *r, const popc_sweep_plan *p, const char *path,
				 popc_error *err);

typedef struct popc_sweep_tally {
	long long planned, ok, failed, missing;
} popc_sweep_tally;

/* Called by popc_sweep_results_write for every run that failed (exit_status
 * > 0) or has no result (exit_status < 0), in id order; reason is "" when
 * none was recorded. */
typedef void (*popc_sweep_visit)(void *user, long long i, int exit_status, const char *reason);

/* Writes out_path atomically: the header and the row of every run of the
 * shard (all runs when shard is NULL) that has a result, in id order. */
int popc_sweep_results_write(const popc_sweep_results *r, const popc_sweep_plan *p,
			     const popc_sweep_shard *shard, const char *out_path,
			     popc_sweep_tally *t, popc_sweep_visit visit, void *user,
			     popc_error *err);

#endif
