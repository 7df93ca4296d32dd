/* popc sweep --list (sweep_list.c): one `popc run` command line per run, for
 * GNU parallel or any other runner; `popc sweep merge` gathers their results. */
#ifndef POPC_CLI_SWEEP_LIST_H
#define POPC_CLI_SWEEP_LIST_H

#include "popc/sweep/sweep_plan.h"

/* Prints the lines of the runs of shard sh on stdout, program being the popc
 * they call and dir_abs the sweep directory (absolute). Returns an exit code. */
int sweep_list_print(const popc_sweep_plan *p, const popc_sweep_shard *sh, const char *program,
		     const char *dir_abs);

#endif
