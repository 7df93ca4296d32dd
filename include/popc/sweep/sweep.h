/* Parameter sweeps (DESIGN section 8): the planner, run ids, sharding and the
 * summary rows that `popc sweep` and `popc sweep merge` write.
 *
 * A sweep is a base scene and a list of axes, each a scene key with a list of
 * values ("--vary operator.speed=0.01:0.1:10"). Its runs are the cartesian
 * product of the axes, the last axis varying fastest (nested loops in the
 * order the axes were given). Run i has the id "i" written with a fixed number
 * of digits (the width of n_runs - 1, at least 4), so ids sort as text in the
 * order of the product, are the same on every machine, and name the run's
 * directory DIR/runs/<id>/.
 *
 * Shard I of N owns the runs with i mod N == I: shards never overlap, cover
 * the sweep together, and each gets a slice of every region of the product,
 * which balances the load when one corner of the product runs slower.
 *
 * The summary row of a run is built from a `popc run --summary` CSV row (its
 * header and its row, popc_run_summary_csv_header/_row), picking columns by
 * name. The sweep's in-process runs and runs made by `popc run` command lines
 * (--list, GNU parallel) go through the same function, so both give the same
 * bytes; only wall_time_s, the last column, differs from one run to the next. */
#ifndef POPC_SWEEP_H
#define POPC_SWEEP_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "popc/core/chatter.h"
#include "popc/util/error.h"
#include "popc/scene/scene.h"

/* Limits: a range has at most this many points, a sweep this many runs, and a
 * value this many characters. They bound memory and keep ids to 9 digits. */
#define POPC_SWEEP_RANGE_MAX 10000000L
#define POPC_SWEEP_RUNS_MAX 1000000000LL
#define POPC_SWEEP_VALUE_MAX 256
#define POPC_SWEEP_ID_MAX 16
#define POPC_SWEEP_ROW_MAX 8192

/* One --vary axis. */
typedef struct popc_sweep_axis {
	char section[64], key[64];
	char spec[POPC_SWEEP_VALUE_MAX * 2]; /* the text after '=' as given */
	int n_values;
	char **values;                       /* text applied with popc_scene_set */
} popc_sweep_axis;

typedef struct popc_sweep_plan {
	popc_scene base;                 /* the resolved base scene */
	int n_axes;
	popc_sweep_axis *axes;
	long long n_runs;
	int id_width;
	uint64_t plan_id;                /* FNV-1a of base scene text, axes and columns */
	char *columns;                   /* summary.csv header line, with '\n' */
} popc_sweep_plan;

/* Expands a range or list into values (no scene involved):
 *   "a,b,c"      a list (items may not be empty or hold '"' or newlines)
 *   "lo:hi:n"    n points from lo to hi, evenly spaced (hi exact)
 *   "lo:hi:n:log" n points from lo to hi, evenly spaced in log (lo, hi > 0)
 * Range points are written with 12 significant digits ("%.12g"), so that
 * 0:1:11 gives 0.3, not 0.30000000000000004, and a log range gives the same
 * text on machines whose libm exp/log differ in the last bit. Duplicate
 * values are an error. The caller frees with popc_sweep_values_free. */
int popc_sweep_expand(const char *spec, char ***values, int *n_values, popc_error *err);
void popc_sweep_values_free(char **values, int n_values);

/* Parses "section.key=LIST" into an axis (values expanded, key not checked). */
int popc_sweep_axis_parse(const char *vary, popc_sweep_axis *axis, popc_error *err);
void popc_sweep_axis_free(popc_sweep_axis *axis);

/* Builds a plan on the resolved base scene. Takes ownership of axes (an array
 * of n_axes parsed axes, freed by popc_sweep_plan_free even on error). Checks,
 * before anything runs: keys known and given once, every value accepted by
 * popc_scene_set for its key (the message names the key, the value and the
 * allowed range), the product within POPC_SWEEP_RUNS_MAX, and, when
 * check_every_run is set, every run's scene through popc_scene_validate, its
 * axis (the simulated one only) and every operator table the runs read (each
 * table once). */
int popc_sweep_plan_init(popc_sweep_plan *p, const popc_scene *base, popc_sweep_axis *axes,
			 int n_axes, int check_every_run, popc_error *err);
void popc_sweep_plan_free(popc_sweep_plan *p);

/* The value index on every axis of run i (value_index has n_axes entries). */
void popc_sweep_run_values(const popc_sweep_plan *p, long long i, int *value_index);

/* The resolved scene of run i: base, then each axis' value, then validation. */
int popc_sweep_run_scene(const popc_sweep_plan *p, long long i, popc_scene *s, popc_error *err);

/* The id of run i (buf holds at least POPC_SWEEP_ID_MAX bytes). */
void popc_sweep_run_id(const popc_sweep_plan *p, long long i, char *buf);
/* Parses an id back; -1 when text is not an id of this plan. */
long long popc_sweep_id_parse(const popc_sweep_plan *p, const char *text);

/* FNV-1a 64-bit, the hash of plan ids. */
uint64_t popc_sweep_fnv1a(uint64_t h, const void *data, size_t n);
#define POPC_SWEEP_FNV_OFFSET 0xcbf29ce484222325ULL

/* ---- sharding ------------------------------------------------------------ */

typedef struct popc_sweep_shard {
	long long index, count;      /* shard index in [0, count) */
} popc_sweep_shard;

/* "I/N" with 0 <= I < N. */
int popc_sweep_shard_parse(const char *text, popc_sweep_shard *sh, popc_error *err);

/* The shard of a Slurm array task: index (SLURM_ARRAY_TASK_ID - MIN) / STEP
 * of SLURM_ARRAY_TASK_COUNT. Pass the four variables' values (NULL when
 * unset; min and step may be NULL). Returns 1 when id and count are set and
 * give a shard, 0 when they are not set, or a negative popc_status. */
int popc_sweep_shard_from_slurm(const char *task_id, const char *task_count, const char *task_min,
				const char *task_step, popc_sweep_shard *sh, popc_error *err);

static inline int popc_sweep_in_shard(const popc_sweep_shard *sh, long long i)
{
	return i % sh->count == sh->index;
}

/* ---- summary rows -------------------------------------------------------- */

/* The summary.csv header line (with '\n') of a sweep over these axes:
 *   run,<section.key>...,exit_status,<metrics>...,wall_time_s
 * The metrics are columns of the popc run summary, by name, then the chatter
 * detector's chatter_s, chatter_intervals and limit_cycle (chatter.h, with
 * its default thresholds, as popc-analyze compare). Caller frees. */
char *popc_sweep_columns_header(const popc_sweep_axis *axes, int n_axes);

/* Builds the sweep row of run i (with '\n') from a popc run summary header and
 * row (as popc_run_summary_csv_header/_row write them, with or without the
 * trailing newline) and the chatter detector's result (chatter_s,
 * chatter_intervals, limit_cycle). run_row or chatter may be NULL for a run
 * that produced no summary (setup failed, worker died): those cells are empty.
 * So are chatter_s and chatter_intervals when chatter was not checked
 * (popc_chatter_checked: shorter than one window), and limit_cycle when the
 * limit cycle was not (popc_chatter_lc_checked: shorter than half its window),
 * as popc-analyze compare leaves them: never a 0 without data. exit_status
 * is the run's exit code (include/popc/error.h); wall_time_s the run's time.
 * Returns the length, or a negative popc_status when a column is missing or
 * the row does not fit in cap. */
int popc_sweep_row(const popc_sweep_plan *p, long long i, int exit_status, const char *run_header,
		   const char *run_row, const popc_chatter_result *chatter, double wall_time_s,
		   char *buf, size_t cap, popc_error *err);

/* Reads the exit_status cell of a sweep row; -1 if the row is malformed. */
int popc_sweep_row_exit_status(const popc_sweep_plan *p, const char *row);

/* The popc_status in the "status" column of a popc run summary row (header
 * names the columns). Returns 0 and sets *status, or -1. */
int popc_sweep_run_csv_status(const char *run_header, const char *run_row, int *status);

/* ---- the sweep directory -------------------------------------------------- *
 *
 *   DIR/sweep.plan        the plan (plan id, runs, vary specs, columns)
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
 *                         so it is always whole
 *
 * A run is finished when some row of it has exit_status 0; where a run has
 * several rows (retries, or the same run in two shard directories), the first
 * successful one counts, else the last failed one. */

/* Writes DIR/sweep.plan and DIR/scene.ini (creating DIR, DIR/rows and
 * DIR/runs), or, when DIR already holds a plan, checks it is the same plan. */
int popc_sweep_dir_prepare(const popc_sweep_plan *p, const char *dir, const char *scene_path,
			   popc_error *err);

/* A plan rebuilt from a sweep directory's plan file (no scene needed): rows
 * can be read and converted, runs cannot be made. */
int popc_sweep_plan_from_dir(popc_sweep_plan *p, const char *dir, popc_error *err);

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

/* The results of a sweep: the best row of every run found in the rows files
 * of some sweep directories (and in --list runs' run.csv files). */
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
	char **texts;              /* loaded files */
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

/* Creates a directory and its missing parents (mode 0777 less the umask). */
int popc_sweep_mkdir_p(const char *path, popc_error *err);

/* The chatter detector (default thresholds, the scene's encoder resolution)
 * over a popc log, as popc-analyze compare runs it. */
int popc_sweep_chatter_from_log(const char *log_path, popc_chatter_result *res, popc_error *err);

/* ---- one run, in this process ---------------------------------------------- */

typedef struct popc_sweep_result {
	int exit_status;          /* the run's exit code (include/popc/error.h) */
	int interrupted;          /* stopped by stop_flag: no summary written */
	int recorded;             /* the row is in the rows file (even when the
				   * run's own summary.csv could not be written) */
	double wall_time_s;       /* scene, axis, run and log, without the summary */
	char reason[POPC_ERROR_MSG_MAX + 64];
} popc_sweep_result;

/* Runs run i of the plan on the simulated axis in this process and appends
 * its row to the rows file rows_fd. With keep_log, DIR/runs/<id>/ gets the
 * resolved scene.ini, log.csv and then, once the row is recorded, a
 * summary.csv (header and row, renamed into place). A run stopped by
 * *stop_flag records nothing, so that a resumed sweep runs it again. Returns
 * 0 when the run was made and its result recorded (whatever the run's exit
 * status), or a negative popc_status when its row could not be written or,
 * with res->recorded set, when the row is recorded but the run's summary.csv
 * could not be written (err names it). */
int popc_sweep_run_one(const popc_sweep_plan *p, long long i, const char *dir, int keep_log,
		       int rows_fd, volatile sig_atomic_t *stop_flag, popc_sweep_result *res,
		       popc_error *err);

#endif
