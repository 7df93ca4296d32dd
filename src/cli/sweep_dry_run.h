/* popc sweep --dry-run and popc map --dry-run (sweep_dry_run.c): the plan and
 * its runs printed, nothing written: no directory, plan, lock or run
 * directory is made (unlike --list, which writes each run's scene). */
#ifndef POPC_CLI_SWEEP_DRY_RUN_H
#define POPC_CLI_SWEEP_DRY_RUN_H

#include "popc/sweep/sweep_plan.h"

/* What a sweep into dir would find there, read only: "does not exist (it
 * would be made)", "exists, no sweep in it", "holds this sweep: K of N runs
 * have a result (it would resume)", or "holds another sweep (it would be
 * refused)". Returns 1 for the last, else 0. */
int sweep_dry_run_dir(FILE *f, const popc_sweep_plan *p, const char *dir);

/* popc sweep --dry-run: a header line, then one line per run of the shard:
 * "ID<TAB>section.key=value ..." on stdout. Returns an exit code: 0, or 2
 * when dir holds another sweep (the sweep itself would be refused). */
int sweep_dry_run_print(const popc_sweep_plan *p, const popc_sweep_shard *sh, const char *dir);

#endif
