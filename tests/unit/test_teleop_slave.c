/* The teleoperation loop with the program's axis as the slave (issue 26,
 * run_teleop.c; docs/TELEOPERATION.md, "A Modbus slave"), as with
 * axis.kind = modbus, without a drive: an admittance-type axis that wraps
 * the simulated slave and can fail one exchange or its stop. The runner then
 * simulates the master. Table-driven: with no fault the master's ticks are
 * the simulated run's bit for bit; a failed exchange (each status a Modbus
 * axis returns) stops the run with that status, every tick before it, its
 * reason, the slave stopped once and no exchange after the failure; a stop
 * that fails after a completed run is the run's error. Counts, never times. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/axes/sim_axis.h"
#include "popc/log/log_columns.h"
#include "popc/run/run.h"

#define TICKS_MAX 400

/* the wrapped slave and what the runner did with it */
typedef struct fake_slave {
	popc_axis *inner;
	long long fail_at;  /* the exchange that fails (1: the one bringing tick 1), 0: none */
	int fail_st;        /* its status */
	int stop_st;        /* what stop() returns */
	long long exchanges, after_fail, starts, stops;
	int failed;
} fake_slave;

static int fake_start(popc_axis *a, popc_error *err)
{
	fake_slave *f = a->priv;
	f->starts++;
	return f->inner->ops->start(f->inner, err);
}

static int fake_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	fake_slave *f = a->priv;
	return f->inner->ops->sample(f->inner, out, err);
}

static int fake_exchange(popc_axis *a, double v_c_mps, popc_axis_sample *next, popc_error *err)
{
	fake_slave *f = a->priv;
	if (f->failed)
		f->after_fail++;
	if (++f->exchanges == f->fail_at) {
		f->failed = 1;
		return popc_error_set(err, f->fail_st, "injected at exchange %lld", f->exchanges);
	}
	return f->inner->ops->exchange(f->inner, v_c_mps, next, err);
}

static int fake_stop(popc_axis *a, popc_error *err)
{
	fake_slave *f = a->priv;
	f->stops++;
	return f->stop_st ? popc_error_set(err, f->stop_st, "disable not confirmed") : 0;
}

static void fake_destroy(popc_axis *a)
{
	(void)a; /* the test owns it */
}

/* admittance-type, as the Modbus axis with a servo map: the runner takes it for the slave */
static const popc_axis_ops fake_ops = {
	.name = "modbus",
	.log_columns = POPC_LOG_COL_TIMING | POPC_LOG_COL_ADMITTANCE,
	.start = fake_start,
	.sample = fake_sample,
	.exchange = fake_exchange,
	.stop = fake_stop,
	.destroy = fake_destroy,
};

static void load_wall(popc_scene *s)
{
	char path[1024];
	popc_error err;
	snprintf(path, sizeof path, "%s/data/scenes/teleop-wall.ini", getenv("POPC_SOURCE_ROOT"));
	popc_scene_defaults(s);
	assert_int_equal(popc_scene_load(s, path, &err), 0);
	s->duration_s = 0.3;
	assert_int_equal(popc_scene_validate(s, &err), 0);
}

typedef struct ticks {
	long long n;
	popc_tick t[TICKS_MAX + 1];
} ticks;

static void keep_tick(void *user, const popc_tick *t)
{
	ticks *k = user;
	if (k->n <= TICKS_MAX)
		k->t[k->n++] = *t;
}

static void assert_same_ticks(const ticks *a, const ticks *b, long long n)
{
	assert_true(a->n >= n && b->n >= n);
	for (long long i = 0; i < n; i++) {
		const popc_tick *p = &a->t[i], *q = &b->t[i];
		/* bitwise: the doubles' bytes */
		assert_memory_equal(&p->t_s, &q->t_s, sizeof p->t_s);
		assert_int_equal(p->count, q->count);
		assert_memory_equal(&p->x_m, &q->x_m, sizeof p->x_m);
		assert_memory_equal(&p->v_mps, &q->v_mps, sizeof p->v_mps);
		assert_memory_equal(&p->f_e_N, &q->f_e_N, sizeof p->f_e_N);
		assert_memory_equal(&p->f_pc_N, &q->f_pc_N, sizeof p->f_pc_N);
		assert_memory_equal(&p->f_c_N, &q->f_c_N, sizeof p->f_c_N);
		assert_memory_equal(&p->W_J, &q->W_J, sizeof p->W_J);
		assert_int_equal(p->flags, q->flags);
	}
}

typedef struct fault_case {
	const char *name;
	long long fail_at;
	int fail_st;
	int stop_st;
	int want_st;
	const char *want_reason; /* the stop reason's beginning */
} fault_case;

static const fault_case cases[] = {
	{"completed", 0, 0, 0, 0, "completed"},
	{"drive fault", 120, POPC_ERR_SAFETY, 0, POPC_ERR_SAFETY, "safety stop: injected"},
	{"link lost", 120, POPC_ERR_COMM, 0, POPC_ERR_COMM, "communication lost: injected"},
	{"signal mid-retry", 120, POPC_ERR_INTERRUPTED, 0, POPC_ERR_INTERRUPTED, "signal: injected"},
	{"map rejected", 1, POPC_ERR_INVALID, 0, POPC_ERR_INVALID, "axis error: injected"},
	{"stop unconfirmed", 0, 0, POPC_ERR_COMM, POPC_ERR_COMM,
	 "safe stop incomplete: disable not confirmed"},
	{"fault, stop unconfirmed", 120, POPC_ERR_SAFETY, POPC_ERR_COMM, POPC_ERR_SAFETY,
	 "safety stop: injected at exchange 120; safe stop incomplete"},
};

static void test_fault_table(void **state)
{
	(void)state;
	popc_scene s;
	load_wall(&s);
	const long long n_ticks = popc_scene_ticks(&s) + 1;
	/* the simulated run: the master's ticks */
	static ticks sim, got;
	popc_axis *master;
	popc_error err;
	popc_run_summary sum;
	assert_int_equal(popc_axis_create(&master, &s, NULL, &err), 0);
	sim.n = 0;
	popc_run_options ro = {.on_tick = keep_tick, .tick_user = &sim};
	assert_int_equal(popc_run(&s, master, &ro, &sum, &err), 0);
	popc_axis_destroy(&master);
	assert_int_equal(sim.n, n_ticks);

	/* where the simulated slave starts: the master's tick-0 true position */
	popc_axis_sample sm;
	assert_int_equal(popc_sim_axis_create(&master, &s, &err), 0);
	assert_int_equal(master->ops->start(master, &err), 0);
	assert_int_equal(master->ops->sample(master, &sm, &err), 0);
	popc_axis_destroy(&master);

	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const fault_case *c = &cases[i];
		fake_slave f = {.fail_at = c->fail_at, .fail_st = c->fail_st, .stop_st = c->stop_st};
		assert_int_equal(popc_sim_slave_axis_create(&f.inner, &s, sm.x_true_m, &err), 0);
		popc_axis slave = {.ops = &fake_ops, .priv = &f};
		/* the log's columns: the master's, the network's, the drive's timing;
		 * no slave true position */
		unsigned cols = popc_run_log_columns(&s, &slave);
		assert_int_equal(cols, POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TELEOP | POPC_LOG_COL_TIMING);
		got.n = 0;
		popc_run_options o = {.on_tick = keep_tick, .tick_user = &got};
		int st = popc_run(&s, &slave, &o, &sum, &err);
		popc_axis_destroy(&f.inner);
		printf("%-24s status %d, %lld ticks, %s\n", c->name, st, sum.ticks, sum.stop_reason);
		assert_int_equal(st, c->want_st);
		assert_int_equal(sum.status, c->want_st);
		assert_true(strncmp(sum.stop_reason, c->want_reason, strlen(c->want_reason)) == 0);
		/* exchange k brings tick k: a failure at k leaves ticks 0 .. k-1 */
		long long want_ticks = c->fail_at ? c->fail_at : n_ticks;
		assert_int_equal(sum.ticks, want_ticks);
		assert_int_equal(got.n, want_ticks);
		assert_same_ticks(&sim, &got, want_ticks);
		assert_int_equal(f.starts, 1);
		assert_int_equal(f.stops, 1);
		assert_int_equal(f.after_fail, 0);
	}
}

/* the simulated slave's log keeps its columns (xs_true among them) */
static void test_sim_columns(void **state)
{
	(void)state;
	popc_scene s;
	load_wall(&s);
	popc_axis *master;
	popc_error err;
	assert_int_equal(popc_axis_create(&master, &s, NULL, &err), 0);
	assert_int_equal(popc_run_log_columns(&s, master),
			 POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TELEOP | POPC_LOG_COL_SLAVE_TRUE);
	popc_axis_destroy(&master);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_fault_table),
		cmocka_unit_test(test_sim_columns),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
