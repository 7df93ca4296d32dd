/* A teleoperation run's two-port figures as cells of a sweep's summary
 * (src/sweep/sweep_teleop.c; docs/SWEEPS.md, "Teleoperation scenes"): the
 * tele_* columns of a teleoperation sweep's table (sweep_columns.h), read
 * from the run summary's tele_* fields (run.h). */
#ifndef POPC_SWEEP_TELEOP_H
#define POPC_SWEEP_TELEOP_H

#include "popc/run/run.h"

/* A run whose slave's true position moved by more than this, peak to peak,
 * over the run's last second oscillates (the delay study's definition,
 * docs/TELEOPERATION.md; tests/unit/test_teleop.c's OSC_PP_M). */
#define POPC_SWEEP_TELEOP_SETTLED_PP_M 1e-3

/* The exit status of a diverged run (README, exit codes: 6 unstable). */
#define POPC_SWEEP_TELEOP_EXIT_DIVERGED 6

typedef struct popc_sweep_teleop_value {
	int is_whole;      /* whole: a count or a verdict (0/1) */
	long long whole;
	double real;
} popc_sweep_teleop_value;

/* The cell of column name for a run that exited with exit_status and gave
 * sum (NULL: none). Returns 1 with *v set, 0 for an empty cell (no summary,
 * or a figure the run did not reach: tele_xs_late_pp of a run that stopped
 * before its last second), -1 when name is not a tele_* column.
 *
 * tele_oscillating is the study's verdict: 1 when the run diverged (exit 6)
 * or its slave moved by more than POPC_SWEEP_TELEOP_SETTLED_PP_M peak to peak
 * over its last second, 0 when it completed and did not; empty when it
 * stopped otherwise (no verdict). */
int popc_sweep_teleop_cell(const char *name, const popc_run_summary *sum, int exit_status,
			   popc_sweep_teleop_value *v);

#endif
