/* The chatter columns' detector (sweep_chatter.h). */
#include "popc/sweep/sweep_chatter.h"

#include <string.h>

#include "popc/log/log.h"
#include "popc/log/log_reader.h"
#include "popc/scene/from_scene.h"

int popc_sweep_chatter_init(popc_chatter *det, const popc_scene *s,
			    const popc_controller_config *ccfg, popc_error *err)
{
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	/* the thresholds are relative to the scene run (docs/ANALYSIS.md) */
	cc.resolution_m = s->enc_resolution_m;
	cc.pc_bound_N = popc_sweep_chatter_pc_scale(s);
	int st = popc_chatter_init(det, &cc, popc_scene_period_s(s), &ccfg->env, err);
	if (st) {
		/* the detector's parameters that come from the scene, as its keys */
		static const popc_error_name keys[] = {
			{"period_s", "1 / run.rate"},
			{"resolution_m", "encoder.resolution"},
			{"pc_bound_N", "controller.pc_bound"},
		};
		static const popc_error_name adm_keys[] = {
			{"period_s", "1 / run.rate"},
			{"resolution_m", "encoder.resolution"},
			{"pc_bound_N", "the velocity of one force count (admittance.force_resolution, "
				       "environment.stiffness)"},
		};
		if (s->causality == POPC_CAUSALITY_ADMITTANCE)
			popc_error_name_params(err, adm_keys, sizeof adm_keys / sizeof adm_keys[0]);
		else
			popc_error_name_params(err, keys, sizeof keys / sizeof keys[0]);
	}
	return st;
}

double popc_sweep_chatter_pc_scale(const popc_scene *s)
{
	if (s->causality != POPC_CAUSALITY_ADMITTANCE)
		return s->pc_bound_N;
	/* the parallel PC's output is a velocity: its scale is one force count's
	 * (popc_admittance_count_velocity_mps), not admittance.pc_velocity_bound */
	return POPC_ADMITTANCE_CHATTER_COUNTS *
	       popc_admittance_count_velocity_mps(s->adm_force_resolution_N, s->env_stiffness_Npm,
						  s->adm_virtual_mass_kg, s->adm_virtual_damping_Nspm,
						  popc_scene_period_s(s));
}

int popc_sweep_chatter_from_log(const char *log_path, popc_chatter_result *res, popc_error *err)
{
	popc_log_reader r;
	int st = popc_log_reader_open(&r, log_path, NULL, err);
	if (st)
		return st;
	popc_scene s;
	popc_scene_defaults(&s);
	st = popc_log_reader_scene(&r, &s, err);
	/* the columns the detector reads (popc_chatter_add) */
	static const popc_log_column_id used[] = {POPC_LOG_COLUMN_T, POPC_LOG_COLUMN_X,
						  POPC_LOG_COLUMN_F_PC, POPC_LOG_COLUMN_W,
						  POPC_LOG_COLUMN_E_REF};
	enum { N_USED = sizeof used / sizeof used[0] };
	int col[N_USED];
	for (int k = 0; k < N_USED && !st; k++) {
		/* an admittance log: the detector reads the parallel PC's v_pc in
		 * f_pc's place, as the run's on_tick hook gives it */
		const char *name = popc_log_columns[used[k]].name;
		if (used[k] == POPC_LOG_COLUMN_F_PC && s.causality == POPC_CAUSALITY_ADMITTANCE)
			name = "v_pc";
		st = popc_log_reader_require(&r, name, &col[k], err);
	}
	popc_controller_config ccfg;
	popc_chatter det;
	if (!st) {
		popc_controller_config_from_scene(&ccfg, &s);
		st = popc_sweep_chatter_init(&det, &s, &ccfg, err);
	}
	double v[POPC_LOG_MAX_COLUMNS];
	while (!st && (st = popc_log_reader_next(&r, v, err)) == 1) {
		popc_log_row row;
		memset(&row, 0, sizeof row);
		for (int k = 0; k < N_USED; k++)
			popc_log_row_set(&row, used[k], v[col[k]]);
		popc_chatter_add(&det, &row.tick);
		st = 0;
	}
	popc_log_reader_close(&r);
	if (st < 0)
		return st;
	popc_chatter_finish(&det, res);
	return 0;
}
