/* libpopc's admittance port and device (API 1.1; docs/LIBRARY.md,
 * docs/ADMITTANCE.md): every admittance variant stepped through the public
 * API against the simulated admittance device gives, cell for cell and bit
 * for bit, the rows of popc_lib_run's log (popc run SCENE --log LOG) of the
 * two admittance scenes; the two causalities refuse each other's calls, naming
 * what is wrong; a non-finite velocity never reaches the device. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/popc.h"

static int failures;

static void check(int ok, const char *what)
{
	printf("%s - %s\n", ok ? "ok" : "not ok", what);
	if (!ok)
		failures++;
}

/* The log's cell of column name for the API's tick, its admittance fields
 * and the device's sample; 0 when the log has no such admittance column. */
static int cell(const char *name, const popc_lib_tick *t, const popc_lib_admittance_tick *a,
		const popc_lib_admittance_sample *smp, double *out)
{
	const struct {
		const char *name;
		double value;
	} cells[] = {
		{"t", t->t_s}, {"x", t->x_m}, {"count", (double)t->count}, {"x_true", smp->x_true_m},
		{"v", t->v_mps}, {"f_e", t->f_e_N}, {"f_pc", t->f_pc_N}, {"f_c", t->f_c_N},
		{"W", t->W_J}, {"E_ref", t->E_ref_J}, {"flags", (double)t->flags},
		{"f_count", (double)a->f_count}, {"f_meas", a->f_meas_N}, {"x_cmd", smp->x_cmd_m},
		{"v_ve", a->v_ve_mps}, {"v_pc", a->v_pc_mps},
	};
	for (size_t i = 0; i < sizeof cells / sizeof cells[0]; i++)
		if (!strcmp(cells[i].name, name)) {
			*out = cells[i].value;
			return 1;
		}
	return 0;
}

static void test_loop_equals_run(const char *scene_path, const char *variant, const char *dir)
{
	const char *base = strrchr(scene_path, '/') ? strrchr(scene_path, '/') + 1 : scene_path;
	popc_lib_scene *s;
	popc_lib_error err;
	popc_lib_scene_create(&s, NULL);
	int st = popc_lib_scene_load(s, scene_path, &err);
	if (!st)
		st = popc_lib_scene_set(s, "admittance.variant", variant, &err);
	char log_path[1024];
	snprintf(log_path, sizeof log_path, "%s/%s-%s.csv", dir, base, variant);
	if (!st)
		st = popc_lib_run(s, log_path, &err);
	popc_lib_port *port = NULL;
	popc_lib_sim *sim = NULL;
	popc_lib_log_reader *r = NULL;
	popc_lib_admittance_sample smp;
	if (!st)
		st = popc_lib_port_create_admittance(s, &port, &err);
	if (!st)
		st = popc_lib_sim_create_admittance(s, &sim, &smp, &err);
	if (!st)
		st = popc_lib_log_reader_open(&r, log_path, &err);
	if (st) {
		printf("not ok - %s %s: %s\n", base, variant, err.msg);
		failures++;
		return;
	}
	check(popc_lib_port_causality(port) == POPC_LIB_CAUSALITY_ADMITTANCE,
	      "the port's causality is admittance");
	int ncol = popc_lib_log_reader_column_count(r);
	double v[64];
	long long ticks = popc_lib_scene_tick_count(s), k = 0, differ = -1, active = 0;
	const char *differ_col = "", *unknown = NULL;
	for (; k < ticks; k++) {
		popc_lib_tick t;
		popc_lib_admittance_tick a;
		popc_lib_port_step_admittance(port, smp.count, smp.force_count, &t, &a);
		active += a.v_pc_mps != 0.0;
		if (popc_lib_log_reader_next(r, v, &err) != 1)
			break;
		for (int i = 0; i < ncol; i++) {
			const char *name = popc_lib_log_reader_column_name(r, i);
			double mine;
			if (!cell(name, &t, &a, &smp, &mine)) {
				unknown = name;
				continue;
			}
			if (memcmp(&mine, &v[i], sizeof mine) != 0 && differ < 0) {
				differ = k;
				differ_col = name;
			}
		}
		if (k + 1 < ticks && popc_lib_sim_exchange_admittance(sim, a.v_c_mps, &smp, &err))
			break;
	}
	char what[1024];
	snprintf(what, sizeof what, "%s %s: %lld of %lld ticks through the API equal popc_lib_run's "
		 "log, every cell (first difference: tick %lld, column %s; PC active on %lld ticks)",
		 base, variant, k, ticks, differ, differ_col, active);
	check(k == ticks && differ < 0, what);
	snprintf(what, sizeof what, "%s %s: the log's 15 columns, none the test does not know (%d; %s)",
		 base, variant, ncol, unknown ? unknown : "none");
	check(unknown == NULL && ncol == 15, what);
	check(popc_lib_log_reader_next(r, v, &err) == 0 &&
	      !strcmp(popc_lib_log_reader_stop_reason(r), "completed"), "  the log ends, completed");
	popc_lib_log_reader_close(r);
	popc_lib_sim_free(sim);
	popc_lib_port_free(port);
	popc_lib_scene_free(s);
}

/* The two causalities' calls on the other's handles, and bad input */
static void test_refusals(const char *scene_path)
{
	popc_lib_scene *imp, *adm;
	popc_lib_error err = {{0}};
	popc_lib_scene_create(&imp, NULL);
	popc_lib_scene_create(&adm, NULL);
	popc_lib_scene_load(adm, scene_path, NULL);
	popc_lib_port *p = NULL;
	popc_lib_sim *sim = NULL;
	int st = popc_lib_port_create_admittance(imp, &p, &err);
	check(st == POPC_LIB_ERR_INVALID && p == NULL && strstr(err.msg, "device.causality") &&
	      strstr(err.msg, "admittance"),
	      "an admittance port of an impedance scene is refused, naming device.causality");
	popc_lib_admittance_sample as, before;
	st = popc_lib_sim_create_admittance(imp, &sim, &as, &err);
	check(st == POPC_LIB_ERR_INVALID && sim == NULL && strstr(err.msg, "device.causality"),
	      "an admittance device of an impedance scene is refused, naming device.causality");
	/* the impedance calls on an admittance scene would run the wrong device
	 * and controller silently */
	st = popc_lib_port_create_impedance(adm, 0.0, &p, &err);
	check(st == POPC_LIB_ERR_INVALID && p == NULL && strstr(err.msg, "device.causality") &&
	      strstr(err.msg, "popc_lib_port_create_admittance"),
	      "an impedance port of an admittance scene is refused, naming device.causality");
	popc_lib_sample is;
	st = popc_lib_sim_create(adm, &sim, &is, &err);
	check(st == POPC_LIB_ERR_INVALID && sim == NULL && strstr(err.msg, "device.causality") &&
	      strstr(err.msg, "popc_lib_sim_create_admittance"),
	      "an impedance device of an admittance scene is refused, naming device.causality");
	/* a port of one causality stepped as the other: no motion, no force */
	popc_lib_port *ap = NULL, *ip = NULL;
	popc_lib_port_create_admittance(adm, &ap, NULL);
	popc_lib_port_create_impedance(imp, 0.0, &ip, NULL);
	popc_lib_tick t;
	popc_lib_admittance_tick a;
	memset(&t, 0xff, sizeof t);
	memset(&a, 0xff, sizeof a);
	popc_lib_port_step_admittance(ip, 5, 100, &t, &a);
	popc_lib_tick zero;
	popc_lib_admittance_tick azero;
	memset(&zero, 0, sizeof zero);
	memset(&azero, 0, sizeof azero);
	check(!memcmp(&t, &zero, sizeof t) && !memcmp(&a, &azero, sizeof a),
	      "an impedance port stepped as admittance gives 0 in every field");
	memset(&t, 0xff, sizeof t);
	popc_lib_port_step(ap, 5, &t);
	check(!memcmp(&t, &zero, sizeof t), "an admittance port stepped as impedance gives 0 in every field");
	/* ... and its state is untouched: its first real tick is tick 0 */
	popc_lib_port_step_admittance(ap, 0, 0, &t, NULL);
	check(t.t_s == 0.0 && isfinite(t.v_mps), "  the admittance port's next step is its tick 0");
	popc_lib_port_free(ap);
	popc_lib_port_free(ip);
	/* the devices: the other causality's exchange refused, naming the call to make */
	popc_lib_sample smp;
	popc_lib_sim *isim = NULL;
	popc_lib_sim_create(imp, &isim, &smp, NULL);
	st = popc_lib_sim_exchange_admittance(isim, 0.0, &as, &err);
	check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "popc_lib_sim_exchange"),
	      "an impedance device refuses a velocity, naming popc_lib_sim_exchange");
	popc_lib_sim_free(isim);
	st = popc_lib_sim_create_admittance(adm, &sim, &as, &err);
	check(st == 0, "the admittance scene's device is made");
	st = popc_lib_sim_exchange(sim, 0.0, &smp, &err);
	check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "popc_lib_sim_exchange_admittance"),
	      "an admittance device refuses a force, naming popc_lib_sim_exchange_admittance");
	/* popc_lib_sim_tick (API 1.3) is impedance alone: an admittance port or
	 * device refused, nothing stepped */
	{
		popc_lib_port *ip2 = NULL, *ap2 = NULL;
		popc_lib_sim *isim2 = NULL;
		popc_lib_sample s2, s2_before;
		popc_lib_port_create_impedance(imp, 0.0, &ip2, NULL);
		popc_lib_port_create_admittance(adm, &ap2, NULL);
		popc_lib_sim_create(imp, &isim2, &s2, NULL);
		s2_before = s2;
		st = popc_lib_sim_tick(ip2, sim, &s2, &t, &err);
		check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "impedance-type") &&
		      !memcmp(&s2, &s2_before, sizeof s2),
		      "popc_lib_sim_tick refuses an admittance device, naming impedance-type");
		st = popc_lib_sim_tick(ap2, isim2, &s2, &t, &err);
		check(st == POPC_LIB_ERR_INVALID && !memcmp(&s2, &s2_before, sizeof s2),
		      "popc_lib_sim_tick refuses an admittance port");
		popc_lib_port_step(ip2, s2.count, &t);
		check(t.t_s == 0.0, "  nothing stepped: the impedance port's next step is its tick 0");
		popc_lib_port_free(ip2);
		popc_lib_port_free(ap2);
		popc_lib_sim_free(isim2);
	}
	static const double bad[] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
	for (size_t i = 0; i < 3; i++) {
		before = as;
		st = popc_lib_sim_exchange_admittance(sim, bad[i], &as, &err);
		check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "v_c_mps") &&
		      !memcmp(&as, &before, sizeof as),
		      "a non-finite velocity is refused, naming v_c_mps, the sample untouched");
	}
	check(popc_lib_sim_exchange_admittance(sim, 0.0, &as, &err) == 0 && isfinite(as.x_true_m),
	      "  and the device runs on");
	popc_lib_sim_free(sim);
	popc_lib_scene_free(imp);
	popc_lib_scene_free(adm);
}

int main(int argc, char **argv)
{
	if (argc < 4) {
		fprintf(stderr, "usage: test_lib_admittance ADMITTANCE_SCENE ADMITTANCE_WALL_SCENE "
			"SCRATCH_DIR\n");
		return 2;
	}
	check(popc_lib_api_version() >= POPC_LIB_API_VERSION_INT(1, 1, 0),
	      "the library is API 1.1 or later (the admittance calls)");
	test_refusals(argv[1]);
	static const char *const variants[] = {"none", "parallel-pc", "parallel-ignore",
					       "parallel-hold", "parallel-improved"};
	/* admittance.ini: a steady push; admittance-wall.ini: the low-force
	 * wall, where the PC acts (docs/ADMITTANCE.md) */
	for (int sc = 1; sc <= 2; sc++)
		for (size_t i = 0; i < sizeof variants / sizeof variants[0]; i++)
			test_loop_equals_run(argv[sc], variants[i], argv[3]);
	printf("# %d failed\n", failures);
	return failures ? 1 : 0;
}
