/* PO/PC variants: one-step logic against hand-computed cases (seed Figs. 7
 * and 9, Table I), bound and NaN guards, FOAW. Scene: K_e = 1000 N/m wall at
 * 0, delta = 1e-5 m, T = 1 ms, so one count is f_e = 0.01 N. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "popc/core/controller.h"
#include "test_new_controller.h"

#define E_TOL 1e-20   /* J: values are ~1e-7 J; doubles resolve ~1e-23 J there */
#define F_TOL 1e-13   /* N: forces ~1e-2 N */

static popc_controller *make(popc_variant v, popc_ignore_mode mode, double bound)
{
	popc_controller_config cfg = {
		.variant = v, .pc_bound_N = bound, .ignore_mode = mode, .resolution_m = 1e-5,
		.period_s = 1e-3, .foaw_window = 16, .foaw_noise_m = 1e-5,
		.env = {.kind = POPC_ENV_WALL, .stiffness_Npm = 1000.0, .position_m = 0.0},
	};
	popc_controller *c = new_controller(&cfg);
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
	popc_controller *c = make(v, mode, 5.0);
	for (int k = 0; k < n; k++) {
		popc_tick t = step(c, counts[k]);
		if (fabs(t.W_J - ex[k].W) > E_TOL || fabs(t.E_ref_J - ex[k].E_ref) > E_TOL ||
		    fabs(t.f_pc_N - ex[k].f_pc) > F_TOL || fabs(t.f_c_N - ex[k].f_c) > F_TOL ||
		    t.flags != ex[k].flags)
			fail_msg("variant %s k=%d: W %.17g E_ref %.17g f_pc %.17g f_c %.17g flags %u; "
				 "expected %.17g %.17g %.17g %.17g %u",
				 popc_variant_name(v), k, t.W_J, t.E_ref_J, t.f_pc_N, t.f_c_N, t.flags,
				 ex[k].W, ex[k].E_ref, ex[k].f_pc, ex[k].f_c, ex[k].flags);
	}
	popc_controller_free(c);
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
		popc_controller *c = make((popc_variant)v, POPC_IGNORE_LITERAL, 0.004);
		popc_tick t;
		const long long counts[] = {0, 1, 2, 1, 2, 3, 3, 2, 1, 1, 0, -1, 0, 1, 5000, 4999};
		for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
			t = step(c, counts[k]);
			/* energy-bounding's f_pc is the energy bound's correction of f_e,
			 * which pc_bound does not clamp (controller.c) */
			if (v != POPC_VARIANT_ENERGY_BOUNDING)
				assert_true(fabs(t.f_pc_N) <= 0.004);
			assert_true(isfinite(t.f_c_N));
			if (t.flags & POPC_FLAG_CLAMP)
				assert_true(fabs(t.f_pc_N) == 0.004);
		}
		popc_controller_step(c, 0, (double)NAN, &t);
		assert_true(isfinite(t.f_c_N));
		popc_controller_step(c, 0, (double)INFINITY, &t);
		assert_true(isfinite(t.f_c_N));
		popc_controller_free(c);
	}
}

/* (E_ref - W) / dx overflows to +-inf: the sign is kept, the bound applies
 * and CLAMP (not GUARD) is flagged. The observer is driven to a huge energy
 * deficit, W = -1e305 J, so that over one count (1e-5 m) the quotient is
 * 1e310 > DBL_MAX. */
static void test_infinite_pc_force_is_clamped(void **state)
{
	(void)state;
	for (int dir = -1; dir <= 1; dir += 2) {
		popc_controller *c = make(POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, 5.0);
		popc_tick t = step(c, 10);
		t = step(c, 11);
		c->obs.W_sum_J = -1e305; /* W(k) = W_sum + W_comp (controller.h) */
		c->obs.W_comp_J = 0.0;
		t = step(c, 11 + dir);
		double dx = dir * 1e-5, quotient = (t.E_ref_J - t.W_J) / dx;
		assert_true(t.W_J < -9e304);
		assert_true(isinf(quotient) && (quotient > 0) == (dir > 0)); /* a real overflow */
		assert_true(t.f_pc_N == dir * 5.0);
		assert_true(t.flags == (POPC_FLAG_CLAMP | POPC_FLAG_ACTIVE));
		assert_true(t.f_c_N == t.f_e_N + t.f_pc_N && isfinite(t.f_c_N));
		popc_controller_free(c);
	}
}

/* filtered-velocity, one step at a time. FOAW with N = 16, d = delta = 1e-5 m,
 * T = 1 ms; counts 0, 2, 2, 1:
 * k1: window 1: v = 2e-5 / 1e-3 = 0.02; f_e = 0.02; E_ref = 0.02 2e-5 / 2 = 2e-7;
 *     W = f_c(0) v T = 0; f_pc = 2e-7 / (v T = 2e-5) = 0.01, f_c = 0.03
 * k2: window 2, the middle sample exactly on the band edge
 *     (|2 (2 - 2) - 1 (2 - 0)| = 2 <= n m = 2): v = 2e-5 / 2 / 1e-3 = 0.01;
 *     E_ref = 2e-7 (dx = 0); W = 0.03 1e-5 = 3e-7 >= E_ref: f_pc = 0, f_c = 0.02
 *     (ref-energy would see dx = 0 and W = 0 here)
 * k3: window 2 (|2 (1 - 2) - 1 (1 - 2)| = 1 <= 2; window 3: |3 (1 - 2) - 1 (1 - 0)| = 4 > 3):
 *     v = -1e-5 / 2 / 1e-3 = -0.005; f_e = 0.01; E_ref = 2e-7 + 0.03 (-1e-5) / 2 = 5e-8;
 *     W = 3e-7 + 0.02 (-5e-6) = 2e-7 (W uses v T = -5e-6, E_ref dx = -1e-5);
 *     W >= E_ref: f_pc = 0, f_c = 0.01.
 * ref-energy on the same counts: k2 dx = 0, W = 0, f_pc = 0, f_c = 0.02; k3 W = 0.02 (-1e-5)
 * = -2e-7, f_pc = (5e-8 + 2e-7) / -1e-5 = -0.025, f_c = -0.015. */
static void test_filtered_velocity_one_step(void **state)
{
	(void)state;
	const long long counts[] = {0, 2, 2, 1};
	const double v[] = {0, 0.02, 0.01, -0.005};
	const expect ex[] = {
		{0, 0, 0, 0, 0},
		{0, 2e-7, 0.01, 0.03, POPC_FLAG_ACTIVE},
		{3e-7, 2e-7, 0, 0.02, 0},
		{2e-7, 5e-8, 0, 0.01, 0},
	};
	run_case(POPC_VARIANT_FILTERED_VELOCITY, POPC_IGNORE_LITERAL, counts, ex, 4);
	const expect ref[] = {
		{0, 0, 0, 0, 0},
		{0, 2e-7, 0.01, 0.03, POPC_FLAG_ACTIVE},
		{0, 2e-7, 0, 0.02, 0},
		{-2e-7, 5e-8, -0.025, -0.015, POPC_FLAG_ACTIVE},
	};
	run_case(POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, counts, ref, 4);
	popc_controller *c = make(POPC_VARIANT_FILTERED_VELOCITY, POPC_IGNORE_LITERAL, 5.0);
	for (int k = 0; k < 4; k++) {
		popc_tick t = step(c, counts[k]);
		if (fabs(t.v_mps - v[k]) > 1e-15)
			fail_msg("k=%d: v %.17g, expected %.17g", k, t.v_mps, v[k]);
	}
	popc_controller_free(c);
}

/* Environments: the bilateral spring pulls as well as pushes; the wall's
 * damping adds while in contact, and the wall never pulls: moving out fast
 * enough, K pen + B v < 0 is clamped to 0. K = 1000 N/m, B = 2 N s/m. */
static void test_environments(void **state)
{
	(void)state;
	popc_environment spring = {.kind = POPC_ENV_SPRING, .stiffness_Npm = 1000.0,
				   .damping_Nspm = 2.0, .position_m = 0.01};
	popc_environment wall = {.kind = POPC_ENV_WALL, .stiffness_Npm = 1000.0,
				 .damping_Nspm = 2.0, .position_m = 0.0};
	const struct {
		const popc_environment *e;
		double x, v, f;
		int contact;
	} cases[] = {
		{&spring, 0.005, -0.1, -5.2, 1},   /* 1000 (-0.005) + 2 (-0.1): pulls */
		{&spring, 0.02, 0.1, 10.2, 1},
		{&spring, -1.0, 0.0, -1010.0, 1},  /* far from the rest position: still attached */
		{&wall, -1e-3, 1.0, 0.0, 0},       /* free space, whatever the velocity */
		{&wall, 1e-3, 0.5, 2.0, 1},        /* 1 + 2 0.5 */
		{&wall, 1e-3, -0.2, 0.6, 1},       /* 1 - 0.4: damping on the way out */
		{&wall, 1e-3, -1.0, 0.0, 1},       /* 1 - 2 < 0: never pulls */
		{&wall, 0.0, 0.5, 1.0, 1},         /* on the surface: in contact */
		{&wall, 0.0, -0.5, 0.0, 1},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		double f = popc_environment_force(cases[i].e, cases[i].x, cases[i].v);
		if (fabs(f - cases[i].f) > 1e-12 ||
		    popc_environment_in_contact(cases[i].e, cases[i].x) != cases[i].contact)
			fail_msg("case %zu: f_e %.17g, expected %.17g", i, f, cases[i].f);
	}
	/* an undamped wall ignores the velocity, even an infinite one (0 inf is NaN) */
	wall.damping_Nspm = 0.0;
	assert_true(popc_environment_force(&wall, 1e-3, (double)INFINITY) == 1000.0 * 1e-3);
	assert_true(popc_environment_force(&wall, 1e-3, -(double)INFINITY) == 1000.0 * 1e-3);
	/* in the controller: the backward-difference velocity feeds the damping;
	 * 100 counts in, then back 1 and 49 counts: 1 + 2 1 = 3 N, 0.99 - 2 0.01 = 0.97 N,
	 * 0.5 - 2 0.49 < 0: 0 N */
	popc_controller_config cfg = {
		.variant = POPC_VARIANT_NONE, .pc_bound_N = 5.0, .resolution_m = 1e-5,
		.period_s = 1e-3, .foaw_window = 16, .foaw_noise_m = 1e-5,
		.env = {.kind = POPC_ENV_WALL, .stiffness_Npm = 1000.0, .damping_Nspm = 2.0},
	};
	popc_controller *c = new_controller(&cfg);
	const long long counts[] = {0, 100, 99, 50};
	const double f_e[] = {0.0, 3.0, 0.97, 0.0};
	for (int k = 0; k < 4; k++) {
		popc_tick t = step(c, counts[k]);
		if (fabs(t.f_e_N - f_e[k]) > 1e-12 || t.f_c_N != t.f_e_N)
			fail_msg("k=%d: f_e %.17g, expected %.17g", k, t.f_e_N, f_e[k]);
	}
	cfg.env.kind = POPC_ENV_SPRING;
	popc_controller_free(c);
	c = new_controller(&cfg);
	(void)step(c, 0);
	popc_tick t = step(c, -100); /* -1 + 2 (-1) = -3 N: the spring pulls back */
	assert_true(fabs(t.f_e_N + 3.0) < 1e-12 && t.f_c_N == t.f_e_N);
	popc_controller_free(c);
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
	popc_controller *c = new_controller(&cfg);
	popc_tick t = step(c, 0);
	t = step(c, 1); /* f_e = 0.01: below the limit */
	assert_true(t.f_c_N == t.f_e_N && !(t.flags & POPC_FLAG_LIMIT));
	t = step(c, 2); /* f_e = 0.02 > 0.015 */
	assert_true(t.f_c_N == 0.015 && (t.flags & POPC_FLAG_LIMIT));
	t = step(c, 3); /* W(3) = W(2) + f_c(2) dx = 0.01e-5 + 0.015e-5 */
	assert_true(fabs(t.W_J - 0.025e-5) < E_TOL);
	popc_controller_free(c);
}

/* FOAW: a constant-velocity count ramp is estimated exactly once the window
 * has filled; the plain backward difference would alternate 0 and delta/T. */
static void test_foaw_slow_ramp(void **state)
{
	(void)state;
	for (int mode = 0; mode < 2; mode++) {
		/* the band in counts (d = delta) and in metres (d = 1.5 delta) */
		popc_foaw f;
		popc_foaw_init(&f, 16, mode ? 1.5e-5 : 1e-5, 1e-5, 1e-3);
		assert_true(f.noise_counts == (mode ? 0 : 1));
		double v = 0;
		for (int k = 0; k < 40; k++)
			v = popc_foaw_update(&f, k / 4, (double)(k / 4) * 1e-5); /* a count every 4 ms */
		/* true slope 2.5e-3 m/s; the end-fit line through quantized samples lies within
		 * +-d of all of them, its slope is within d / (N T) of the truth */
		assert_true(fabs(v - 2.5e-3) <= f.noise_m / (16 * 1e-3) + 1e-12);
		assert_true(v > 0);
	}
	popc_foaw f;
	popc_foaw_init(&f, 16, 1e-5, 1e-5, 1e-3);
	assert_true(popc_foaw_update(&f, 50000, 0.5) == 0.0); /* first sample */
	/* a jump beyond the band: the one-step slope, 100 counts in 1 ms = 1 m/s */
	assert_true(fabs(popc_foaw_update(&f, 50100, 0.501) - 1.0) < 1e-12);
	/* a band of a whole number of counts given as text: 3e-5 / 1e-5 = 2.9999999999999996 */
	popc_foaw_init(&f, 16, 3e-5, 1e-5, 1e-3);
	assert_true(f.noise_counts == 3);
	popc_foaw_init(&f, 16, 1e-5, 0.0, 1e-3); /* positions that are not counts */
	assert_true(f.noise_counts == 0);
}

/* The window choice depends on counts only, not on where they happen: a slow
 * ramp with one-count dips, replayed at every offset from -2000 to 2000
 * counts, gives bitwise the velocities it gives at 0. In metres, a sample on
 * the band edge (|deviation| = d) rounds in or out depending on the absolute
 * position: with the test in metres this pattern chose another window (v off
 * by more than 1e-9 m/s) at 3975 of the 4001 offsets. Counts near the 2^55
 * limit of the integer test and a huge jump too. */
static void test_foaw_offset_invariant(void **state)
{
	(void)state;
	/* 1 count every 3 ticks, with a one-count dip and a two-tick stall */
	static const int pattern[] = {0, 0, 0, 1, 1, 1, 2, 2, 1, 2, 3, 3, 3, 4, 4, 4, 5,
				      5, 4, 5, 6, 6, 6, 6, 7, 7, 7, 8, 8, 8, 9, 8, 9, 10,
				      10, 10, 11, 11, 11, 12, 12, 11, 12, 13, 13, 13};
	enum { LEN = sizeof pattern / sizeof pattern[0] };
	double ref[LEN];
	popc_foaw f;
	popc_foaw_init(&f, 16, 1e-5, 1e-5, 1e-3);
	for (int k = 0; k < LEN; k++)
		ref[k] = popc_foaw_update(&f, pattern[k], pattern[k] * 1e-5);
	int differ = 0;
	for (long long off = -2000; off <= 2000; off++) {
		popc_foaw_init(&f, 16, 1e-5, 1e-5, 1e-3);
		for (int k = 0; k < LEN; k++) {
			long long c = off + pattern[k];
			double v = popc_foaw_update(&f, c, (double)c * 1e-5);
			if (memcmp(&v, &ref[k], sizeof v) != 0) {
				if (!differ)
					print_message("offset %lld k %d: v %.17g, at 0 %.17g\n", off, k, v,
						      ref[k]);
				differ++;
				break;
			}
		}
	}
	assert_int_equal(differ, 0);
	/* far from 0 the counts still decide (the metres there are 1e13 m: no matter) */
	const long long far[] = {(1LL << 55) - 20, -(1LL << 55), 4000000000000000000LL - 100};
	for (size_t i = 0; i < sizeof far / sizeof far[0]; i++) {
		popc_foaw_init(&f, 16, 1e-5, 1e-5, 1e-3);
		for (int k = 0; k < LEN; k++) {
			double v = popc_foaw_update(&f, far[i] + pattern[k], 0.0);
			assert_true(v == ref[k]);
		}
	}
	/* a jump of more than 2^55 counts ends the window: the one-step slope */
	popc_foaw_init(&f, 16, 1e-5, 1e-5, 1e-3);
	(void)popc_foaw_update(&f, -(1LL << 60), 0.0);
	(void)popc_foaw_update(&f, -(1LL << 60), 0.0);
	double v = popc_foaw_update(&f, 1LL << 60, 0.0);
	assert_true(v == (double)(1LL << 61) * 1e-5 / 1e-3);
}

/* popc_observer_same_rule (popc-analyze energy steps one observer for two
 * definitions that share a rule): observers that share a rule give the same
 * bits at every step of a motion with one-count reversals and a varying
 * force, for every pair of variants and Table I modes; and the rule is what
 * the variant decides: seed eq. 3, Table I by its mode, filtered velocity. */
static void test_observer_same_rule(void **state)
{
	(void)state;
	static const struct {
		popc_variant a;
		popc_ignore_mode ma;
		popc_variant b;
		popc_ignore_mode mb;
		int same;
	} cases[] = {
		{POPC_VARIANT_REF_ENERGY, POPC_IGNORE_UNDO, POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, 1},
		{POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, POPC_VARIANT_NONE, POPC_IGNORE_LITERAL, 1},
		{POPC_VARIANT_REF_ENERGY, POPC_IGNORE_LITERAL, POPC_VARIANT_IGNORE, POPC_IGNORE_LITERAL, 0},
		{POPC_VARIANT_IGNORE, POPC_IGNORE_LITERAL, POPC_VARIANT_IGNORE, POPC_IGNORE_UNDO, 0},
		{POPC_VARIANT_IGNORE, POPC_IGNORE_UNDO, POPC_VARIANT_IMPROVED, POPC_IGNORE_UNDO, 1},
		{POPC_VARIANT_FILTERED_VELOCITY, POPC_IGNORE_LITERAL, POPC_VARIANT_FILTERED_VELOCITY,
		 POPC_IGNORE_UNDO, 1},
		{POPC_VARIANT_FILTERED_VELOCITY, POPC_IGNORE_LITERAL, POPC_VARIANT_REF_ENERGY,
		 POPC_IGNORE_LITERAL, 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_observer a, b;
		popc_observer_init(&a, cases[i].a, cases[i].ma);
		popc_observer_init(&b, cases[i].b, cases[i].mb);
		if (popc_observer_same_rule(&a, &b) != cases[i].same ||
		    popc_observer_same_rule(&b, &a) != cases[i].same)
			fail_msg("case %zu: %s/%d against %s/%d: same rule expected %d", i,
				 popc_variant_name(cases[i].a), (int)cases[i].ma,
				 popc_variant_name(cases[i].b), (int)cases[i].mb, cases[i].same);
	}
	/* every pair: a shared rule gives the same bits (W, E_ref, dx, flags) */
	static const long long counts[] = {0, 1, 2, 1, 2, 1, 0, -1, 0, 3, 2, 3, 3, 2, 1, 2};
	const int n = (int)(sizeof counts / sizeof counts[0]);
	int shared = 0;
	for (int va = 0; va < POPC_VARIANT_COUNT; va++)
		for (int vb = 0; vb < POPC_VARIANT_COUNT; vb++)
			for (int m = 0; m < 4; m++) {
				popc_observer a, b;
				popc_observer_init(&a, (popc_variant)va, (popc_ignore_mode)(m & 1));
				popc_observer_init(&b, (popc_variant)vb, (popc_ignore_mode)(m >> 1));
				if (!popc_observer_same_rule(&a, &b))
					continue;
				shared++;
				for (int k = 0; k < n; k++) {
					const double x = (double)counts[k] * 1e-5, v = 0.3 * (double)k - 2.0;
					const double f_e = 0.01 * (double)counts[k], f_c = f_e + 0.7 * (double)(k % 3) - 0.5;
					popc_observation oa, ob;
					popc_observer_update(&a, x, counts[k], v, 1e-3, f_e, &oa);
					popc_observer_update(&b, x, counts[k], v, 1e-3, f_e, &ob);
					popc_observer_commit(&a, &oa, f_e, f_c);
					popc_observer_commit(&b, &ob, f_e, f_c);
					if (memcmp(&a.W_J, &b.W_J, sizeof a.W_J) != 0 ||
					    memcmp(&a.E_ref_J, &b.E_ref_J, sizeof a.E_ref_J) != 0 ||
					    memcmp(&oa.dx_m, &ob.dx_m, sizeof oa.dx_m) != 0 || oa.flags != ob.flags)
						fail_msg("%s/%d and %s/%d share a rule but differ at step %d: "
							 "W %.17g against %.17g",
							 popc_variant_name((popc_variant)va), m & 1,
							 popc_variant_name((popc_variant)vb), m >> 1, k, a.W_J, b.W_J);
				}
			}
	assert_true(shared > 2 * POPC_VARIANT_COUNT); /* more than each with itself */
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
		cmocka_unit_test(test_infinite_pc_force_is_clamped),
		cmocka_unit_test(test_filtered_velocity_one_step),
		cmocka_unit_test(test_environments),
		cmocka_unit_test(test_foaw_slow_ramp),
		cmocka_unit_test(test_foaw_offset_invariant),
		cmocka_unit_test(test_observer_same_rule),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
