/* The sweep directory (src/sweep/sweep_dir.c): the plan file, run
 * directories and rows files.
 *
 *   DIR/sweep.plan        the plan (plan id, the popc version and build that
 *                         made it, runs, vary specs, columns; an
 *                         also_built_by line per other build that resumed or
 *                         merged it with --allow-other-build)
 *   DIR/scene.ini         the resolved base scene
 *   DIR/rows/HOST.PID.csv the rows of the runs one worker process made: the
 *                         header, then per run an optional "# <id> stop =
 *                         <reason>" line and the row, appended with one
 *                         write() (O_APPEND) each. One writer per file, so no
 *                         two processes (nor two machines on NFS) ever append
 *                         to the same file; a worker killed mid-write leaves
 *                         at most an incomplete last line, which readers skip.
 *                         When the name is taken (a pid used again: containers,
 *                         Slurm nodes), HOST.PID.1.csv, HOST.PID.2.csv, ...: a
 *                         file is written by one process lifetime only, so a
 *                         row never joins a line an earlier process left cut.
 *                         A file whose header was cut (no rows) is skipped.
 *   DIR/runs/<id>/        scene.ini, log.csv and summary.csv (unless --no-log);
 *                         for --list, scene.ini (the run's resolved scene,
 *                         which its `popc run` line runs), then log.csv and
 *                         run.csv from the line
 *   DIR/summary.csv       every row in id order (summary-shard-I-of-N.csv for
 *                         a shard), written to a temporary name and renamed,
 *                         so it is always whole (sweep_results.h)
 *
 * A run is finished when some row of it has exit_status 0; where a run has
 * several rows (retries, or the same run in two shard directories), the first
 * successful one counts, else the last failed one. */
#ifndef POPC_SWEEP_DIR_H
#define POPC_SWEEP_DIR_H

#include <stddef.h>

#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

/* Writes DIR/sweep.plan and DIR/scene.ini (creating DIR, DIR/rows and
 * DIR/runs), or, when DIR already holds a plan, checks it is the same plan
 * and was made by the same popc version and build (p->popc_version,
 * p->popc_build): another build is refused (POPC_ERR_INVALID, naming both)
 * unless allow_other_build, and then recorded (popc_sweep_dir_note_build).
 * Returns 0, 1 when another build was allowed and recorded, or a negative
 * popc_status. */
int popc_sweep_dir_prepare(const popc_sweep_plan *p, const char *dir, const char *scene_path,
			   int allow_other_build, popc_error *err);

/* What a sweep or map does with its directory before any run: makes DIR,
 * takes its lock for the runs of shard (sweep_lock.h: POPC_ERR_BUSY when
 * another popc holds it), then popc_sweep_dir_prepare. A DIR that cannot be
 * made or locked (read-only) is POPC_ERR_INVALID: nothing ran. The lock is
 * held until the process (and every worker it forks) ends. */
int popc_sweep_dir_open(const popc_sweep_plan *p, const char *dir, const char *scene_path,
			int allow_other_build, const popc_sweep_shard *shard, popc_error *err);

/* Records in DIR/sweep.plan that p's popc version and build added results
 * to the sweep ("also_built_by = popc V (build B)", once per build), unless
 * the plan was made by that build. */
int popc_sweep_dir_note_build(const popc_sweep_plan *p, const char *dir, popc_error *err);

/* A plan rebuilt from a sweep directory's plan file (no scene needed): rows
 * can be read and converted, runs cannot be made. */
int popc_sweep_plan_from_dir(popc_sweep_plan *p, const char *dir, popc_error *err);
/* The same from a plan file's path (DIR/sweep.plan; the fuzz harness's
 * memory file): its digest checked, its lines parsed; errors name path and,
 * for a line, path:line. */
int popc_sweep_plan_read(popc_sweep_plan *p, const char *path, popc_error *err);

/* Path of run i's directory (DIR/runs/<id>) into buf. */
int popc_sweep_run_dir(const popc_sweep_plan *p, const char *dir, long long i, char *buf,
		       size_t cap);

/* Creates a new rows file for this process in DIR/rows, named after the host
 * and name_pid (getpid(), or a test's stand-in), with O_CREAT | O_EXCL: the
 * first free one of HOST.PID.csv, HOST.PID.1.csv, HOST.PID.2.csv, ...; writes
 * the header; returns its descriptor (>= 0) or a negative popc_status. */
int popc_sweep_rows_open(const popc_sweep_plan *p, const char *dir, long name_pid,
			 popc_error *err);

/* Appends run i's row (and, for a failed run, its reason) with one write(). */
int popc_sweep_rows_append(const popc_sweep_plan *p, int fd, long long i, const char *row,
			   int exit_status, const char *reason, popc_error *err);

/* Rows held for one write() of several: a write costs a few microseconds of
 * system time, some percent of a 2-tick run (docs/BENCHMARKS.md section 6).
 * A held row is not recorded: until popc_sweep_rows_flush has written it, a
 * worker that dies loses it, and its run is made again (sweep_pool.c). The
 * rows are written as popc_sweep_rows_append writes them, in order. */
typedef struct popc_sweep_rows_batch {
	int fd;
	int n_rows, max_rows; /* held; written when max_rows are (1: each at
			       * once), or fewer when they fill the buffer */
	size_t len;
	char *buf;            /* always room for one more entry after an add */
} popc_sweep_rows_batch;

/* The most bytes of one row with its reason line. */
#define POPC_SWEEP_ROWS_ENTRY_MAX (POPC_SWEEP_ROW_MAX + 640)

int popc_sweep_rows_batch_init(popc_sweep_rows_batch *b, int fd, int max_rows, popc_error *err);
void popc_sweep_rows_batch_free(popc_sweep_rows_batch *b);
/* Holds run i's row as popc_sweep_rows_append would write it; writes the
 * held rows once max_rows are held or the buffer has no room for another
 * (n_rows is then 0). */
int popc_sweep_rows_batch_add(popc_sweep_rows_batch *b, const popc_sweep_plan *p, long long i,
			      const char *row, int exit_status, const char *reason, popc_error *err);
/* Writes the held rows with one write() (none held: nothing). */
int popc_sweep_rows_flush(popc_sweep_rows_batch *b, popc_error *err);

#endif
