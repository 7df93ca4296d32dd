/* PO/PC variants: one-step logic against hand-computed cases (seed Figs. 7
 * and 9, Table I), bound and NaN guards, FOAW. Scene: K_e = 1000 N/m wall at
 * 0, delta = 1e-5 m, T = 1 ms, so one count is f_e = 0.01 N. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "popc/controller.h"

#define E_TOL 1e-20   /* J: values are ~1e-7 J; doubles resolve ~1e-23 J there */
#define F_TOL 1e-13   /* N: forces ~1e-2 N */

static popc_controller make(popc_variant v, popc_ignore_mode mode, double bound)
{
	popc_controller_config cfg = {
		.variant = v, .pc_bound_N = bound, .ignore_mode = mode, .resolution_m = 1e-5,
		.period_s = 1e-3, .foaw_window = 16, .foaw_noise_m = 1e-5,
		.env = {.kind = POPC_ENV_WALL, .stiffness_Npm = 1000.0, .position_m = 0.0},
	};
	popc_controller c;
	popc_controller_init(&c, &cfg);
	return c;
}

static popc_tick step(popc_controller *c, long long count)
{
	popc_tick t;
	popc_controller_step(c, count, (double)count * 1e-5, &t);
	return t;
}

typedef struct {
	double W, E_ref, f_pc, f_c;
	unsigned flags;
} expect;

static void run_case(popc_variant v, popc_ignore_mode mode, const long long *counts,
		     const expect *ex, int n)
{
	popc_controller c = make(v, mode, 5.0);
	for (int k = 0; k < n; k++) {
		popc_tick t = step(&c, counts[k]);
		if (fabs(t.W_J - ex[k].W) > E_TOL || fabs(t.E_ref_J - ex[k].E_ref) > E_TOL ||
		    fabs(t.f_pc_N - ex[k].f_pc) > F_TOL || fabs(t.f_c_N - ex[k].f_c) > F_TOL ||
		    t.flags != ex[k].flags)
			fail_msg("variant %s k=%d: W %.17g E_ref %.17g f_pc %.17g f_c %.17g flags %u; "
				 "expected %.17g %.17g %.17g %.17g %u",
				 popc_variant_name(v), k, t.W_J, t.E_ref_J, t.f_pc_N, t.f_c_N, t.flags,
				 ex[k].W, ex[k].E_ref, ex[k].f_pc, ex[k].f_c, ex[k].flags);
	}
}

/* Fig. 7: up one count, up one more, back one count. Hand computation:
 * k1: E = (0.01+0) 1e-5/2 = 5e-8, W = 0; f_pc = 5e-8/1e-5 = 0.005, f_c = 0.015
 * k2: E = 5e-8 + 0.03e-5/2 = 2e-7, W = 0.015e-5 = 1.5e-7, f_pc = 0.005, f_c = 0.025
 * k3: E = 2e-7 - 1.5e-7 = 5e-8, W = 1.5e-7 - 0.025e-5 = -1e-7,
 *     f_pc = (5e-8 + 1e-7) / -1e-5 = -0.015, f_c = -0.005: the gap grew (Fig. 7). */
static const long long fig7_counts[] = {0, 1, 2, 1};

static void test_ref_energy_one_count_reversal(void **state)
{
	(void)state;
	const expect ex[] = {
		{0, 0, 0, 0, 0},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE},
		{1.5e-7, 2e-7, 0.005, 0.025, POPC_FLAG_ACTIVE},
		{-1e-7, 5e-8, -0.015, -0.005, POPC_FLAG_ACTIVE},
	};
	run_case(POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, fig7_counts, ex, 4);
}

/* Table I, literal: at the reversal W = W(k-1) - Prev_fc Prev_dx with
 * Prev_fc = f_e(2) = 0.02: W = 1.5e-7 - 2e-7 = -5e-8; f_pc = 1e-7 / -1e-5 = -0.01. */
static void test_ignore_literal_reversal(void **state)
{
	(void)state;
	const expect ex[] = {
		{0, 0, 0, 0, 0},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE},
		{1.5e-7, 2e-7, 0.005, 0.025, POPC_FLAG_ACTIVE},
		{-5e-8, 5e-8, -0.01, 0.0, POPC_FLAG_ACTIVE | POPC_FLAG_IGNORE},
	};
	run_case(POPC_VARIANT_IGNORE, POPC_IGNORE_LITERAL, fig7_counts, ex, 4);
	run_case(POPC_VARIANT_IMPROVED, POPC_IGNORE_LITERAL, fig7_counts, ex, 4);
}

/* Undo reading: Prev_fc = f_c(1) = 0.015 removes exactly step 2's increment:
 * W = 1.5e-7 - 1.5e-7 = 0, f_pc = 5e-8 / -1e-5 = -0.005. */
static void test_ignore_undo_reversal(void **state)
{
	(void)state;
	const expect ex[] = {
		{0, 0, 0, 0, 0},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE},
		{1.5e-7, 2e-7, 0.005, 0.025, POPC_FLAG_ACTIVE},
		{0, 5e-8, -0.005, 0.005, POPC_FLAG_ACTIVE | POPC_FLAG_IGNORE},
	};
	run_case(POPC_VARIANT_IGNORE, POPC_IGNORE_UNDO, fig7_counts, ex, 4);
}

/* Fig. 9: a count, then no displacement. ref-energy cannot act (dx = 0:
 * f_pc = 0, no division); hold and improved keep f_pc(k-1) (Table I). */
static const long long fig9_counts[] = {0, 1, 1, 1};

static void test_zero_displacement(void **state)
{
	(void)state;
	const expect ref[] = {
		{0, 0, 0, 0, 0},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE},
		{0, 5e-8, 0, 0.01, 0},
		{0, 5e-8, 0, 0.01, 0},
	};
	run_case(POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, fig9_counts, ref, 4);
	const expect held[] = {
		{0, 0, 0, 0, 0},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE | POPC_FLAG_HOLD},
		{0, 5e-8, 0.005, 0.015, POPC_FLAG_ACTIVE | POPC_FLAG_HOLD},
	};
	run_case(POPC_VARIANT_HOLD, POPC_IGNORE_LITERAL, fig9_counts, held, 4);
	run_case(POPC_VARIANT_IMPROVED, POPC_IGNORE_LITERAL, fig9_counts, held, 4);
}

/* po-pc uses the zero threshold: W = 0 is not below it, so nothing acts on
 * the way in; on the reversal W = -0.01e-5 < 0 gives f_pc = -W/dx = -0.01. */
static void test_po_pc_zero_threshold(void **state)
{
	(void)state;
	const expect ex[] = {
		{0, 0, 0, 0, 0},
		{0, 5e-8, 0, 0.01, 0},
		{1e-7, 2e-7, 0, 0.02, 0},
		{-1e-7, 5e-8, -0.01, 0.0, POPC_FLAG_ACTIVE},
	};
	run_case(POPC_VARIANT_PO_PC, POPC_IGNORE_LITERAL, fig7_counts, ex, 4);
	const expect none[] = {
		{0, 0, 0, 0, 0}, {0, 5e-8, 0, 0.01, 0}, {1e-7, 2e-7, 0, 0.02, 0}, {-1e-7, 5e-8, 0, 0.01, 0},
	};
	run_case(POPC_VARIANT_NONE, POPC_IGNORE_LITERAL, fig7_counts, none, 4);
}

/* The bound holds and is flagged; NaN positions never reach the command. */
static void test_bound_and_guards(void **state)
{
	(void)state;
	for (int v = 0; v < POPC_VARIANT_COUNT; v++) {
		popc_controller c = make((popc_variant)v, POPC_IGNORE_LITERAL, 0.004);
		popc_tick t;
		const long long counts[] = {0, 1, 2, 1, 2, 3, 3, 2, 1, 1, 0, -1, 0, 1, 5000, 4999};
		for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
			t = step(&c, counts[k]);
			assert_true(fabs(t.f_pc_N) <= 0.004);
			assert_true(isfinite(t.f_c_N));
			if (t.flags & POPC_FLAG_CLAMP)
				assert_true(fabs(t.f_pc_N) == 0.004);
		}
		popc_controller_step(&c, 0, NAN, &t);
		assert_true(isfinite(t.f_c_N));
		popc_controller_step(&c, 0, INFINITY, &t);
		assert_true(isfinite(t.f_c_N));
	}
	/* an energy gap over a tiny displacement: +-inf is clamped to the bound */
	popc_controller c = make(POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, 5.0);
	popc_tick t;
	popc_controller_step(&c, 0, 0.0, &t);
	popc_controller_step(&c, 1000, 0.01, &t);   /* E_ref - W = 0.05 J */
	popc_controller_step(&c, 1000, 0.01 + 1e-310, &t);
	assert_true(t.f_pc_N == 0.0 || fabs(t.f_pc_N) == 5.0);
	assert_true(isfinite(t.f_c_N));
}

/* The axis' command limit: f_c is clamped and flagged, and the PO uses the
 * clamped command (the force really sent) in the next step. */
static void test_axis_force_limit(void **state)
{
	(void)state;
	popc_controller_config cfg = {
		.variant = POPC_VARIANT_NONE, .pc_bound_N = 5.0, .force_limit_N = 0.015,
		.resolution_m = 1e-5, .period_s = 1e-3, .foaw_window = 16, .foaw_noise_m = 1e-5,
		.env = {.kind = POPC_ENV_WALL, .stiffness_Npm = 1000.0, .position_m = 0.0},
	};
	popc_controller c;
	popc_controller_init(&c, &cfg);
	popc_tick t = step(&c, 0);
	t = step(&c, 1); /* f_e = 0.01: below the limit */
	assert_true(t.f_c_N == t.f_e_N && !(t.flags & POPC_FLAG_LIMIT));
	t = step(&c, 2); /* f_e = 0.02 > 0.015 */
	assert_true(t.f_c_N == 0.015 && (t.flags & POPC_FLAG_LIMIT));
	t = step(&c, 3); /* W(3) = W(2) + f_c(2) dx = 0.01e-5 + 0.015e-5 */
	assert_true(fabs(t.W_J - 0.025e-5) < E_TOL);
}

/* FOAW: a constant-velocity count ramp is estimated exactly once the window
 * has filled; the plain backward difference would alternate 0 and delta/T. */
static void test_foaw_slow_ramp(void **state)
{
	(void)state;
	popc_foaw f;
	popc_foaw_init(&f, 16, 1e-5, 1e-3);
	double v = 0;
	for (int k = 0; k < 40; k++)
		v = popc_foaw_update(&f, (double)(k / 4) * 1e-5); /* one count every 4 ms */
	/* true slope 2.5e-3 m/s; the end-fit line through quantized samples lies within
	 * +-delta of all of them, its slope is within delta / (N T) of the truth */
	assert_true(fabs(v - 2.5e-3) <= 1e-5 / (16 * 1e-3) + 1e-12);
	assert_true(v > 0);
	popc_foaw_init(&f, 16, 1e-5, 1e-3);
	assert_true(popc_foaw_update(&f, 0.5) == 0.0); /* first sample */
	/* a jump beyond the band: the one-step slope, 1 m/s up to rounding of 0.5 + 1e-3 */
	assert_true(fabs(popc_foaw_update(&f, 0.5 + 1e-3) - 1.0) < 1e-12);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_ref_energy_one_count_reversal),
		cmocka_unit_test(test_ignore_literal_reversal),
		cmocka_unit_test(test_ignore_undo_reversal),
		cmocka_unit_test(test_zero_displacement),
		cmocka_unit_test(test_po_pc_zero_threshold),
		cmocka_unit_test(test_bound_and_guards),
		cmocka_unit_test(test_axis_force_limit),
		cmocka_unit_test(test_foaw_slow_ramp),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
