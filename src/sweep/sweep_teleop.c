/* The tele_* cells of a teleoperation sweep (sweep_teleop.h). */
#include "popc/sweep/sweep_teleop.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* The slave's late peak to peak, when the run reached its last second. */
static int late_pp(const popc_run_summary *sum, double *pp)
{
	if (!(sum->tele_xs_late_min_m <= sum->tele_xs_late_max_m))
		return 0; /* no tick in the window: min +inf, max -inf */
	*pp = sum->tele_xs_late_max_m - sum->tele_xs_late_min_m;
	return isfinite(*pp);
}

int popc_sweep_teleop_cell(const char *name, const popc_run_summary *sum, int exit_status,
			   popc_sweep_teleop_value *v)
{
	static const struct {
		const char *name;
		int kind; /* 0 a count, 1 a double */
		size_t off;
	} fields[] = {
		{"tele_violations", 0, offsetof(popc_run_summary, tele_violations)},
		{"tele_margin_min_m", 1, offsetof(popc_run_summary, tele_margin_min_J[0])},
		{"tele_margin_min_s", 1, offsetof(popc_run_summary, tele_margin_min_J[1])},
		{"tele_active_m", 0, offsetof(popc_run_summary, tele_active[0])},
		{"tele_active_s", 0, offsetof(popc_run_summary, tele_active[1])},
		{"tele_clamped_m", 0, offsetof(popc_run_summary, tele_clamped[0])},
		{"tele_clamped_s", 0, offsetof(popc_run_summary, tele_clamped[1])},
		{"tele_f_c_max", 1, offsetof(popc_run_summary, tele_f_c_max_N)},
		{"tele_v_c_max", 1, offsetof(popc_run_summary, tele_v_c_max_mps)},
		{"tele_drift_end", 1, offsetof(popc_run_summary, tele_drift_end_m)},
	};
	memset(v, 0, sizeof *v);
	int known = strcmp(name, "tele_xs_late_pp") == 0 || strcmp(name, "tele_oscillating") == 0;
	for (size_t i = 0; i < sizeof fields / sizeof fields[0] && !known; i++)
		known = strcmp(name, fields[i].name) == 0;
	if (!known)
		return -1;
	if (!sum || !sum->has_teleop)
		return 0;
	double pp = 0.0;
	int has_pp = late_pp(sum, &pp);
	if (strcmp(name, "tele_xs_late_pp") == 0) {
		v->real = pp;
		return has_pp;
	}
	if (strcmp(name, "tele_oscillating") == 0) {
		v->is_whole = 1;
		if (exit_status == POPC_SWEEP_TELEOP_EXIT_DIVERGED) {
			v->whole = 1;
			return 1;
		}
		if (exit_status != 0 || !has_pp)
			return 0;
		v->whole = !(pp <= POPC_SWEEP_TELEOP_SETTLED_PP_M);
		return 1;
	}
	for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
		if (strcmp(name, fields[i].name) != 0)
			continue;
		const char *at = (const char *)sum + fields[i].off;
		if (fields[i].kind == 0) {
			v->is_whole = 1;
			memcpy(&v->whole, at, sizeof v->whole);
			return 1;
		}
		memcpy(&v->real, at, sizeof v->real);
		/* no NaN or infinity reaches a summary cell (a run stopped at
		 * its non-finite command has not folded one in; belt and braces) */
		return isfinite(v->real);
	}
	return 0;
}
