/* libpopc's public API, table-driven where it takes input: versions; bad
 * scene input refused with the key and the allowed range; the port's tick
 * equal to popc run's log row and the observer's W equal to the port's;
 * the log writer's rows read back bit for bit; frees that take NULL; the
 * data path is the caller's, never the environment's; popc_lib_sim_tick's
 * bits are the two calls'; a log's scene runs to the same log. */
#define _POSIX_C_SOURCE 200809L /* setenv */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/popc.h"
#include "popc_config.h"

static int failures;

static void check(int ok, const char *what)
{
	printf("%s - %s\n", ok ? "ok" : "not ok", what);
	if (!ok)
		failures++;
}

static void test_versions(void)
{
	check(popc_lib_api_version() == POPC_LIB_API_VERSION, "the library's API version is the header's");
	check(popc_lib_api_version() >> 16 == POPC_LIB_API_VERSION_MAJOR, "  its major is the soname's");
	check(strcmp(popc_lib_version(), POPC_VERSION) == 0, "popc_lib_version is the project's version");
}

/* key, value, status, words the message must hold */
static const struct bad_set {
	const char *key, *value;
	int status;
	const char *says;
} bad_sets[] = {
	{"controller.variant", "nonesuch", POPC_LIB_ERR_INVALID, "controller.variant"},
	{"run.rate", "0", POPC_LIB_ERR_INVALID, "run.rate"},
	{"run.rate", "nan", POPC_LIB_ERR_INVALID, "run.rate"},
	{"encoder.resolution", "-1", POPC_LIB_ERR_INVALID, "encoder.resolution"},
	{"nosuchsection.key", "1", POPC_LIB_ERR_INVALID, "nosuchsection"},
	{"rate", "1000", POPC_LIB_ERR_INVALID, "section.key"},
	{".rate", "1000", POPC_LIB_ERR_INVALID, "section.key"},
	{"run.", "1000", POPC_LIB_ERR_INVALID, "section.key"},
};

static void test_bad_input(const char *dir)
{
	for (size_t i = 0; i < sizeof bad_sets / sizeof bad_sets[0]; i++) {
		const struct bad_set *b = &bad_sets[i];
		popc_lib_scene *s;
		popc_lib_error err = {{0}};
		popc_lib_scene_create(&s, NULL);
		int st = popc_lib_scene_set(s, b->key, b->value, &err);
		char what[1024];
		snprintf(what, sizeof what, "set %s=%s: status %d, says '%s' (%s)", b->key, b->value,
			 b->status, b->says, err.msg);
		check(st == b->status && strstr(err.msg, b->says) != NULL, what);
		popc_lib_scene_free(s);
	}
	popc_lib_scene *s;
	popc_lib_error err = {{0}};
	popc_lib_scene_create(&s, NULL);
	int st = popc_lib_scene_load(s, "/nonexistent/scene.ini", &err);
	check(st == POPC_LIB_ERR_INVALID || st == POPC_LIB_ERR_IO, "a missing scene file is refused");
	check(strstr(err.msg, "/nonexistent/scene.ini") != NULL, "  naming it");
	popc_lib_port *p = NULL;
	st = popc_lib_port_create_impedance(s, -1.0, &p, &err);
	check(st == POPC_LIB_ERR_INVALID && p == NULL && strstr(err.msg, "force_limit_N"),
	      "a negative force limit is refused, naming it");
	st = popc_lib_port_create_impedance(s, (double)NAN, &p, &err);
	check(st == POPC_LIB_ERR_INVALID && p == NULL, "a NaN force limit is refused");
	popc_lib_scene_free(s);
	/* NaN and inf reach neither the device nor a log cell */
	popc_lib_scene_create(&s, NULL);
	popc_lib_scene_set(s, "run.duration", "0.01", NULL);
	popc_lib_sim *sim = NULL;
	popc_lib_sample smp, before;
	popc_lib_sim_create(s, &sim, &smp, NULL);
	static const double bad_forces[] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
	for (size_t i = 0; i < 3; i++) {
		before = smp;
		st = popc_lib_sim_exchange(sim, bad_forces[i], &smp, &err);
		check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "f_c_N") &&
		      memcmp(&smp, &before, sizeof smp) == 0,
		      "a non-finite force is refused, naming f_c_N, the sample untouched");
	}
	check(popc_lib_sim_exchange(sim, 0.0, &smp, &err) == 0 && isfinite(smp.x_true_m),
	      "  and the device runs on");
	popc_lib_sim_free(sim);
	char path[1024];
	snprintf(path, sizeof path, "%s/nan.csv", dir);
	popc_lib_log_writer *w = NULL;
	st = popc_lib_log_writer_open(&w, path, s, "sim", POPC_LIB_LOG_X_TRUE, &err);
	popc_lib_row row;
	memset(&row, 0, sizeof row);
	st = st ? st : popc_lib_log_write_row(w, &row, &err);
	row.tick.t_s = 0.001;
	row.E_port_J = (double)NAN;
	int st_nan = popc_lib_log_write_row(w, &row, &err);
	check(!st && st_nan == POPC_LIB_ERR_INVALID && strstr(err.msg, "E_port") && strstr(err.msg, "nan.csv"),
	      "a NaN cell is refused, naming the log and the column");
	row.E_port_J = 0.0;
	row.dt_s = (double)NAN; /* not a column of this log: not written, not refused */
	check(popc_lib_log_write_row(w, &row, &err) == 0, "  a NaN where the log has no column is not written");
	check(popc_lib_log_writer_close(w, "completed", &err) == 0, "  the log closes");
	popc_lib_log_reader *r = NULL;
	double v[64];
	int rows = 0;
	if (popc_lib_log_reader_open(&r, path, &err) == 0) {
		while (popc_lib_log_reader_next(r, v, &err) == 1)
			rows++;
		popc_lib_log_reader_close(r);
	}
	check(rows == 2, "  the log holds the two good rows, nothing of the refused one");
	popc_lib_scene_free(s);
}

/* The port, the device and the observer over the scene; every tick's cells
 * against the log popc_lib_run wrote (the log of popc run) */
static void test_loop_equals_run(const char *scene_path, const char *variant, const char *dir)
{
	popc_lib_scene *s;
	popc_lib_error err;
	popc_lib_scene_create(&s, NULL);
	int st = popc_lib_scene_load(s, scene_path, &err);
	if (!st)
		st = popc_lib_scene_set(s, "controller.variant", variant, &err);
	if (!st)
		st = popc_lib_scene_set(s, "run.duration", "1", &err);
	char log_path[1024], mine_path[1024];
	snprintf(log_path, sizeof log_path, "%s/run-%s.csv", dir, variant);
	snprintf(mine_path, sizeof mine_path, "%s/mine-%s.csv", dir, variant);
	if (!st)
		st = popc_lib_run(s, log_path, &err);
	popc_lib_port *port = NULL;
	popc_lib_sim *sim = NULL;
	popc_lib_observer *obs = NULL;
	popc_lib_log_writer *w = NULL;
	popc_lib_log_reader *r = NULL;
	popc_lib_sample smp;
	if (!st)
		st = popc_lib_port_create_impedance(s, 0.0, &port, &err);
	if (!st)
		st = popc_lib_sim_create(s, &sim, &smp, &err);
	if (!st)
		st = popc_lib_observer_create(s, &obs, &err);
	if (!st)
		st = popc_lib_log_writer_open(&w, mine_path, s, "sim", POPC_LIB_LOG_X_TRUE, &err);
	if (!st)
		st = popc_lib_log_reader_open(&r, log_path, &err);
	if (st) {
		printf("not ok - %s: %s\n", variant, err.msg);
		failures++;
		return;
	}
	int ncol = popc_lib_log_reader_column_count(r);
	int ifc = -1, iW = -1, ixt = -1, iEp = -1, iflags = -1;
	for (int i = 0; i < ncol; i++) {
		const char *n = popc_lib_log_reader_column_name(r, i);
		if (!strcmp(n, "f_c")) ifc = i;
		if (!strcmp(n, "W")) iW = i;
		if (!strcmp(n, "x_true")) ixt = i;
		if (!strcmp(n, "E_port")) iEp = i;
		if (!strcmp(n, "flags")) iflags = i;
	}
	double v[64];
	long long ticks = popc_lib_scene_tick_count(s), k = 0, differ = -1, obs_differ = -1;
	for (; k < ticks; k++) {
		popc_lib_tick t;
		popc_lib_port_step(port, smp.count, &t);
		double W;
		popc_lib_observer_step(obs, &t, &W, NULL);
		if (memcmp(&W, &t.W_J, sizeof W) != 0 && obs_differ < 0)
			obs_differ = k;
		popc_lib_row row = {.tick = t, .x_true_m = smp.x_true_m, .E_port_J = smp.E_port_J};
		popc_lib_log_write_row(w, &row, NULL);
		if (popc_lib_log_reader_next(r, v, &err) != 1)
			break;
		if ((memcmp(&v[ifc], &t.f_c_N, sizeof(double)) || memcmp(&v[iW], &t.W_J, sizeof(double)) ||
		     memcmp(&v[ixt], &smp.x_true_m, sizeof(double)) ||
		     memcmp(&v[iEp], &smp.E_port_J, sizeof(double)) || v[iflags] != (double)t.flags) &&
		    differ < 0)
			differ = k;
		if (k + 1 < ticks && popc_lib_sim_exchange(sim, t.f_c_N, &smp, &err))
			break;
	}
	char what[1024];
	snprintf(what, sizeof what, "%s: %lld ticks through the API equal popc_lib_run's log (first "
		 "difference: %lld)", variant, k, differ);
	check(k == ticks && differ < 0, what);
	snprintf(what, sizeof what, "%s: the observer alone gives the port's W (first difference: %lld)",
		 variant, obs_differ);
	check(obs_differ < 0, what);
	check(popc_lib_log_reader_next(r, v, &err) == 0 &&
	      !strcmp(popc_lib_log_reader_stop_reason(r), "completed"), "  the log ends, completed");
	check(popc_lib_log_writer_close(w, "completed", &err) == 0, "  the API's log closes");
	popc_lib_log_reader_close(r);
	popc_lib_observer_free(obs);
	popc_lib_sim_free(sim);
	popc_lib_port_free(port);
	popc_lib_scene_free(s);
	/* the two files are the same bytes: header and rows */
	char cmd[2200];
	snprintf(cmd, sizeof cmd, "cmp -s '%s' '%s'", log_path, mine_path);
	snprintf(what, sizeof what, "%s: the API's log writer wrote popc run's file, byte for byte",
		 variant);
	check(system(cmd) == 0, what);
}

/* Every field the same bits (the padding after flags is no field). */
static int same_tick(const popc_lib_tick *a, const popc_lib_tick *b)
{
#define SAME(f) (memcmp(&a->f, &b->f, sizeof a->f) == 0)
	return SAME(t_s) && SAME(x_m) && SAME(count) && SAME(v_mps) && SAME(f_e_N) && SAME(f_pc_N) &&
	       SAME(f_c_N) && SAME(W_J) && SAME(E_ref_J) && SAME(flags);
#undef SAME
}

/* popc_lib_sim_tick (API 1.3) gives, tick by tick, the bits of
 * popc_lib_port_step and popc_lib_sim_exchange called one after the other:
 * two loops of the same scene side by side, every field compared. */
static void test_sim_tick(const char *scene_path, const char *variant)
{
	popc_lib_scene *s;
	popc_lib_error err;
	popc_lib_scene_create(&s, NULL);
	int st = popc_lib_scene_load(s, scene_path, &err);
	if (!st)
		st = popc_lib_scene_set(s, "controller.variant", variant, &err);
	if (!st)
		st = popc_lib_scene_set(s, "run.duration", "2", &err);
	popc_lib_port *p1 = NULL, *p2 = NULL;
	popc_lib_sim *s1 = NULL, *s2 = NULL;
	popc_lib_sample m1, m2;
	if (!st)
		st = popc_lib_port_create_impedance(s, 0.0, &p1, &err);
	if (!st)
		st = popc_lib_port_create_impedance(s, 0.0, &p2, &err);
	if (!st)
		st = popc_lib_sim_create(s, &s1, &m1, &err);
	if (!st)
		st = popc_lib_sim_create(s, &s2, &m2, &err);
	if (st) {
		printf("not ok - sim_tick %s: %s\n", variant, err.msg);
		failures++;
		return;
	}
	long long ticks = popc_lib_scene_tick_count(s), k = 0, differ = -1;
	for (; k < ticks; k++) {
		popc_lib_tick t1, t2;
		popc_lib_port_step(p1, m1.count, &t1);
		int st1 = 0, st2 = 0;
		if (k + 1 < ticks) {
			st1 = popc_lib_sim_exchange(s1, t1.f_c_N, &m1, NULL);
			st2 = popc_lib_sim_tick(p2, s2, &m2, &t2, NULL);
		} else {
			popc_lib_port_step(p2, m2.count, &t2);
		}
		if ((st1 != st2 || !same_tick(&t1, &t2) || memcmp(&m1, &m2, sizeof m1)) && differ < 0)
			differ = k;
		if (st1 || st2)
			break;
	}
	char what[256];
	snprintf(what, sizeof what, "%s: popc_lib_sim_tick gives the bits of port_step + sim_exchange "
		 "(%lld ticks, first difference: %lld)", variant, k, differ);
	check(k == ticks && differ < 0, what);
	popc_lib_sim_free(s1);
	popc_lib_sim_free(s2);
	popc_lib_port_free(p1);
	popc_lib_port_free(p2);
	popc_lib_scene_free(s);
}

/* popc_lib_sim_create_options (API 1.3): POPC_LIB_SIM_NO_PORT_ENERGY gives
 * the default device's counts and true positions bit for bit, E_port 0;
 * unknown option bits are refused, naming the one allowed. */
static void test_sim_options(const char *scene_path)
{
	popc_lib_scene *s;
	popc_lib_error err = {{0}};
	popc_lib_scene_create(&s, NULL);
	int st = popc_lib_scene_load(s, scene_path, &err);
	if (!st)
		st = popc_lib_scene_set(s, "run.duration", "2", &err);
	popc_lib_port *p = NULL;
	popc_lib_sim *full = NULL, *bare = NULL, *none = NULL;
	popc_lib_sample m1, m2;
	if (!st)
		st = popc_lib_port_create_impedance(s, 0.0, &p, &err);
	if (!st)
		st = popc_lib_sim_create_options(s, 0, &full, &m1, &err);
	if (!st)
		st = popc_lib_sim_create_options(s, POPC_LIB_SIM_NO_PORT_ENERGY, &bare, &m2, &err);
	if (st) {
		printf("not ok - sim options: %s\n", err.msg);
		failures++;
		return;
	}
	long long ticks = popc_lib_scene_tick_count(s), k = 0, differ = -1;
	int E_moved = 0;
	for (; k + 1 < ticks; k++) {
		popc_lib_tick t;
		if (popc_lib_sim_tick(p, full, &m1, &t, NULL) ||
		    popc_lib_sim_exchange(bare, t.f_c_N, &m2, NULL))
			break;
		E_moved |= m1.E_port_J != 0.0;
		if ((m1.count != m2.count || memcmp(&m1.x_true_m, &m2.x_true_m, sizeof(double)) ||
		     m2.E_port_J != 0.0) && differ < 0)
			differ = k;
	}
	char what[700];
	snprintf(what, sizeof what, "sim options: NO_PORT_ENERGY gives the counts and x_true, E_port 0 "
		 "(%lld exchanges, first difference: %lld; E_port moved without it: %d)", k, differ,
		 E_moved);
	check(k + 1 == ticks && differ < 0 && E_moved, what);
	st = popc_lib_sim_create_options(s, 2, &none, &m1, &err);
	snprintf(what, sizeof what, "sim options: bit 2 refused, the allowed named (%s)",
		 st ? err.msg : "accepted");
	check(st == POPC_LIB_ERR_INVALID && none == NULL &&
	      strstr(err.msg, "POPC_LIB_SIM_NO_PORT_ENERGY") != NULL, what);
	popc_lib_sim_free(full);
	popc_lib_sim_free(bare);
	popc_lib_port_free(p);
	popc_lib_scene_free(s);
}

/* The scene of a log (popc_lib_scene_from_log, API 1.3): a run of a scene
 * far from the defaults, its log's scene made over the defaults and run
 * again, gives the same file byte for byte; a recorded log and a header key
 * out of range are refused, naming the file, the line and the key, the scene
 * left as it was. */
static const struct bad_log {
	const char *name, *text, *says;
} bad_logs[] = {
	{"recorded.csv", "t,x,f_c\n0,0,0\n", "not a popc log"},
	{"rate.csv", "# format = popc-log 1\n# source = sim\n# run.rate = 1e9\nt,x\n0,0\n",
	 "rate.csv:3: header: run.rate"},
	{"key.csv", "# format = popc-log 1\n# source = sim\n# controller.nosuch = 1\nt,x\n0,0\n",
	 "key.csv:3: header: unknown key controller.nosuch"},
};

static void test_scene_from_log(const char *scene_path, const char *dir)
{
	static const char *const sets[][2] = {
		{"controller.variant", "windowed-po"}, {"run.rate", "2000"}, {"run.duration", "0.5"},
		{"environment.stiffness", "3000"},     {"encoder.resolution", "2e-5"},
	};
	popc_lib_scene *s, *back;
	popc_lib_error err = {{0}};
	popc_lib_scene_create(&s, NULL);
	popc_lib_scene_create(&back, NULL);
	int st = popc_lib_scene_load(s, scene_path, &err);
	for (size_t i = 0; !st && i < sizeof sets / sizeof sets[0]; i++)
		st = popc_lib_scene_set(s, sets[i][0], sets[i][1], &err);
	char first[1024], second[1024];
	snprintf(first, sizeof first, "%s/from-log-1.csv", dir);
	snprintf(second, sizeof second, "%s/from-log-2.csv", dir);
	if (!st)
		st = popc_lib_run(s, first, &err);
	popc_lib_log_reader *r = NULL;
	if (!st)
		st = popc_lib_log_reader_open(&r, first, &err);
	if (!st)
		st = popc_lib_scene_from_log(back, r, &err);
	if (!st)
		st = popc_lib_run(back, second, &err);
	char what[2400];
	snprintf(what, sizeof what, "scene from log: made and run again (%s)", st ? err.msg : "ok");
	check(st == 0, what);
	check(popc_lib_scene_period_s(back) == 1.0 / 2000.0 &&
	      popc_lib_scene_tick_count(back) == popc_lib_scene_tick_count(s),
	      "  its run.rate and run.duration are the log's");
	snprintf(what, sizeof what, "cmp -s '%s' '%s'", first, second);
	check(st == 0 && system(what) == 0, "  the log of the log's scene is the log, byte for byte");
	popc_lib_log_reader_close(r);
	for (size_t i = 0; i < sizeof bad_logs / sizeof bad_logs[0]; i++) {
		const struct bad_log *b = &bad_logs[i];
		char path[1100];
		snprintf(path, sizeof path, "%s/%s", dir, b->name);
		FILE *f = fopen(path, "w");
		if (f) {
			fputs(b->text, f);
			fclose(f);
		}
		double T0 = popc_lib_scene_period_s(back);
		r = NULL;
		memset(&err, 0, sizeof err);
		st = popc_lib_log_reader_open(&r, path, &err);
		if (!st)
			st = popc_lib_scene_from_log(back, r, &err);
		snprintf(what, sizeof what, "scene from log: %s refused, says '%s', scene unchanged (%s)",
			 b->name, b->says, err.msg);
		check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, b->says) != NULL &&
		      popc_lib_scene_period_s(back) == T0, what);
		popc_lib_log_reader_close(r);
	}
	popc_lib_scene_free(back);
	popc_lib_scene_free(s);
}

/* A bare scene name is looked up in the data path the caller passes
 * (popc_lib_scene_set_data_path), never in POPC_DATA_PATH: the library reads
 * no environment (docs/LIBRARY.md). dir/data/scenes/mine.ini is the scene. */
static void test_data_path(const char *scene_path, const char *dir)
{
	char data[1024], cmd[3000];
	snprintf(data, sizeof data, "%s/data", dir);
	snprintf(cmd, sizeof cmd, "mkdir -p '%s/scenes' && cp '%s' '%s/scenes/mine.ini'", data,
		 scene_path, data);
	check(system(cmd) == 0, "data path: a scene 'mine' in a data directory");
	setenv("POPC_DATA_PATH", data, 1);
	popc_lib_scene *s;
	popc_lib_error err = {{0}};
	popc_lib_scene_create(&s, NULL);
	int st = popc_lib_scene_load(s, "mine", &err);
	char what[1200];
	snprintf(what, sizeof what, "data path: POPC_DATA_PATH alone does not find 'mine': status %d (%s)",
		 st, err.msg);
	check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "mine") != NULL, what);
	unsetenv("POPC_DATA_PATH");
	st = popc_lib_scene_set_data_path(s, data, &err);
	if (!st)
		st = popc_lib_scene_load(s, "mine", &err);
	snprintf(what, sizeof what, "data path: popc_lib_scene_set_data_path finds 'mine': status %d (%s)",
		 st, st ? err.msg : "");
	check(st == 0, what);
	/* an empty entry is the installed directory, after the caller's */
	snprintf(cmd, sizeof cmd, "/nonexistent:%s:", data);
	st = popc_lib_scene_set_data_path(s, cmd, &err);
	if (!st)
		st = popc_lib_scene_load(s, "mine", &err);
	check(st == 0, "data path: DIR:DIR: searches each in turn");
	char long_path[1100];
	memset(long_path, 'a', 1024);
	long_path[1024] = '\0';
	st = popc_lib_scene_set_data_path(s, long_path, &err);
	snprintf(what, sizeof what, "data path: 1024 characters refused, the limit named (%s)",
		 st ? err.msg : "accepted");
	check(st == POPC_LIB_ERR_INVALID && strstr(err.msg, "1023") != NULL, what);
	/* NULL: back to the installed directory alone, where 'mine' is not */
	st = popc_lib_scene_set_data_path(s, NULL, &err);
	if (!st)
		st = popc_lib_scene_load(s, "mine", &err);
	check(st == POPC_LIB_ERR_INVALID, "data path: NULL is the installed directory alone");
	popc_lib_scene_free(s);
}

int main(int argc, char **argv)
{
	if (argc < 3) {
		fprintf(stderr, "usage: test_lib_api SCENE SCRATCH_DIR\n");
		return 2;
	}
	test_versions();
	test_bad_input(argv[2]);
	test_data_path(argv[1], argv[2]);
	static const char *const variants[] = {"none", "ref-energy", "filtered-velocity", "improved",
					       "pc-off-reversals", "energy-bounding", "windowed-po"};
	for (size_t i = 0; i < sizeof variants / sizeof variants[0]; i++)
		test_loop_equals_run(argv[1], variants[i], argv[2]);
	for (size_t i = 0; i < sizeof variants / sizeof variants[0]; i++)
		test_sim_tick(argv[1], variants[i]);
	test_sim_options(argv[1]);
	test_scene_from_log(argv[1], argv[2]);
	popc_lib_scene_free(NULL);
	popc_lib_port_free(NULL);
	popc_lib_observer_free(NULL);
	popc_lib_sim_free(NULL);
	popc_lib_log_reader_close(NULL);
	check(popc_lib_log_writer_close(NULL, NULL, NULL) == 0, "every free takes NULL");
	printf("# %d failed\n", failures);
	return failures ? 1 : 0;
}
