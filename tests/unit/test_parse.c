/* Tests for popc/util/parse.h, the one number grammar of every popc program:
 * tables of accepted and refused texts for numbers and whole numbers (decimal,
 * exponent, signs, blanks, hex, inf/nan, trailing junk, overflow, underflow,
 * empty), exact whole numbers over the whole long long range, and agreement
 * between the two (a text that is a whole number is that number). */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "popc/util/parse.h"
#include "popc/util/text.h"

static uint64_t bits_of(double v)
{
	uint64_t b;
	memcpy(&b, &v, sizeof b);
	return b;
}

static const char *status_name(popc_parse_status st)
{
	switch (st) {
	case POPC_PARSE_OK: return "OK";
	case POPC_PARSE_EMPTY: return "EMPTY";
	case POPC_PARSE_INVALID: return "INVALID";
	case POPC_PARSE_NOT_WHOLE: return "NOT_WHOLE";
	case POPC_PARSE_OVERFLOW: return "OVERFLOW";
	case POPC_PARSE_UNDERFLOW: return "UNDERFLOW";
	case POPC_PARSE_RANGE: return "RANGE";
	}
	return "?";
}

/* ---- numbers --------------------------------------------------------------- */

static void test_double_table(void **state)
{
	(void)state;
	const struct {
		const char *text;
		popc_parse_status want;
		double value;
	} cases[] = {
		/* decimal */
		{"1", POPC_PARSE_OK, 1.0},
		{"0.1", POPC_PARSE_OK, 0.1},
		{"123.456", POPC_PARSE_OK, 123.456},
		{".5", POPC_PARSE_OK, 0.5},
		{"5.", POPC_PARSE_OK, 5.0},
		{"0000.25000", POPC_PARSE_OK, 0.25},
		/* exponent */
		{"1e3", POPC_PARSE_OK, 1e3},
		{"1E3", POPC_PARSE_OK, 1e3},
		{"2.5e-3", POPC_PARSE_OK, 2.5e-3},
		{"2.5e+3", POPC_PARSE_OK, 2.5e3},
		{"1e308", POPC_PARSE_OK, 1e308},
		{"1.7976931348623157e308", POPC_PARSE_OK, 1.7976931348623157e308},
		{"4.9e-324", POPC_PARSE_OK, 4.9e-324},   /* the smallest subnormal */
		{"2.2250738585072014e-308", POPC_PARSE_OK, 2.2250738585072014e-308},
		{"0e-400", POPC_PARSE_OK, 0.0},          /* zero is zero at any exponent */
		{"0.000e999999999999999999", POPC_PARSE_OK, 0.0},
		/* signs */
		{"-1.5", POPC_PARSE_OK, -1.5},
		{"+1.5", POPC_PARSE_OK, 1.5},
		{"-0", POPC_PARSE_OK, -0.0},
		{"--1", POPC_PARSE_INVALID, 0},
		{"+-1", POPC_PARSE_INVALID, 0},
		{"-", POPC_PARSE_INVALID, 0},
		{"+", POPC_PARSE_INVALID, 0},
		/* blanks belong to the syntax around a number, not to it */
		{" 1", POPC_PARSE_INVALID, 0},
		{"1 ", POPC_PARSE_INVALID, 0},
		{"\t1", POPC_PARSE_INVALID, 0},
		{"1 2", POPC_PARSE_INVALID, 0},
		{"- 1", POPC_PARSE_INVALID, 0},
		/* hex, as strtod would take it */
		{"0x2", POPC_PARSE_INVALID, 0},
		{"0X2", POPC_PARSE_INVALID, 0},
		{"0x1p1", POPC_PARSE_INVALID, 0},
		{"-0x1.8p1", POPC_PARSE_INVALID, 0},
		/* inf and nan */
		{"inf", POPC_PARSE_INVALID, 0},
		{"-inf", POPC_PARSE_INVALID, 0},
		{"INF", POPC_PARSE_INVALID, 0},
		{"infinity", POPC_PARSE_INVALID, 0},
		{"nan", POPC_PARSE_INVALID, 0},
		{"NaN", POPC_PARSE_INVALID, 0},
		{"nan(0x1)", POPC_PARSE_INVALID, 0},
		/* trailing junk */
		{"2s", POPC_PARSE_INVALID, 0},
		{"1e", POPC_PARSE_INVALID, 0},
		{"1e+", POPC_PARSE_INVALID, 0},
		{"1e-", POPC_PARSE_INVALID, 0},
		{"1.5.2", POPC_PARSE_INVALID, 0},
		{"1,5", POPC_PARSE_INVALID, 0},      /* a decimal comma is the log reader's option */
		{"1e5.5", POPC_PARSE_INVALID, 0},
		{"1;", POPC_PARSE_INVALID, 0},
		{"1\n", POPC_PARSE_INVALID, 0},
		{"e5", POPC_PARSE_INVALID, 0},
		{".", POPC_PARSE_INVALID, 0},
		{"one", POPC_PARSE_INVALID, 0},
		/* overflow and underflow */
		{"1e309", POPC_PARSE_OVERFLOW, 0},
		{"-1e309", POPC_PARSE_OVERFLOW, 0},
		{"1.8e308", POPC_PARSE_OVERFLOW, 0},
		{"1e99999999999999999999", POPC_PARSE_OVERFLOW, 0},
		{"1e-400", POPC_PARSE_UNDERFLOW, 0},
		{"-2.4e-324", POPC_PARSE_UNDERFLOW, 0}, /* half the smallest subnormal: rounds to -0 */
		{"0.0000001e-99999", POPC_PARSE_UNDERFLOW, 0},
		/* empty */
		{"", POPC_PARSE_EMPTY, 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		double v = 12345.0;
		popc_parse_status st = popc_parse_double_text(cases[i].text, &v);
		if (st != cases[i].want)
			fail_msg("'%s': %s, want %s", cases[i].text, status_name(st),
				 status_name(cases[i].want));
		if (st == POPC_PARSE_OK && bits_of(v) != bits_of(cases[i].value))
			fail_msg("'%s': %.17g, want %.17g", cases[i].text, v, cases[i].value);
		if (st != POPC_PARSE_OK && v != 12345.0)
			fail_msg("'%s': refused but *out changed to %.17g", cases[i].text, v);
		/* the inline fast path of the log reader gives the same verdict */
		double w;
		const char *t = cases[i].text;
		popc_parse_status fast = popc_parse_double_exact(t, t + strlen(t), &w);
		if (fast != st)
			fail_msg("'%s': popc_parse_double_exact %s, popc_parse_double_text %s", t,
				 status_name(fast), status_name(st));
	}
}

/* A span is read up to its end, not to a NUL: "12,34" as two fields. */
static void test_double_span(void **state)
{
	(void)state;
	const char *text = "12,3.5e1";
	double a = 0, b = 0;
	assert_int_equal(popc_parse_double_span(text, text + 2, &a), POPC_PARSE_OK);
	assert_int_equal(popc_parse_double_span(text + 3, text + 8, &b), POPC_PARSE_OK);
	assert_true(a == 12.0 && b == 35.0);
	assert_int_equal(popc_parse_double_span(text, text + 3, &a), POPC_PARSE_INVALID);
	assert_int_equal(popc_parse_double_span(text, text, &a), POPC_PARSE_EMPTY);
	/* "1e5" cut before its exponent's digits is "1e": junk */
	assert_int_equal(popc_parse_double_span(text + 5, text + 7, &a), POPC_PARSE_INVALID);
}

/* Blanks (space, tab) around a value are the reader's to drop: trimmed, the
 * text is a number. */
static void test_trim(void **state)
{
	(void)state;
	const char *text = " \t 2.5 \t";
	const char *b = text, *e = text + strlen(text);
	popc_trim_blanks(&b, &e);
	assert_int_equal(e - b, 3);
	assert_memory_equal(b, "2.5", 3);
	double v;
	assert_int_equal(popc_parse_double_span(b, e, &v), POPC_PARSE_OK);
	assert_true(v == 2.5);
	const char *blank = " \t ";
	b = blank;
	e = blank + 3;
	popc_trim_blanks(&b, &e);
	assert_true(b == e);
}

/* ---- whole numbers --------------------------------------------------------- */

static void test_whole_table(void **state)
{
	(void)state;
	const struct {
		const char *text;
		long long lo, hi;
		unsigned flags;
		popc_parse_status want;
		long long value;
	} cases[] = {
		{"42", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"-42", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, -42},
		{"+42", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"-0", 0, 10, 0, POPC_PARSE_OK, 0},
		{"007", 0, 10, 0, POPC_PARSE_OK, 7}, /* decimal, never octal */
		/* the same spelling as any number, when the value is whole */
		{"42.0", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"42.", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"4.2e1", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"420e-1", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"4200000e-5", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 42},
		{"1e3", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 1000},
		{"0.0", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 0},
		{".0e5", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 0},
		{"0e999999999999999999", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 0},
		{"0000000000000000000000000000001", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 1},
		{"1.00000000000000000000000000000", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 1},
		{"100000000000000000000000e-6", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK,
		 100000000000000000LL}, /* 10^23 * 10^-6 */
		/* exact beyond 2^53, where a double would round */
		{"9007199254740993", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 9007199254740993LL},
		{"9007199254740993.0", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, 9007199254740993LL},
		{"9223372036854775807", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, LLONG_MAX},
		{"9.223372036854775807e18", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, LLONG_MAX},
		{"-9223372036854775808", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OK, LLONG_MIN},
		/* not whole */
		{"4.5", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_NOT_WHOLE, 0},
		{"-0.5", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_NOT_WHOLE, 0},
		{"9007199254740993.5", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_NOT_WHOLE, 0},
		{"2.0000000000000001", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_NOT_WHOLE, 0}, /* 2.0 as a double */
		{"1e-400", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_NOT_WHOLE, 0},
		{"123e-1", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_NOT_WHOLE, 0},
		/* overflow */
		{"9223372036854775808", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		{"-9223372036854775809", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		{"1e19", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		{"99999999999999999999999", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		{"1e999999999999999999", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		{"1e400", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		/* range */
		{"0", 1, 10, 0, POPC_PARSE_RANGE, 0},
		{"11", 1, 10, 0, POPC_PARSE_RANGE, 0},
		{"-1", 0, 10, 0, POPC_PARSE_RANGE, 0},
		{"1", 1, 10, 0, POPC_PARSE_OK, 1},
		{"10", 1, 10, 0, POPC_PARSE_OK, 10},
		{"1e1", 1, 10, 0, POPC_PARSE_OK, 10},
		/* refused spellings, as for every number */
		{"", 0, 10, 0, POPC_PARSE_EMPTY, 0},
		{" 1", 0, 10, 0, POPC_PARSE_INVALID, 0},
		{"1 ", 0, 10, 0, POPC_PARSE_INVALID, 0},
		{"0x2", 0, 10, 0, POPC_PARSE_INVALID, 0},
		{"0x1p1", 0, 10, 0, POPC_PARSE_INVALID, 0},
		{"inf", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_INVALID, 0},
		{"nan", LLONG_MIN, LLONG_MAX, 0, POPC_PARSE_INVALID, 0},
		{"4x", 0, 10, 0, POPC_PARSE_INVALID, 0},
		{"4e", 0, 10, 0, POPC_PARSE_INVALID, 0},
		{"-", 0, 10, 0, POPC_PARSE_INVALID, 0},
		/* hexadecimal where a register map allows it */
		{"0x2a", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_OK, 42},
		{"0X2A", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_OK, 42},
		{"0xFFFF", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_OK, 0xFFFF},
		{"0x10000", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_RANGE, 0},
		{"0100", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_OK, 100}, /* not octal 64 */
		{"42", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_OK, 42},
		{"-0x2a", LLONG_MIN, LLONG_MAX, POPC_PARSE_HEX, POPC_PARSE_INVALID, 0},
		{"+0x2a", LLONG_MIN, LLONG_MAX, POPC_PARSE_HEX, POPC_PARSE_INVALID, 0},
		{"0x", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_INVALID, 0},
		{"0xg", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_INVALID, 0},
		{"0x1p1", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_INVALID, 0},
		{"0x1.8", 0, 0xFFFF, POPC_PARSE_HEX, POPC_PARSE_INVALID, 0},
		{"0x7fffffffffffffff", LLONG_MIN, LLONG_MAX, POPC_PARSE_HEX, POPC_PARSE_OK, LLONG_MAX},
		{"0x8000000000000000", LLONG_MIN, LLONG_MAX, POPC_PARSE_HEX, POPC_PARSE_OVERFLOW, 0},
		{"0x10000000000000000", LLONG_MIN, LLONG_MAX, POPC_PARSE_HEX, POPC_PARSE_OVERFLOW, 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *t = cases[i].text;
		long long v = 12345;
		popc_parse_status st =
			popc_parse_ll_span(t, t + strlen(t), cases[i].lo, cases[i].hi, cases[i].flags, &v);
		if (st != cases[i].want)
			fail_msg("'%s' in [%lld, %lld]: %s, want %s", t, cases[i].lo, cases[i].hi,
				 status_name(st), status_name(cases[i].want));
		if (st == POPC_PARSE_OK && v != cases[i].value)
			fail_msg("'%s': %lld, want %lld", t, v, cases[i].value);
		if (st != POPC_PARSE_OK && v != 12345)
			fail_msg("'%s': refused but *out changed to %lld", t, v);
		if (cases[i].flags == 0) {
			long long w = 12345;
			if (popc_parse_ll_text(t, cases[i].lo, cases[i].hi, &w) != st || (st == 0 && w != v))
				fail_msg("'%s': popc_parse_ll_text disagrees with popc_parse_ll_span", t);
		}
	}
}

static void test_int_and_u64(void **state)
{
	(void)state;
	int i = 0;
	assert_int_equal(popc_parse_int_text("2147483647", INT_MIN, INT_MAX, &i), POPC_PARSE_OK);
	assert_int_equal(i, INT_MAX);
	assert_int_equal(popc_parse_int_text("-2147483648", INT_MIN, INT_MAX, &i), POPC_PARSE_OK);
	assert_int_equal(i, INT_MIN);
	assert_int_equal(popc_parse_int_text("2147483648", INT_MIN, INT_MAX, &i), POPC_PARSE_RANGE);
	assert_int_equal(popc_parse_int_text("1e10", 1, 100, &i), POPC_PARSE_RANGE);
	assert_int_equal(popc_parse_int_text("0x10", 1, 100, &i), POPC_PARSE_INVALID);
	assert_int_equal(i, INT_MIN);

	const struct {
		const char *text;
		uint64_t hi;
		unsigned flags;
		popc_parse_status want;
		uint64_t value;
	} cases[] = {
		{"18446744073709551615", UINT64_MAX, 0, POPC_PARSE_OK, UINT64_MAX},
		{"1.8446744073709551615e19", UINT64_MAX, 0, POPC_PARSE_OK, UINT64_MAX},
		{"18446744073709551616", UINT64_MAX, 0, POPC_PARSE_OVERFLOW, 0},
		{"-0", UINT64_MAX, 0, POPC_PARSE_OK, 0},
		{"-1", UINT64_MAX, 0, POPC_PARSE_RANGE, 0},   /* strtoull would give 2^64 - 1 */
		{"11", 10, 0, POPC_PARSE_RANGE, 0},
		{"0xff", UINT64_MAX, POPC_PARSE_HEX, POPC_PARSE_OK, 255},
		/* the sweep plan's id: hex digits, no prefix */
		{"00ab0123456789ef", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_OK, 0x00ab0123456789efULL},
		{"ffffffffffffffff", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_OK, UINT64_MAX},
		{"10000000000000000", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_OVERFLOW, 0},
		{"0x10", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_INVALID, 0},
		{"-1", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_INVALID, 0},
		{" 1", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_INVALID, 0},
		{"", UINT64_MAX, POPC_PARSE_BASE16, POPC_PARSE_EMPTY, 0},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		const char *t = cases[k].text;
		uint64_t v = 12345;
		popc_parse_status st = popc_parse_u64_span(t, t + strlen(t), cases[k].hi, cases[k].flags, &v);
		if (st != cases[k].want)
			fail_msg("'%s': %s, want %s", t, status_name(st), status_name(cases[k].want));
		if (st == POPC_PARSE_OK && v != cases[k].value)
			fail_msg("'%s': %llu, want %llu", t, (unsigned long long)v,
				 (unsigned long long)cases[k].value);
	}
}

static uint64_t rng_state = 88172645463325252ULL;

static uint64_t rng(void)
{
	rng_state ^= rng_state << 13;
	rng_state ^= rng_state >> 7;
	rng_state ^= rng_state << 17;
	return rng_state;
}

/* Every long long, written as printf writes it and in three other spellings
 * of the same value ("N.000", "N000e-3", "D.DDDe+K"), reads back exactly; the
 * same text as a number reads as the double nearest to it, and the value plus
 * one half is not whole. */
static void test_whole_random(void **state)
{
	(void)state;
	char text[80];
	for (int i = 0; i < 200000; i++) {
		long long want = (long long)rng();
		if (i % 4 == 1)
			want >>= rng() % 63; /* small magnitudes as well */
		for (int f = 0; f < 3; f++) {
			if (f == 0)
				snprintf(text, sizeof text, "%lld", want);
			else if (f == 1)
				snprintf(text, sizeof text, "%lld.000", want);
			else
				snprintf(text, sizeof text, "%lld000e-3", want);
			long long got;
			if (popc_parse_ll_text(text, LLONG_MIN, LLONG_MAX, &got) != POPC_PARSE_OK || got != want)
				fail_msg("'%s' did not read back as %lld", text, want);
			double d;
			if (popc_parse_double_text(text, &d) != POPC_PARSE_OK || d != (double)want)
				fail_msg("'%s' as a number: %.17g, want %.17g", text, d, (double)want);
		}
		/* D.DDDe+K: the digits with the point after the first */
		char digits[32];
		int n = snprintf(digits, sizeof digits, "%llu",
				 want < 0 ? 0ULL - (unsigned long long)want : (unsigned long long)want);
		snprintf(text, sizeof text, "%s%c.%se+%d", want < 0 ? "-" : "", digits[0], digits + 1, n - 1);
		long long got;
		if (popc_parse_ll_text(text, LLONG_MIN, LLONG_MAX, &got) != POPC_PARSE_OK || got != want)
			fail_msg("'%s' did not read back as %lld", text, want);
		snprintf(text, sizeof text, "%lld.5", want);
		if (popc_parse_ll_text(text, LLONG_MIN, LLONG_MAX, &got) != POPC_PARSE_NOT_WHOLE)
			fail_msg("'%s' read as a whole number", text);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_double_table), cmocka_unit_test(test_double_span),
		cmocka_unit_test(test_trim),         cmocka_unit_test(test_whole_table),
		cmocka_unit_test(test_int_and_u64),  cmocka_unit_test(test_whole_random),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
