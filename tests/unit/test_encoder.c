/* Encoder quantization: count = floor(x / delta), the paper's rule (Sec. IV-A). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "popc/core/encoder.h"

static void test_quantizer_table(void **state)
{
	(void)state;
	const struct {
		double x, delta;
		int ok;
		long long count;
	} cases[] = {
		{0.0, 1e-5, 1, 0},
		{-0.0, 1e-5, 1, 0},
		{9.99e-6, 1e-5, 1, 0},          /* inside the first cell */
		{1e-5, 1e-5, 1, 1},             /* 1e-5 / 1e-5 is exactly 1 */
		{2.5e-5, 1e-5, 1, 2},
		{-1e-12, 1e-5, 1, -1},          /* floor, not truncation: just below zero is -1 */
		{-1e-5, 1e-5, 1, -1},
		{-1.5e-5, 1e-5, 1, -2},
		/* the doubles nearest 0.03 and 1e-5 have a quotient just below 3000: floor is 2999 */
		{0.03, 1e-5, 1, 2999},
		{0.03125, 0.0009765625, 1, 32}, /* powers of two: exact */
		{1.0, 1e-8, 1, 100000000},
		{5e-4, 1e-3, 1, 0},
		{1e3, 1e-8, 1, 100000000000LL},
		{(double)NAN, 1e-5, 0, 0},
		{(double)INFINITY, 1e-5, 0, 0},
		{-(double)INFINITY, 1e-5, 0, 0},
		{1e300, 1e-5, 0, 0},            /* far beyond 2^53 counts */
		/* the limit, with a power-of-two delta so the quotients are exact:
		 * 2^53 - 1 counts is the last exact one, 2^53 is refused */
		{8589934592.0 - 0x1p-20, 0x1p-20, 1, 9007199254740991LL},
		{-8589934592.0 + 0x1p-20, 0x1p-20, 1, -9007199254740991LL},
		{8589934592.0, 0x1p-20, 0, 0},
		{-8589934592.0, 0x1p-20, 0, 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		int ok = -1;
		long long c = popc_encoder_count(cases[i].x, cases[i].delta, &ok);
		assert_int_equal(ok, cases[i].ok);
		if (ok)
			assert_int_equal(c, cases[i].count);
	}
}

/* The measured position lies in [x - delta, x]: the quantizer never reads ahead. */
static void test_measured_within_one_cell_below(void **state)
{
	(void)state;
	const double delta = 1e-5;
	uint64_t s = 88172645463325252ull;
	for (int i = 0; i < 200000; i++) {
		s ^= s << 13;
		s ^= s >> 7;
		s ^= s << 17;
		double x = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * 0.1;
		int ok;
		long long c = popc_encoder_count(x, delta, &ok);
		double xm = popc_encoder_position(c, delta);
		assert_true(ok);
		/* one ulp of slack for count * delta rounding */
		assert_true(xm <= x + 1e-18 && x - xm < delta * (1 + 1e-12));
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_quantizer_table),
		cmocka_unit_test(test_measured_within_one_cell_below),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
