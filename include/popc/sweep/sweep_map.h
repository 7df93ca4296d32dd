/* Stability maps (src/sweep/sweep_map.c): the first unacceptable wall
 * stiffness K of every line of a map, and the last acceptable K above it
 * where the line folds, found by a coarse scan of the log-K grid that
 * brackets every transition wider than its step, then bisection in log K.
 *
 * A map is a sweep (sweep_plan.h) whose last axis is environment.stiffness
 * on a log grid of n_k points from k_lo to k_hi, spaced by a ratio of at most
 * 1 + tol (popc_map_grid_points). A line is one value of every other axis
 * (the variant, the wall damping, ...): the n_k runs that share them, so run
 * i is point i mod n_k of line i / n_k. A map runs only the few points of
 * each line that the search asks for; their ids, rows, results, shards and
 * resumption are the sweep's.
 *
 * The search is a pure function of the verdicts known so far (no state is
 * stored): it replays the scan and the bisections and returns the indices it
 * needs next, or its result. The same verdicts give the same
 * answer on every machine and after any interruption, so a resumed or
 * sharded map makes the runs a one-machine map makes, and no others. */
#ifndef POPC_SWEEP_MAP_H
#define POPC_SWEEP_MAP_H

#include <stddef.h>

#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

/* What makes a run acceptable (docs/MAPS.md, "Criteria"). Every criterion
 * counts a diverged run (exit 6) as unacceptable. */
typedef enum popc_map_criterion {
	POPC_MAP_DIVERGED,      /* the run did not diverge */
	POPC_MAP_LIMIT_CYCLE,   /* ... and no sustained limit cycle (limit_cycle = 0) */
	POPC_MAP_CHATTER,       /* ... and no PC chatter (chatter_s = 0) */
	POPC_MAP_PASSIVE,       /* ... and E_port never below -port_tol_J */
	POPC_MAP_DEVICE_PASSIVE, /* ... and E_dev = E_port + the plant's damping's
				  * dissipation never below -port_tol_J */
	POPC_MAP_STABLE,        /* a teleoperation run: completed (exit 0), so
				 * bounded, and settled (tele_oscillating = 0:
				 * its slave within 1 mm peak to peak over the
				 * last second, sweep_teleop.h) */
	POPC_MAP_N_CRITERIA
} popc_map_criterion;

const char *popc_map_criterion_name(popc_map_criterion c);
/* Parses "passive,diverged" into a bit set (1 << criterion); names the
 * unknown word and the allowed ones. */
int popc_map_criteria_parse(const char *text, unsigned *set, popc_error *err);

typedef enum popc_map_verdict {
	POPC_MAP_UNKNOWN = 0,   /* not run yet */
	POPC_MAP_OK,            /* acceptable */
	POPC_MAP_BAD,           /* not acceptable */
	POPC_MAP_UNDECIDED,     /* the run failed otherwise, or lacks the cell
				 * the criterion reads (too short for the detector,
				 * an axis without a true position) */
} popc_map_verdict;

/* What a run's row says, as the criteria read it. */
typedef struct popc_map_facts {
	int exit_status;
	int has_limit_cycle, limit_cycle;
	int has_chatter;
	double chatter_s;
	int has_port_energy_min;
	double port_energy_min_J;
	int has_device_energy_min;
	double device_energy_min_J;
	int has_tele_oscillating, tele_oscillating; /* a teleoperation sweep's */
} popc_map_facts;

/* The facts of a sweep row of plan p (a row of its summary.csv). */
int popc_map_facts_from_row(const popc_sweep_plan *p, const char *row, popc_map_facts *f,
			    popc_error *err);

/* The cell of the column named name in a row of plan p: *cell and *len
 * (len 0: empty). Returns 0, or -1 when the plan has no such column. */
int popc_map_row_cell(const popc_sweep_plan *p, const char *row, const char *name,
		      const char **cell, size_t *len);

/* The verdict of criterion c on a run (port_tol_J >= 0). */
popc_map_verdict popc_map_verdict_of(popc_map_criterion c, const popc_map_facts *f,
				     double port_tol_J);

/* ---- the grid -------------------------------------------------------------- */

/* Points of the log grid from k_lo to k_hi with a ratio of at most 1 + tol
 * between neighbours: ceil(log(k_hi / k_lo) / log(1 + tol)) + 1 (at least 2). */
long popc_map_grid_points(double k_lo, double k_hi, double tol);

/* The most points of a map's grid: 2^20, e.g. --tol 1e-4 over 45 decades
 * (a line's verdicts and the plan's K texts are held in memory).
 * popc_map_grid_points returns -1 beyond it, or when k_hi / k_lo or tol is
 * not a finite number above 0 (1e9 / 1e-300 overflows a double): the count
 * is compared as a double, never converted out of a long's range. */
#define POPC_MAP_GRID_MAX (1L << 20)

/* The scan's default step, in grid steps: 16 steps of 2 % are a factor of
 * 1.37; four decades at 2 % (467 points) take 31 scan points and two
 * bisections of 4 runs, 39 runs, 8.4 % of the grid (docs/MAPS.md). */
#define POPC_MAP_SCAN_STEPS_DEFAULT 16

/* Points of the scan of an n_k-point line with a step of scan_steps grid
 * steps: 0, scan_steps, 2 scan_steps, ... below n_k - 1, and n_k - 1. */
long popc_map_scan_points(long n_k, long scan_steps);

/* ---- the search ------------------------------------------------------------ */

typedef enum popc_map_outcome {
	POPC_MAP_NEEDS_RUNS,    /* need[0 .. n_need) are to run next */
	POPC_MAP_BRACKET,       /* the first failure bad_index, ok_index = bad_index - 1
				 * acceptable, and no acceptable scan point above */
	POPC_MAP_ALL_OK,        /* every scan point acceptable (no failure seen) */
	POPC_MAP_NONE_OK,       /* not acceptable at k_lo, nor at any scan point */
	POPC_MAP_NOT_MONOTONIC, /* the first failure bad_index (ok_index = bad_index - 1,
				 * or -1 when it is k_lo), and acceptable scan points
				 * above it: the band's top last_ok_index, with
				 * last_bad_index = last_ok_index + 1 (-1 when
				 * acceptable at k_hi) */
	POPC_MAP_UNDECIDED_RUN, /* a run the search needs has no verdict (culprit) */
} popc_map_outcome;

typedef struct popc_map_search {
	popc_map_outcome outcome;
	long *need;                    /* the caller's array of popc_map_scan_points
					* (n_k, scan_steps) entries */
	int n_need;
	long ok_index, bad_index;      /* the first failure's bracket; -1 where none */
	long last_ok_index, last_bad_index; /* NOT_MONOTONIC: the band's top; -1 otherwise */
	long culprit;                  /* UNDECIDED_RUN: the run without a verdict */
	long runs;                     /* the points the search used */
} popc_map_search;

/* One line's search: verdict[0 .. n_k) the verdicts of its points under one
 * criterion, need an array of popc_map_scan_points(n_k, scan_steps) entries.
 * First the scan (one batch); then, in one batch each step, bisection in
 * index (log K) between the scan point below the first unacceptable scan
 * point and it, and, where an acceptable scan point lies above that, between
 * the highest one and the next scan point. Points known for another
 * criterion are used where the search reaches them and change nothing else,
 * so a line's result does not depend on the other criteria asked for. */
void popc_map_search_line(const unsigned char *verdict, long n_k, long scan_steps, long *need,
			  popc_map_search *out);

#endif
