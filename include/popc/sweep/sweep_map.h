/* Stability maps (src/sweep/sweep_map.c): the largest acceptable wall
 * stiffness K of every line of a map, found by bisection in log K.
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
 * stored): it replays the bisection from the two ends of the grid and returns
 * the indices it needs next, or its result. The same verdicts give the same
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

/* Grid steps that make a factor of two (the re-run points K/2 and 2K):
 * round(log 2 / log(ratio)), at least 1. */
long popc_map_check_steps(double k_lo, double k_hi, long n_k);

/* ---- the search ------------------------------------------------------------ */

typedef enum popc_map_outcome {
	POPC_MAP_NEEDS_RUNS,    /* need[0 .. n_need) are to run next */
	POPC_MAP_BRACKET,       /* ok_index acceptable, bad_index = ok_index + 1 not,
				 * and the checks agree */
	POPC_MAP_ALL_OK,        /* acceptable up to k_hi (the edge is above the range) */
	POPC_MAP_NONE_OK,       /* not acceptable at k_lo (the edge is below the range) */
	POPC_MAP_NOT_MONOTONIC, /* an acceptable point above an unacceptable one:
				 * culprit_ok > culprit_bad; no edge is drawn */
	POPC_MAP_UNDECIDED_RUN, /* a run the search needs has no verdict (culprit_ok) */
} popc_map_outcome;

typedef struct popc_map_search {
	popc_map_outcome outcome;
	long need[2];
	int n_need;
	long ok_index, bad_index;      /* the bracket (BRACKET); -1 otherwise */
	long check_low, check_high;    /* the re-run points: ok_index - check_steps
					* and bad_index + check_steps, clamped to
					* the grid; -1 when not reached */
	long culprit_ok, culprit_bad;  /* NOT_MONOTONIC / UNDECIDED_RUN */
	long runs;                     /* the points the search used */
} popc_map_search;

/* One line's search: verdict[0 .. n_k) the verdicts of its points under one
 * criterion. Bisection in index (log K) from the two ends, then the two
 * checks; every known verdict is compared with the bracket, so an acceptable
 * point above it or an unacceptable one below it (a run for another
 * criterion, a check) marks the line not monotonic. */
void popc_map_search_line(const unsigned char *verdict, long n_k, long check_steps,
			  popc_map_search *out);

#endif
