/* A run's summary row (src/sweep/sweep_row.c): built from a `popc run
 * --summary` CSV row by the column table (sweep_columns.h), and read back.
 *
 * The sweep's in-process runs (popc_sweep_row_of_run, from the run's summary)
 * and runs made by `popc run` command lines (--list, GNU parallel;
 * popc_sweep_row, from the run's summary.csv text) give the same bytes: both
 * walk the same column table, and a run summary cell is the same function's
 * text either way (popc_run_summary_put_cell, behind popc run's CSV row too);
 * only wall_time_s, the last column, differs from one run to the next. */
#ifndef POPC_SWEEP_ROW_H
#define POPC_SWEEP_ROW_H

#include <stddef.h>

#include "popc/core/chatter.h"
#include "popc/run/run.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

/* Builds the sweep row of run i (with '\n') from a popc run summary header and
 * row (as popc_run_summary_csv_header/_row write them, with or without the
 * trailing newline) and the chatter detector's result (chatter_s,
 * chatter_intervals, limit_cycle). run_row or chatter may be NULL for a run
 * that produced no summary (setup failed, worker died): those cells are empty
 * (the table's empty rules). exit_status is the run's exit code
 * (popc/util/error.h); wall_time_s the run's time. Returns the length, or a
 * negative popc_status when a column is missing or the row does not fit in
 * cap. */
int popc_sweep_row(const popc_sweep_plan *p, long long i, int exit_status, const char *run_header,
		   const char *run_row, const popc_chatter_result *chatter, double wall_time_s,
		   char *buf, size_t cap, popc_error *err);

/* The same row from the run's summary itself (NULL: none; s the run's
 * scene), without its CSV text: the row a sweep makes in its own process. */
int popc_sweep_row_of_run(const popc_sweep_plan *p, long long i, int exit_status,
			  const popc_run_summary *sum, const popc_scene *s,
			  const popc_chatter_result *chatter, double wall_time_s, char *buf, size_t cap,
			  popc_error *err);

/* Checks run i's row as read back from a file (a rows file, a --list run's
 * run.csv made into a row): [row, row + len) without its line end. Its axis
 * cells must be run i's values in the plan, every other cell but the id
 * empty or a number of popc's grammar (popc/util/parse.h: no nan, inf, hex
 * or junk), so that an edited file cannot put into summary.csv what no run
 * made. Returns 0, or POPC_ERR_INVALID naming the column and the cell. */
int popc_sweep_row_check(const popc_sweep_plan *p, long long i, const char *row, size_t len,
			 popc_error *err);

/* Reads the exit_status cell of a sweep row; -1 if the row is malformed. */
int popc_sweep_row_exit_status(const popc_sweep_plan *p, const char *row);

/* The popc_status in the "status" column of a popc run summary row (header
 * names the columns). Returns 0 and sets *status, or -1. */
int popc_sweep_run_csv_status(const char *run_header, const char *run_row, int *status);

/* The "wall_time_s" cell of a popc run summary row, a number as everywhere
 * (popc/util/parse.h); 0 when the header has no such column or the cell is
 * not a number. */
double popc_sweep_run_csv_wall_time_s(const char *run_header, const char *run_row);

/* Splits one CSV line (ending at '\n', '\r' or NUL; no quoting: popc's
 * summaries hold none) into at most max cells: cell[i] points into line,
 * len[i] is its length. Returns the cell count, which may exceed max (the
 * cells past max are counted, not stored). */
int popc_sweep_split_cells(const char *line, const char **cell, size_t *len, int max);

#endif
