/* Stability maps (sweep_map.h): the log-K grid, the criteria, and the
 * bisection replayed from verdicts: every edge position of a monotonic line
 * is found exactly with the stated number of runs, and folds are named. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/sweep/sweep.h"

static void test_grid(void **state)
{
	(void)state;
	/* 4 decades at 2 %: ceil(ln 1e4 / ln 1.02) = 466 steps */
	assert_int_equal(popc_map_grid_points(1e2, 1e6, 0.02), 467);
	/* the ratio between neighbours is at most 1 + tol */
	for (double tol = 0.001; tol < 0.5; tol *= 1.7) {
		long n = popc_map_grid_points(3.0, 7e5, tol);
		double ratio = pow(7e5 / 3.0, 1.0 / (double)(n - 1));
		assert_true(ratio <= 1 + tol);
		assert_true(pow(7e5 / 3.0, 1.0 / (double)(n - 2)) > 1 + tol); /* and no finer */
	}
	/* a factor of two is 35 steps of 1.02 (1.02^35 = 2.0) */
	assert_int_equal(popc_map_check_steps(1e2, 1e6, 467), 35);
	assert_int_equal(popc_map_grid_points(1, 1.001, 0.5), 2);
}

static void test_criteria(void **state)
{
	(void)state;
	unsigned set;
	popc_error err;
	assert_int_equal(popc_map_criteria_parse("passive,diverged", &set, &err), 0);
	assert_int_equal(set, (1u << POPC_MAP_PASSIVE) | (1u << POPC_MAP_DIVERGED));
	assert_int_not_equal(popc_map_criteria_parse("passive,stable", &set, &err), 0);
	assert_non_null(strstr(err.msg, "'stable'"));
	assert_non_null(strstr(err.msg, "limit-cycle"));
	assert_int_not_equal(popc_map_criteria_parse("", &set, &err), 0);

	popc_map_facts f = {.exit_status = 0, .has_limit_cycle = 1, .limit_cycle = 0,
			    .has_chatter = 1, .chatter_s = 0, .has_port_energy_min = 1,
			    .port_energy_min_J = -5e-7, .has_device_energy_min = 1,
			    .device_energy_min_J = -2e-7};
	for (int c = 0; c < POPC_MAP_N_CRITERIA; c++)
		assert_int_equal(popc_map_verdict_of((popc_map_criterion)c, &f, 1e-6), POPC_MAP_OK);
	assert_int_equal(popc_map_verdict_of(POPC_MAP_PASSIVE, &f, 1e-7), POPC_MAP_BAD);
	/* device-passive reads E_dev's minimum, not E_port's */
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DEVICE_PASSIVE, &f, 3e-7), POPC_MAP_OK);
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DEVICE_PASSIVE, &f, 1e-7), POPC_MAP_BAD);
	assert_int_equal(popc_map_criteria_parse("device-passive", &set, &err), 0);
	assert_int_equal(set, 1u << POPC_MAP_DEVICE_PASSIVE);
	f.chatter_s = 0.001;
	assert_int_equal(popc_map_verdict_of(POPC_MAP_CHATTER, &f, 1e-6), POPC_MAP_BAD);
	f.has_limit_cycle = 0;
	assert_int_equal(popc_map_verdict_of(POPC_MAP_LIMIT_CYCLE, &f, 1e-6), POPC_MAP_UNDECIDED);
	f.has_port_energy_min = 0; /* an axis without a true position */
	assert_int_equal(popc_map_verdict_of(POPC_MAP_PASSIVE, &f, 1e-6), POPC_MAP_UNDECIDED);
	f.has_device_energy_min = 0; /* no dissipation: a real axis, friction, a fixed step */
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DEVICE_PASSIVE, &f, 1e-6), POPC_MAP_UNDECIDED);
	f.exit_status = 6; /* diverged: unacceptable under every criterion */
	for (int c = 0; c < POPC_MAP_N_CRITERIA; c++)
		assert_int_equal(popc_map_verdict_of((popc_map_criterion)c, &f, 1e-6), POPC_MAP_BAD);
	f.exit_status = 1; /* failed otherwise: no verdict */
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DIVERGED, &f, 1e-6), POPC_MAP_UNDECIDED);
}

/* Drives the search against a line whose truth is truth[k], as a map does:
 * runs what it asks for, batch by batch. Returns the batches. */
static int drive(const unsigned char *truth, unsigned char *v, long n, long check, popc_map_search *s)
{
	memset(v, POPC_MAP_UNKNOWN, (size_t)n);
	int batches = 0;
	for (;;) {
		popc_map_search_line(v, n, check, s);
		if (s->outcome != POPC_MAP_NEEDS_RUNS)
			return batches;
		batches++;
		assert_true(s->n_need >= 1 && s->n_need <= 2);
		for (int q = 0; q < s->n_need; q++) {
			assert_true(s->need[q] >= 0 && s->need[q] < n);
			assert_int_equal(v[s->need[q]], POPC_MAP_UNKNOWN); /* never twice */
			v[s->need[q]] = truth[s->need[q]];
		}
		assert_true(batches < 64);
	}
}

static void test_every_edge(void **state)
{
	(void)state;
	const long n = 467, check = 35;
	unsigned char truth[467], v[467];
	popc_map_search s;
	/* acceptable below edge e, not from e on: every e */
	for (long e = 0; e <= n; e++) {
		for (long k = 0; k < n; k++)
			truth[k] = k < e ? POPC_MAP_OK : POPC_MAP_BAD;
		int batches = drive(truth, v, n, check, &s);
		long known = 0;
		for (long k = 0; k < n; k++)
			known += v[k] != POPC_MAP_UNKNOWN;
		if (e == 0) {
			assert_int_equal(s.outcome, POPC_MAP_NONE_OK);
			assert_int_equal(known, 2);
		} else if (e == n) {
			assert_int_equal(s.outcome, POPC_MAP_ALL_OK);
			assert_int_equal(known, 2);
		} else {
			assert_int_equal(s.outcome, POPC_MAP_BRACKET);
			assert_int_equal(s.ok_index, e - 1);
			assert_int_equal(s.bad_index, e);
			/* the ends, ceil(log2(466)) = 9 bisections at most, two checks */
			assert_true(known <= 2 + 9 + 2);
			assert_int_equal(s.runs, known);
			assert_true(batches <= 1 + 9 + 1);
			assert_int_equal(s.check_low, e - 1 - check < 0 ? 0 : e - 1 - check);
			assert_int_equal(s.check_high, e + check > n - 1 ? n - 1 : e + check);
		}
	}
}

static void test_not_monotonic(void **state)
{
	(void)state;
	const long n = 467, check = 35;
	unsigned char truth[467], v[467];
	popc_map_search s;
	/* acceptable again from 30 to 40 steps above the edge, where the 2K
	 * check (35 steps) lands: whichever edge the bisection finds, a check
	 * falls on the other side of the fold, and no edge is drawn */
	int flagged = 0;
	for (long e = 100; e < 300; e++) {
		for (long k = 0; k < n; k++)
			truth[k] = k < e ? POPC_MAP_OK : POPC_MAP_BAD;
		for (long k = e + 30; k < e + 40 && k < n; k++)
			truth[k] = POPC_MAP_OK;
		drive(truth, v, n, check, &s);
		if (s.outcome == POPC_MAP_NOT_MONOTONIC) {
			flagged++;
			assert_true(s.culprit_ok > s.culprit_bad);
			assert_int_equal(truth[s.culprit_ok], POPC_MAP_OK);
			assert_int_equal(truth[s.culprit_bad], POPC_MAP_BAD);
		} else {
			/* a bracket it reports is a true edge of the line */
			assert_int_equal(s.outcome, POPC_MAP_BRACKET);
			assert_int_equal(truth[s.ok_index], POPC_MAP_OK);
			assert_int_equal(truth[s.bad_index], POPC_MAP_BAD);
		}
	}
	assert_int_equal(flagged, 200);
	/* a fold that the K/2 check finds: unacceptable at half the edge */
	for (long k = 0; k < n; k++)
		truth[k] = k < 300 ? POPC_MAP_OK : POPC_MAP_BAD;
	for (long k = 255; k < 270; k++)
		truth[k] = POPC_MAP_BAD;
	drive(truth, v, n, check, &s);
	assert_int_equal(s.outcome, POPC_MAP_NOT_MONOTONIC);
	assert_int_equal(s.ok_index, -1);
	/* a run without a verdict stops the line and is named */
	for (long k = 0; k < n; k++)
		truth[k] = k < 300 ? POPC_MAP_OK : POPC_MAP_BAD;
	truth[233] = POPC_MAP_UNDECIDED;
	drive(truth, v, n, check, &s);
	assert_int_equal(s.outcome, POPC_MAP_UNDECIDED_RUN);
	assert_int_equal(s.culprit_ok, 233);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_grid),
		cmocka_unit_test(test_criteria),
		cmocka_unit_test(test_every_edge),
		cmocka_unit_test(test_not_monotonic),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
