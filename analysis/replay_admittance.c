/* popc-analyze replay of an admittance log (docs/ANALYSIS.md, "Replay of an
 * admittance log"): each parallel PC variant recomputed over the recorded
 * force counts with the core's controller (popc_admittance_step, the code
 * that ran). The VE is driven by the force reading alone, so its velocity
 * is the recorded one; what changes is the observer's W, the PC's v_pc and
 * the command v = v_VE + v_pc. The device's response to that command is not
 * recorded: position, count, x_cmd, x_true and E_port are the recording's. */
#include <math.h>
#include <string.h>

#include "analyze.h"
#include "popc/core/encoder.h"
#include "popc/log/log.h"
#include "popc/scene/from_scene.h"

int ana_replay_admittance(ana_log *l, const char *path, const popc_scene *base,
			  const popc_admittance_variant *variants, char (*out_paths)[1100], int n,
			  int quiet)
{
	popc_admittance_controller ctl[POPC_ADMITTANCE_VARIANT_COUNT];
	popc_scene scene[POPC_ADMITTANCE_VARIANT_COUNT];
	popc_log_writer w[POPC_ADMITTANCE_VARIANT_COUNT];
	int open[POPC_ADMITTANCE_VARIANT_COUNT] = {0};
	popc_error err;
	int st = 0, rc = 0;
	if (l->c_f_count < 0) {
		fprintf(stderr, "popc-analyze replay: %s: an admittance log needs its f_count column "
				"(the force counts the variants are replayed over)\n",
			path);
		return POPC_EXIT_USAGE;
	}
	unsigned columns = POPC_LOG_COL_ADMITTANCE |
			   (l->c_x_true >= 0 ? POPC_LOG_COL_X_TRUE : 0u) |
			   (l->c_dt >= 0 && l->c_rtt >= 0 ? POPC_LOG_COL_TIMING : 0u);
	char extra[1400];
	snprintf(extra, sizeof extra, "# replay_of = %s\n# replay_of_variant = %s\n", path, l->variant);
	for (int i = 0; i < n && !st; i++) {
		scene[i] = *base;
		scene[i].adm_variant = variants[i];
		st = popc_log_open(&w[i], out_paths[i], columns, &err);
		if (!st) {
			open[i] = 1;
			st = popc_log_write_header(&w[i], "replay", &scene[i], extra, &err);
		}
	}
	ana_row row;
	long long k = 0;
	while (!st && (st = ana_log_next(l, &row, &err)) == 1) {
		st = 0;
		for (int i = 0; i < n && !st; i++) {
			if (k == 0) {
				/* the VE starts at rest at the first row's measured
				 * position, as run_admittance.c starts it */
				popc_admittance_config acfg;
				popc_admittance_config_from_scene(&acfg, &scene[i]);
				popc_admittance_init(&ctl[i], &acfg,
						     popc_encoder_position(row.tick.count,
									   base->enc_resolution_m));
			}
			popc_log_row lr;
			memset(&lr, 0, sizeof lr);
			popc_admittance_step(&ctl[i], row.adm_count, &lr.adm);
			/* the columns every log has, in their admittance meaning
			 * (run_admittance.c) */
			lr.tick.t_s = row.tick.t_s;
			lr.tick.count = row.tick.count;
			lr.tick.x_m = row.tick.x_m;
			lr.tick.v_mps = lr.adm.v_c_mps;
			lr.tick.f_e_N = lr.adm.f_env_N;
			lr.tick.W_J = lr.adm.W_J;
			lr.tick.flags = lr.adm.flags;
			lr.x_true_m = row.x_true_m;
			lr.E_port_J = isfinite(row.E_port_J) ? row.E_port_J : 0.0;
			lr.dt_s = row.dt_s;
			lr.rtt_s = row.rtt_s;
			lr.x_cmd_m = row.adm_x_cmd_m;
			st = popc_log_write_row(&w[i], &lr, &err);
		}
		k++;
	}
	if (st) {
		rc = ana_fail("replay", st, &err);
		for (int i = 0; i < n; i++) {
			popc_error cerr;
			if (open[i])
				popc_log_write_comment(&w[i], "stop", "input error", &cerr);
		}
	}
	for (int i = 0; i < n; i++) {
		if (!open[i])
			continue;
		popc_error cerr;
		int cst = rc ? 0
			     : popc_log_write_comment(&w[i], "stop",
						      l->unfinished ? "input unfinished" : "completed",
						      &cerr);
		if (!cst)
			cst = popc_log_close(&w[i], &cerr);
		else
			popc_log_close(&w[i], &err);
		if (cst && !rc)
			rc = ana_fail("replay", cst, &cerr);
		else if (!rc && !quiet)
			printf("%s\n", out_paths[i]);
	}
	return rc;
}
