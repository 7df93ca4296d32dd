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
	cc.resolution_m = s->enc_resolution_m;
	return popc_chatter_init(det, &cc, popc_scene_period_s(s), &ccfg->env, err);
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
	int col[5];
	static const char *const names[5] = {"t", "x", "f_pc", "W", "E_ref"};
	for (int k = 0; k < 5 && !st; k++)
		st = popc_log_reader_require(&r, names[k], &col[k], err);
	popc_controller_config ccfg;
	popc_chatter det;
	if (!st) {
		popc_controller_config_from_scene(&ccfg, &s);
		st = popc_sweep_chatter_init(&det, &s, &ccfg, err);
	}
	double v[POPC_LOG_MAX_COLUMNS];
	while (!st && (st = popc_log_reader_next(&r, v, err)) == 1) {
		popc_tick t;
		memset(&t, 0, sizeof t);
		t.t_s = v[col[0]];
		t.x_m = v[col[1]];
		t.f_pc_N = v[col[2]];
		t.W_J = v[col[3]];
		t.E_ref_J = v[col[4]];
		popc_chatter_add(&det, &t);
		st = 0;
	}
	popc_log_reader_close(&r);
	if (st < 0)
		return st;
	popc_chatter_finish(&det, res);
	return 0;
}
