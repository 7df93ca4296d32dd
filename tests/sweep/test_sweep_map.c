/* Stability maps (sweep_map.h): the log-K grid, the criteria, and the
 * search replayed from verdicts: every edge position of a monotonic line is
 * found exactly with the stated number of runs, the first failure of a line
 * with folds at least as wide as the scan's step is found exactly, and the
 * band's top above it is found too. */
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
	assert_int_equal(popc_map_grid_points(1, 1.001, 0.5), 2);
	/* a grid beyond a sweep's range, or whose ratio overflows a double
	 * (1e9 / 1e-300), is refused, not converted to a long (issue 28) */
	assert_int_equal(popc_map_grid_points(1e-300, 1e9, 1e-4), -1);
	assert_int_equal(popc_map_grid_points(1e-300, 1e300, 1e-4), -1);
	assert_int_equal(popc_map_grid_points(1e2, 1e6, 0), -1);
	assert_int_equal(popc_map_grid_points(1e2, (double)INFINITY, 0.02), -1);
	assert_int_equal(popc_map_grid_points(1e2, (double)NAN, 0.02), -1);
	assert_int_equal(popc_map_grid_points(1e6, 1e2, 0.02), -1);
	/* 45 decades at 1e-4: 1,036,217 points, within the 2^20 of a map */
	assert_int_equal(popc_map_grid_points(1e-36, 1e9, 1e-4), 1036217);
	/* the scan of 467 points every 16: 0, 16, ..., 464 and 466 */
	assert_int_equal(popc_map_scan_points(467, 16), 31);
	assert_int_equal(popc_map_scan_points(465, 16), 30);
	assert_int_equal(popc_map_scan_points(2, 16), 2);
	assert_int_equal(popc_map_scan_points(467, 1), 467);
}

static void test_criteria(void **state)
{
	(void)state;
	unsigned set;
	popc_error err;
	assert_int_equal(popc_map_criteria_parse("passive,diverged", &set, &err), 0);
	assert_int_equal(set, (1u << POPC_MAP_PASSIVE) | (1u << POPC_MAP_DIVERGED));
	assert_int_not_equal(popc_map_criteria_parse("passive,steady", &set, &err), 0);
	assert_non_null(strstr(err.msg, "'steady'"));
	assert_non_null(strstr(err.msg, "limit-cycle"));
	assert_int_not_equal(popc_map_criteria_parse("", &set, &err), 0);

	popc_map_facts f = {.exit_status = 0, .has_limit_cycle = 1, .limit_cycle = 0,
			    .has_chatter = 1, .chatter_s = 0, .has_port_energy_min = 1,
			    .port_energy_min_J = -5e-7, .has_device_energy_min = 1,
			    .device_energy_min_J = -2e-7, .has_tele_oscillating = 1,
			    .tele_oscillating = 0};
	for (int c = 0; c < POPC_MAP_N_CRITERIA; c++)
		assert_int_equal(popc_map_verdict_of((popc_map_criterion)c, &f, 1e-6), POPC_MAP_OK);
	assert_int_equal(popc_map_verdict_of(POPC_MAP_PASSIVE, &f, 1e-7), POPC_MAP_BAD);
	/* device-passive reads E_dev's minimum, not E_port's */
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DEVICE_PASSIVE, &f, 3e-7), POPC_MAP_OK);
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DEVICE_PASSIVE, &f, 1e-7), POPC_MAP_BAD);
	assert_int_equal(popc_map_criteria_parse("device-passive", &set, &err), 0);
	assert_int_equal(set, 1u << POPC_MAP_DEVICE_PASSIVE);
	/* stable (issue 26) reads a teleoperation sweep's tele_oscillating:
	 * undecided without it (a one-port sweep), bad when it says 1 */
	assert_int_equal(popc_map_criteria_parse("stable,diverged", &set, &err), 0);
	assert_int_equal(set, (1u << POPC_MAP_STABLE) | (1u << POPC_MAP_DIVERGED));
	f.tele_oscillating = 1;
	assert_int_equal(popc_map_verdict_of(POPC_MAP_STABLE, &f, 1e-6), POPC_MAP_BAD);
	assert_int_equal(popc_map_verdict_of(POPC_MAP_DIVERGED, &f, 1e-6), POPC_MAP_OK);
	f.has_tele_oscillating = 0;
	assert_int_equal(popc_map_verdict_of(POPC_MAP_STABLE, &f, 1e-6), POPC_MAP_UNDECIDED);
	f.has_tele_oscillating = 1;
	f.tele_oscillating = 0;
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
static int drive(const unsigned char *truth, unsigned char *v, long n, long scan, popc_map_search *s)
{
	static long need[512];
	assert_true(popc_map_scan_points(n, scan) <= 512);
	memset(v, POPC_MAP_UNKNOWN, (size_t)n);
	int batches = 0;
	for (;;) {
		popc_map_search_line(v, n, scan, need, s);
		if (s->outcome != POPC_MAP_NEEDS_RUNS)
			return batches;
		batches++;
		/* the scan first, then one point per bisection */
		assert_true(s->n_need >= 1 && (batches == 1 || s->n_need <= 2));
		for (int q = 0; q < s->n_need; q++) {
			assert_true(s->need[q] >= 0 && s->need[q] < n);
			assert_int_equal(v[s->need[q]], POPC_MAP_UNKNOWN); /* never twice */
			v[s->need[q]] = truth[s->need[q]];
		}
		assert_true(batches < 64);
	}
}

static long known_points(const unsigned char *v, long n)
{
	long known = 0;
	for (long k = 0; k < n; k++)
		known += v[k] != POPC_MAP_UNKNOWN;
	return known;
}

static void test_every_edge(void **state)
{
	(void)state;
	const long n = 467, scan = 16;
	unsigned char truth[467], v[467];
	popc_map_search s;
	/* acceptable below edge e, not from e on: every e */
	for (long e = 0; e <= n; e++) {
		for (long k = 0; k < n; k++)
			truth[k] = k < e ? POPC_MAP_OK : POPC_MAP_BAD;
		int batches = drive(truth, v, n, scan, &s);
		long known = known_points(v, n);
		assert_int_equal(s.last_ok_index, -1);
		assert_int_equal(s.last_bad_index, -1);
		if (e == 0) {
			assert_int_equal(s.outcome, POPC_MAP_NONE_OK);
			assert_int_equal(s.bad_index, 0);
			assert_int_equal(known, 31);
		} else if (e == n) {
			assert_int_equal(s.outcome, POPC_MAP_ALL_OK);
			assert_int_equal(s.ok_index, n - 1);
			assert_int_equal(known, 31);
		} else {
			assert_int_equal(s.outcome, POPC_MAP_BRACKET);
			assert_int_equal(s.ok_index, e - 1);
			assert_int_equal(s.bad_index, e);
			/* the scan and log2(16) = 4 bisections: 35 runs of 467 */
			assert_true(known <= 31 + 4);
			assert_int_equal(s.runs, known);
			assert_true(batches <= 1 + 4);
		}
	}
}

static void test_folds(void **state)
{
	(void)state;
	const long n = 467, scan = 16;
	unsigned char truth[467], v[467];
	popc_map_search s;
	/* acceptable again from 40 to 80 steps above the first failure e: the
	 * first failure is e, the band's top e + 79, in 39 runs at most */
	for (long e = 1; e + 80 < n; e++) {
		for (long k = 0; k < n; k++)
			truth[k] = k < e || (k >= e + 40 && k < e + 80) ? POPC_MAP_OK : POPC_MAP_BAD;
		int batches = drive(truth, v, n, scan, &s);
		assert_int_equal(s.outcome, POPC_MAP_NOT_MONOTONIC);
		assert_int_equal(s.ok_index, e - 1);
		assert_int_equal(s.bad_index, e);
		assert_int_equal(s.last_ok_index, e + 79);
		assert_int_equal(s.last_bad_index, e + 80);
		assert_true(known_points(v, n) <= 31 + 4 + 4);
		assert_int_equal(s.runs, known_points(v, n));
		assert_true(batches <= 1 + 4);
	}
	/* an unacceptable fold as wide as the scan's step below the edge at
	 * 300 (the paper's PC variants, issue 23): every position f is found
	 * exactly, and the band's top is the edge */
	for (long f = 1; f + 16 < 300; f++) {
		for (long k = 0; k < n; k++)
			truth[k] = k < 300 && (k < f || k >= f + 16) ? POPC_MAP_OK : POPC_MAP_BAD;
		drive(truth, v, n, scan, &s);
		assert_int_equal(s.bad_index, f);
		assert_int_equal(s.ok_index, f - 1);
		if (f + 16 <= 288) { /* an acceptable scan point between fold and edge */
			assert_int_equal(s.outcome, POPC_MAP_NOT_MONOTONIC);
			assert_int_equal(s.last_ok_index, 299);
			assert_int_equal(s.last_bad_index, 300);
		}
	}
	/* a narrower fold may go unseen; what is reported is still a true
	 * transition of the line, and never below the first failure */
	for (long f = 100; f < 280; f++) {
		for (long k = 0; k < n; k++)
			truth[k] = k < 300 && (k < f || k >= f + 3) ? POPC_MAP_OK : POPC_MAP_BAD;
		drive(truth, v, n, scan, &s);
		assert_true(s.bad_index >= f);
		assert_true(s.bad_index <= 300);
		assert_int_equal(truth[s.ok_index], POPC_MAP_OK);
		assert_int_equal(truth[s.bad_index], POPC_MAP_BAD);
	}
	/* unacceptable at k_lo and acceptable above: the band from k_lo, up to
	 * the range's top (no last_bad) */
	for (long k = 0; k < n; k++)
		truth[k] = k < 20 ? POPC_MAP_BAD : POPC_MAP_OK;
	drive(truth, v, n, scan, &s);
	assert_int_equal(s.outcome, POPC_MAP_NOT_MONOTONIC);
	assert_int_equal(s.ok_index, -1);
	assert_int_equal(s.bad_index, 0);
	assert_int_equal(s.last_ok_index, n - 1);
	assert_int_equal(s.last_bad_index, -1);
	/* a run without a verdict that the search needs stops the line, named */
	for (long k = 0; k < n; k++)
		truth[k] = k < 300 ? POPC_MAP_OK : POPC_MAP_BAD;
	truth[296] = POPC_MAP_UNDECIDED; /* the first bisection point of (288, 304) */
	drive(truth, v, n, scan, &s);
	assert_int_equal(s.outcome, POPC_MAP_UNDECIDED_RUN);
	assert_int_equal(s.culprit, 296);
	truth[296] = POPC_MAP_OK;
	truth[240] = POPC_MAP_UNDECIDED; /* a scan point */
	drive(truth, v, n, scan, &s);
	assert_int_equal(s.outcome, POPC_MAP_UNDECIDED_RUN);
	assert_int_equal(s.culprit, 240);
	/* one that it does not need changes nothing */
	truth[240] = POPC_MAP_OK;
	truth[233] = POPC_MAP_UNDECIDED;
	drive(truth, v, n, scan, &s);
	assert_int_equal(s.outcome, POPC_MAP_BRACKET);
	assert_int_equal(s.bad_index, 300);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_grid),
		cmocka_unit_test(test_criteria),
		cmocka_unit_test(test_every_edge),
		cmocka_unit_test(test_folds),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
