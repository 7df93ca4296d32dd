/* The control tick stripped to its arithmetic (bench_floor.c), for `popc bench loop`. */
#ifndef POPC_BENCH_FLOOR_H
#define POPC_BENCH_FLOOR_H

#include "popc/util/error.h"
#include "popc/scene/scene.h"

typedef struct popc_tick_floor {
	const char *not_covered;    /* non-NULL: the scene is outside the chain's reach */
	long long ticks_checked;    /* commands compared with the real loop's */
	int bitwise_equal;          /* all of them equal bit for bit: the figure is valid */
	long long first_difference; /* else: the first tick that differs */
	double ns_per_tick;         /* fastest of the repeats; NaN when not measured */
} popc_tick_floor;

/* Checks the stripped tick's command sequence against f_c_ref (the real
 * loop's n_ref commands, one per exchange) and, when equal bit for bit, times
 * it: the fastest of `repeats` measurements of at least min_time_s each.
 * Returns 0 (see out) or the status of a scene that cannot be set up. */
int popc_bench_tick_floor(const popc_scene *s, const double *f_c_ref, long long n_ref,
			  double min_time_s, int repeats, popc_tick_floor *out, popc_error *err);

#endif
