/* The successors of Table I, each against its defining property
 * (README "Controller variants"), and the loop delay (run.delay_ticks):
 * - pc-off-reversals: the PC is off exactly while reversal_count reversals
 *   fall within reversal_window ticks, and on as ref-energy otherwise;
 * - energy-bounding: the closed loop on the paper scene stays bounded for any
 *   wall stiffness up to 1e6 N/m (variant none diverges there), every force
 *   step is within 2 b |dx| / T, and the rendered stiffness stays near 2 b / T;
 * - windowed-po: the PO forgets energy older than its window; the velocity
 *   floor and the damping bound hold;
 * - delay: the axis receives the command of tick k at exchange k + d. */
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
#include "popc/core/controller.h"
#include "test_new_controller.h"
#include "popc/core/encoder.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"

/* the unit scene of test_controller.c: 1000 N/m wall at 0, delta 1e-5 m, T 1 ms */
static popc_controller_config base_config(popc_variant v)
{
	popc_controller_config cfg = {
		.variant = v, .pc_bound_N = 5.0, .resolution_m = 1e-5, .period_s = 1e-3,
		.foaw_window = 16, .foaw_noise_m = 1e-5, .reversal_count = 3,
		.reversal_window_ticks = 10, .damping_Nspm = 0.5, .po_window_ticks = 4,
		.po_velocity_floor_mps = 0.0, .po_damping_max_Nspm = 1e9,
		.env = {.kind = POPC_ENV_WALL, .stiffness_Npm = 1000.0, .position_m = 0.0},
	};
	return cfg;
}

static popc_tick step(popc_controller *c, long long count)
{
	popc_tick t;
	popc_controller_step(c, count, (double)count * 1e-5, &t);
	return t;
}

/* pc-off-reversals against ref-energy's PC on its own W and E_ref: the same
 * force except while 3 reversals lie within 10 ticks, where it is 0 and
 * flagged when the PC would have acted. Counts: in to 5, then 1-count
 * reversals (ticks 6, 7, 8: the third turns the PC off), then a steady
 * climb: off until tick 6 leaves the window (tick 16), on again after. */
static void test_pc_off_reversals(void **state)
{
	(void)state;
	const long long counts[] = {0, 1, 2, 3, 4, 5, 4, 5, 4, 5, 6, 7, 8, 9, 10,
				    11, 12, 13, 14, 15, 16, 17, 18, 19, 20};
	const int n = (int)(sizeof counts / sizeof counts[0]);
	popc_controller_config cfg = base_config(POPC_VARIANT_PC_OFF_REVERSALS);
	popc_controller *c = new_controller(&cfg);
	int off_ticks = 0, on_acting = 0;
	for (int k = 0; k < n; k++) {
		popc_tick t = step(c, counts[k]);
		double dx = k ? (double)counts[k] * 1e-5 - (double)counts[k - 1] * 1e-5 : 0.0;
		double pc = t.W_J < t.E_ref_J && dx != 0.0 ? (t.E_ref_J - t.W_J) / dx : 0.0;
		if (pc > 5.0)
			pc = 5.0;
		/* reversals at ticks 6, 7, 8, 9: the 3rd of them (tick 8) turns the
		 * PC off until fewer than 3 lie in (k - 10, k]: ticks 8 .. 16 */
		int off = k >= 8 && k <= 16;
		if (off) {
			assert_true(t.f_pc_N == 0.0);
			assert_int_equal(!!(t.flags & POPC_FLAG_PC_OFF), pc != 0.0);
			off_ticks += pc != 0.0;
		} else {
			if (t.f_pc_N != pc)
				fail_msg("tick %d: f_pc %.17g, ref-energy's rule %.17g", k, t.f_pc_N, pc);
			assert_true(!(t.flags & POPC_FLAG_PC_OFF));
			on_acting += pc != 0.0 && k > 16;
		}
	}
	/* the rule really turned an acting PC off, and it acts again after */
	assert_true(off_ticks > 0);
	assert_true(on_acting > 0);
	popc_controller_free(c);
}

/* windowed-po against its definition: over the counts, f_pc(k) = -D(k) / dx(k)
 * where D(k), the sum of the W - E_ref increments of the last `window`
 * ticks, is negative, and 0 where it is positive or no count moved (the
 * unit scene: floor 0, no damping bound). Returns the ticks the PC acted. */
static int windowed_against_definition(int window, const long long *counts, int n)
{
	popc_controller_config cfg = base_config(POPC_VARIANT_WINDOWED_PO);
	cfg.po_window_ticks = window;
	popc_controller *c = new_controller(&cfg);
	double *inc = malloc((size_t)n * sizeof *inc);
	assert_non_null(inc);
	double f_c_prev = 0.0, f_e_prev = 0.0, x_prev = 0.0;
	int acted = 0;
	for (int k = 0; k < n; k++) {
		double x = (double)counts[k] * 1e-5;
		double f_e = x > 0.0 ? 1000.0 * x : 0.0;
		popc_tick t = step(c, counts[k]);
		/* the windowed sum recomputed from its definition */
		inc[k] = k ? f_c_prev * (x - x_prev) - (f_e + f_e_prev) * (x - x_prev) / 2.0 : 0.0;
		double D = 0.0;
		for (int j = k; j >= 0 && j > k - window; j--)
			D += inc[j];
		double dx = x - x_prev;
		if (k && D < -1e-18 && dx != 0.0) {
			double want = -D / dx;
			if (fabs(t.f_pc_N - want) > 1e-9 * fabs(want))
				fail_msg("window %d, tick %d: f_pc %.17g, -D/dx %.17g", window, k,
					 t.f_pc_N, want);
			acted++;
		} else if (D > 1e-18 || dx == 0.0) {
			if (t.f_pc_N != 0.0)
				fail_msg("window %d, tick %d: f_pc %.17g where D = %.17g, dx = %g",
					 window, k, t.f_pc_N, D, dx);
		}
		f_c_prev = t.f_c_N;
		f_e_prev = f_e;
		x_prev = x;
	}
	free(inc);
	popc_controller_free(c);
	return acted;
}

/* windowed-po: W - E_ref increments over the last 4 ticks only. A long
 * passive phase (pressing in with a held larger force: W grows above E_ref)
 * does not hide a later active step from the windowed PO once it is older
 * than the window, where ref-energy's full PO still has a surplus. */
static void test_windowed_po_forgets(void **state)
{
	(void)state;
	/* in to 20 counts, then out one count per tick: the sampled wall is
	 * active while it recedes (f_c(k-1) lags f_e) */
	long long counts[40];
	for (int k = 0; k < 40; k++)
		counts[k] = k <= 20 ? k : 40 - k;
	assert_true(windowed_against_definition(4, counts, 40) > 0);
}

/* The window is the configuration's, however long: popc_controller_create
 * sizes the ring from it (the scene's po_window stops at
 * POPC_PO_MAX_WINDOW; the controller does not). A window of 5000 ticks over
 * 6000 ticks of pressing in and out of the wall keeps every increment of
 * the last 5000 ticks: a ring cut at 4096 (the controller's fixed array
 * before) forgets the oldest and gives another D from tick 4096 on. */
static void test_windowed_po_long_window(void **state)
{
	(void)state;
	enum { N = 6000 };
	static long long counts[N];
	for (int k = 0; k < N; k++) {
		/* a triangle 0 .. 30 counts, period 60 ticks, in the wall */
		int ph = k % 60;
		counts[k] = ph <= 30 ? ph : 60 - ph;
	}
	assert_true(POPC_PO_MAX_WINDOW < 5000);
	assert_true(windowed_against_definition(5000, counts, N) > 0);
	/* and one slot only */
	assert_true(windowed_against_definition(1, counts, N) > 0);
}

/* windowed-po: no PC below the velocity floor; |f_pc| <= damping bound |v|. */
static void test_windowed_po_floor_and_damping(void **state)
{
	(void)state;
	long long counts[40];
	for (int k = 0; k < 40; k++)
		counts[k] = k <= 20 ? 3 * k : 120 - 3 * k; /* 3 counts per tick: 0.03 m/s */
	/* floor above the speed: the PC never acts */
	popc_controller_config cfg = base_config(POPC_VARIANT_WINDOWED_PO);
	cfg.po_velocity_floor_mps = 0.031;
	popc_controller *c = new_controller(&cfg);
	for (int k = 0; k < 40; k++)
		assert_true(step(c, counts[k]).f_pc_N == 0.0);
	/* floor below, damping bound 0.5 N s/m: |f_pc| <= 0.5 * 0.03 N, and it binds */
	cfg.po_velocity_floor_mps = 0.029;
	cfg.po_damping_max_Nspm = 0.5;
	popc_controller_free(c);
	c = new_controller(&cfg);
	int bound = 0;
	for (int k = 0; k < 40; k++) {
		popc_tick t = step(c, counts[k]);
		assert_true(fabs(t.f_pc_N) <= 0.5 * 0.03 * (1 + 1e-12));
		bound += (t.flags & POPC_FLAG_BOUND) != 0;
	}
	assert_true(bound > 0);
	popc_controller_free(c);
}

/* A run of the paper scene with one variant and wall stiffness. */
typedef struct bound_check {
	popc_controller_config cfg;
	int started;
	double f_c_prev_N, x_prev_m, max_step_excess_N, W_min_J, x_max_m; /* deepest x */
} bound_check;

static void check_tick(void *user, const popc_tick *t)
{
	bound_check *b = user;
	if (b->started) {
		/* a step beyond the hold's bound K_b |dx|, K_b = (1 - eb_margin)
		 * 2 b / T, only where the environment's force saturated f_c (to 0
		 * or to f_e); 1e-12 N for the rounding of f_c = f_e + (f - f_e) */
		double dx = t->x_m - b->x_prev_m;
		double step_max = (1.0 - b->cfg.eb_margin) * 2.0 * b->cfg.damping_Nspm * fabs(dx) /
				  b->cfg.period_s;
		double excess = fabs(t->f_c_N - b->f_c_prev_N) - step_max;
		int saturated = t->f_c_N == 0.0 || fabs(t->f_c_N - t->f_e_N) <= 1e-12;
		if (!saturated && excess > b->max_step_excess_N)
			b->max_step_excess_N = excess;
		/* never beyond the environment: f_c in [0, f_e] on a wall */
		if (t->f_c_N < -1e-12 || t->f_c_N > t->f_e_N + 1e-12)
			b->max_step_excess_N = (double)INFINITY;
	}
	if (t->W_J < b->W_min_J)
		b->W_min_J = t->W_J;
	if (t->x_m > b->x_max_m)
		b->x_max_m = t->x_m;
	b->started = 1;
	b->f_c_prev_N = t->f_c_N;
	b->x_prev_m = t->x_m;
}

static int paper_run(popc_variant v, double K, int delay, popc_run_summary *sum, bound_check *b)
{
	char path[1024];
	popc_error err;
	snprintf(path, sizeof path, "%s/data/scenes/paper.ini", getenv("POPC_SOURCE_ROOT"));
	popc_scene s;
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, path, &err), 0);
	s.variant = v;
	s.env_stiffness_Npm = K;
	s.delay_ticks = delay;
	memset(b, 0, sizeof *b);
	popc_controller_config_from_scene(&b->cfg, &s);
	b->W_min_J = (double)INFINITY;
	popc_axis *axis;
	assert_int_equal(popc_sim_axis_create(&axis, &s, &err), 0);
	popc_run_options ro = {.on_tick = check_tick, .tick_user = b};
	int st = popc_run(&s, axis, &ro, sum, &err);
	popc_axis_destroy(&axis);
	return st;
}

/* Energy bounding: the same bounded loop for every stiffness (measured at
 * K = 1e3 .. 1e6 over 5 s: the run completes, x <= 3.31 mm where the ramp
 * pulls to 30 mm, W >= -3.9e-4 J, rendered 502.6 .. 505 N/m = K_b), where
 * variant none diverges at 1e5. K_b = (1 - eb_margin) 2 b / T = 500 N/m with
 * the default margin 0.5, strictly inside the sampled wall's passivity line
 * 2 b / T = 1000 N/m, where (eb_margin = 0, before issue 23) the contact kept
 * a bounded limit cycle (docs/ANALYSIS.md, "energy-bounding's margin"). */
static void test_energy_bounding_any_stiffness(void **state)
{
	(void)state;
	const double K[] = {1e3, 1e4, 1e5, 1e6};
	for (size_t i = 0; i < sizeof K / sizeof K[0]; i++) {
		popc_run_summary sum;
		bound_check b;
		int st = paper_run(POPC_VARIANT_ENERGY_BOUNDING, K[i], 0, &sum, &b);
		fprintf(stderr, "K = %g: status %d, max x %g m, min W %g J, rendered %g N/m\n", K[i], st,
			b.x_max_m, b.W_min_J, popc_metrics_rendered_stiffness(&sum.metrics));
		if (st != 0 || b.x_max_m > 0.005 || b.W_min_J < -0.02 || b.max_step_excess_N > 1e-9)
			fail_msg("K = %g: status %d, max x %g m, min W %g J, force step excess %g N", K[i],
				 st, b.x_max_m, b.W_min_J, b.max_step_excess_N);
		double kr = popc_metrics_rendered_stiffness(&sum.metrics);
		/* the ZOH bound caps the slope at K_b = (1 - 0.5) 2 b / T = 500 N/m */
		if (!(kr > 450.0 && kr < 500.0 * 1.05))
			fail_msg("K = %g: rendered stiffness %g N/m", K[i], kr);
	}
	popc_run_summary sum;
	bound_check b;
	assert_int_not_equal(paper_run(POPC_VARIANT_NONE, 1e5, 0, &sum, &b), 0);
}

/* The rendered stiffness is K itself when nothing modifies f_e (variant
 * none, a wall without damping, stable at K = 500 N/m < 2 b / T). */
static void test_rendered_stiffness_of_none(void **state)
{
	(void)state;
	popc_run_summary sum;
	bound_check b;
	assert_int_equal(paper_run(POPC_VARIANT_NONE, 500.0, 0, &sum, &b), 0);
	assert_true(fabs(popc_metrics_rendered_stiffness(&sum.metrics) - 500.0) < 1e-9);
}

/* Delay: the axis receives f_c(k) with exchange k + d (0 N before), checked
 * bitwise against a loop that steps the same simulated axis by hand. */
enum { DELAY_TICKS = 2001 };
static long long counts_run[DELAY_TICKS];
static int n_run;

static void record_count(void *user, const popc_tick *t)
{
	(void)user;
	if (n_run < DELAY_TICKS)
		counts_run[n_run++] = t->count;
}

static void check_delay(int d)
{
	char path[1024];
	popc_error err;
	snprintf(path, sizeof path, "%s/data/scenes/paper.ini", getenv("POPC_SOURCE_ROOT"));
	popc_scene s;
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, path, &err), 0);
	s.variant = POPC_VARIANT_IMPROVED;
	s.duration_s = 2.0;
	s.delay_ticks = d;
	popc_axis *axis;
	assert_int_equal(popc_sim_axis_create(&axis, &s, &err), 0);
	popc_run_summary sum;
	n_run = 0;
	popc_run_options ro = {.on_tick = record_count};
	assert_int_equal(popc_run(&s, axis, &ro, &sum, &err), 0);
	popc_axis_destroy(&axis);
	assert_int_equal(n_run, DELAY_TICKS);

	/* by hand: the controller's commands through a queue of d ticks */
	popc_controller_config cfg;
	popc_controller_config_from_scene(&cfg, &s);
	popc_controller *c = new_controller(&cfg);
	assert_int_equal(popc_sim_axis_create(&axis, &s, &err), 0);
	cfg.force_limit_N = axis->force_limit_N;
	popc_controller_free(c);
	c = new_controller(&cfg);
	double queue[8] = {0};
	popc_axis_sample smp;
	assert_int_equal(axis->ops->start(axis, &err), 0);
	assert_int_equal(axis->ops->sample(axis, &smp, &err), 0);
	int differ = 0;
	for (int k = 0; k < DELAY_TICKS; k++) {
		popc_tick t;
		popc_controller_step(c, smp.count, popc_encoder_position(smp.count, s.enc_resolution_m), &t);
		if (smp.count != counts_run[k])
			fail_msg("d = %d, tick %d: count %lld by hand, %lld in the run", d, k, smp.count,
				 counts_run[k]);
		/* f_c(k) goes in at the back, the command of tick k - d comes out */
		double sent = t.f_c_N;
		if (d > 0) {
			sent = queue[0];
			memmove(queue, queue + 1, (size_t)(d - 1) * sizeof queue[0]);
			queue[d - 1] = t.f_c_N;
		}
		differ += sent != t.f_c_N;
		if (k + 1 < DELAY_TICKS)
			assert_int_equal(axis->ops->exchange(axis, sent, &smp, &err), 0);
	}
	axis->ops->stop(axis, &err);
	popc_axis_destroy(&axis);
	popc_controller_free(c);
	/* the delay changed what was sent (d > 0), or nothing (d = 0) */
	assert_int_equal(differ > 0, d > 0);
}

static void test_delay_zero(void **state)
{
	(void)state;
	check_delay(0);
}

static void test_delay_queue(void **state)
{
	(void)state;
	check_delay(1);
	check_delay(3);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_pc_off_reversals),
		cmocka_unit_test(test_windowed_po_forgets),
		cmocka_unit_test(test_windowed_po_long_window),
		cmocka_unit_test(test_windowed_po_floor_and_damping),
		cmocka_unit_test(test_energy_bounding_any_stiffness),
		cmocka_unit_test(test_rendered_stiffness_of_none),
		cmocka_unit_test(test_delay_zero),
		cmocka_unit_test(test_delay_queue),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
