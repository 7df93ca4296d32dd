/* The columns of a sweep's summary.csv, as one table (src/sweep/sweep_columns.c):
 *
 *   run,<section.key>...,exit_status,<metrics>...,chatter_s,chatter_intervals,
 *   limit_cycle,wall_time_s
 *
 * Each column says where its cell comes from, how it is written and when it is
 * empty. The header (popc_sweep_columns_header), every row
 * (popc_sweep_row, sweep_row.h), the readers of rows files and summary.csv
 * (popc_sweep_columns_count, popc_sweep_column_index) and the plan id (which
 * hashes the header, so that a sweep directory of another column set is
 * refused) all derive from it: adding a metric of the popc run summary is one
 * line of the table. */
#ifndef POPC_SWEEP_COLUMNS_H
#define POPC_SWEEP_COLUMNS_H

#include "popc/sweep/sweep_plan.h"
#include "popc/util/json.h"

/* The longest summary line (a row or the header), '\n' included. */
#define POPC_SWEEP_ROW_MAX 8192

/* Where a column's cells come from. */
typedef enum popc_sweep_cell_source {
	POPC_SWEEP_CELL_RUN_ID,            /* the run's id (popc_sweep_run_id) */
	POPC_SWEEP_CELL_AXES,              /* one column per --vary axis, named
					    * section.key: the run's value as given */
	POPC_SWEEP_CELL_EXIT_STATUS,       /* the run's exit code (popc/util/error.h) */
	POPC_SWEEP_CELL_RUN_SUMMARY,       /* the popc run summary's column of the
					    * same name, its text unchanged */
	POPC_SWEEP_CELL_CHATTER_S,         /* the chatter detector (chatter.h, default
					    * thresholds, as popc-analyze compare) */
	POPC_SWEEP_CELL_CHATTER_INTERVALS,
	POPC_SWEEP_CELL_LIMIT_CYCLE,
	POPC_SWEEP_CELL_WALL_TIME_S,       /* the run's wall time: the one cell that
					    * differs between two sweeps of one plan */
	POPC_SWEEP_CELL_TELEOP,            /* a teleoperation run's two-port figures
					    * (sweep_teleop.h): in a teleoperation
					    * sweep's table only */
} popc_sweep_cell_source;

/* How a cell's value is written. */
typedef enum popc_sweep_cell_format {
	POPC_SWEEP_FORMAT_TEXT,            /* the text as it is */
	POPC_SWEEP_FORMAT_INT,             /* decimal, "%d" */
	POPC_SWEEP_FORMAT_DOUBLE,          /* shortest text that reads back to the same
					    * double (popc_format_double) */
} popc_sweep_cell_format;

/* When a cell is empty instead: a verdict or metric without data is an empty
 * cell, never a 0 (a 0 would read as "no chatter" in a merge or a comparison
 * of summaries), as popc-analyze compare leaves them. */
typedef enum popc_sweep_cell_empty {
	POPC_SWEEP_EMPTY_NEVER,
	POPC_SWEEP_EMPTY_WITHOUT_SUMMARY,    /* the run made no summary (its setup
					      * failed, its worker died) */
	POPC_SWEEP_EMPTY_CHATTER_UNCHECKED,  /* no detector result, or a run shorter
					      * than one chatter window
					      * (popc_chatter_checked) */
	POPC_SWEEP_EMPTY_LC_UNCHECKED,       /* no detector result, or a run shorter
					      * than half a limit-cycle window
					      * (popc_chatter_lc_checked) */
} popc_sweep_cell_empty;

typedef struct popc_sweep_column {
	const char *name;                  /* header text; NULL for the axes (their keys) */
	popc_sweep_cell_source source;
	popc_sweep_cell_format format;
	popc_sweep_cell_empty empty;
} popc_sweep_column;

/* The table, in column order. */
extern const popc_sweep_column popc_sweep_columns[];
extern const int popc_sweep_n_columns;

/* The table of a sweep whose runs are one-port scenes (teleop 0: the table
 * above) or teleoperation scenes (teleop 1: the same columns with the tele_*
 * columns before wall_time_s, docs/SWEEPS.md "Teleoperation scenes"); its
 * column count in *n. A sweep is one or the other (popc_sweep_plan_init
 * refuses a mix), so every one-port summary keeps its columns. The functions
 * below without _of are those of the one-port table. */
const popc_sweep_column *popc_sweep_columns_of(int teleop, int *n);
char *popc_sweep_columns_header_of(const popc_sweep_axis *axes, int n_axes, int teleop);
int popc_sweep_columns_count_of(int n_axes, int teleop);
void popc_sweep_columns_json_kinds_of(int n_axes, int teleop, popc_json_kind *kinds);

/* The summary.csv header line (with '\n') of a sweep over these axes. Caller
 * frees; NULL when out of memory. */
char *popc_sweep_columns_header(const popc_sweep_axis *axes, int n_axes);

/* The number of cells of a summary line of a sweep over n_axes axes. */
int popc_sweep_columns_count(int n_axes);

/* The JSON kind of each cell of a line of a sweep over n_axes axes
 * (popc_sweep_columns_count of them), for summary.jsonl: the run id a string,
 * an axis value a number where it reads as one, a run summary column as the
 * run summary types it (popc_run_summary_json_kind), the others by format. */
void popc_sweep_columns_json_kinds(int n_axes, popc_json_kind *kinds);

/* The cell index of the (first) column of this source in a line of a sweep
 * over n_axes axes; -1 when the table has none. */
int popc_sweep_column_index(int n_axes, popc_sweep_cell_source source);

#endif
