/* Tests for numfmt.h: bitwise round trips, agreement with glibc's correctly
 * rounded strtod, shortest output, and a table of edge cases.
 *
 * Random counts scale with the environment variable POPC_NUMFMT_ITER (the
 * number of random round trips; default 2000000; the other random tests use a
 * fixed fraction of it). The generator is a seeded xorshift64*, so every run
 * checks the same values. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/util/numfmt.h"

static uint64_t rng_state;

/* xorshift64* (S. Vigna, 2014): fast, deterministic, good enough to spread
 * bit patterns and digit strings. */
static uint64_t rng(void)
{
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return rng_state * UINT64_C(2685821657736338717);
}

static void rng_seed(uint64_t seed)
{
	rng_state = seed ? seed : 1;
}

static long iterations(void)
{
	const char *s = getenv("POPC_NUMFMT_ITER");
	long n = s ? strtol(s, NULL, 10) : 2000000;
	return n > 0 ? n : 2000000;
}

static uint64_t bits_of(double v)
{
	uint64_t b;
	memcpy(&b, &v, sizeof b);
	return b;
}

static double double_of(uint64_t b)
{
	double v;
	memcpy(&v, &b, sizeof v);
	return v;
}

/* Parses the whole NUL-terminated string with popc_parse_double and fails the
 * test if not all of it was consumed. */
static double parse_all(const char *s)
{
	double v = 0.0;
	size_t n = strlen(s);
	size_t used = popc_parse_double(s, s + n, &v);
	if (used != n) {
		print_error("parse consumed %zu of %zu characters of \"%.80s\"\n", used, n, s);
		fail();
	}
	return v;
}

static void expect_same_bits(double got, double want, const char *what)
{
	if (bits_of(got) != bits_of(want)) {
		print_error("%s: got %.17g (0x%016llx), want %.17g (0x%016llx)\n", what, got,
			    (unsigned long long)bits_of(got), want, (unsigned long long)bits_of(want));
		fail();
	}
}

/* Splits decimal text into its significant digits (no leading or trailing
 * zeros; "" for zero) and the decimal exponent x of the first of them, so
 * that the value is d.ddd * 10^x whatever the notation. */
static void decompose(const char *s, char *digits, int *x)
{
	int point = -1, count = 0, first = -1, exp10 = 0;
	size_t nd = 0;
	if (*s == '-' || *s == '+')
		s++;
	for (; *s && *s != 'e' && *s != 'E'; s++) {
		if (*s == '.') {
			point = count;
			continue;
		}
		if (first < 0 && *s != '0')
			first = count;
		if (first >= 0)
			digits[nd++] = *s;
		count++;
	}
	if (*s)
		exp10 = atoi(s + 1);
	while (nd > 0 && digits[nd - 1] == '0')
		nd--;
	digits[nd] = '\0';
	if (point < 0)
		point = count;
	*x = first < 0 ? 0 : point - first - 1 + exp10;
}

static int significant_digits(const char *s)
{
	char d[800];
	int x;
	decompose(s, d, &x);
	return (int)strlen(d);
}

/* ---- (a) edge cases ------------------------------------------------------ */

static void test_format_table(void **state)
{
	(void)state;
	static const struct {
		double v;
		const char *text;
	} cases[] = {
		{0.0, "0"},
		{-0.0, "-0"},
		{1.0, "1"},
		{-1.5, "-1.5"},
		{0.1, "0.1"},
		{0.3, "0.3"},
		{0.1 + 0.2, "0.30000000000000004"},
		{1.0 / 3.0, "0.3333333333333333"},
		{0.001, "0.001"},
		{0.0001, "0.0001"},
		{1e-5, "1e-05"},
		{-1.25e-7, "-1.25e-07"},
		{123456.0, "123456"},
		{12345.678, "12345.678"},
		{100.0, "100"},
		{1e16, "10000000000000000"},
		{1e17, "1e+17"},
		{1.5e17, "1.5e+17"},
		{9007199254740992.0, "9007199254740992"},
		{9007199254740994.0, "9007199254740994"},
		{1e21, "1e+21"},
		{1e22, "1e+22"},
		{1e23, "1e+23"},
		{1e100, "1e+100"},
		{1.2345678901234567e300, "1.2345678901234567e+300"},
		{DBL_MAX, "1.7976931348623157e+308"},
		{-DBL_MAX, "-1.7976931348623157e+308"},
		{DBL_MIN, "2.2250738585072014e-308"},
		{DBL_TRUE_MIN, "5e-324"},
		{-DBL_TRUE_MIN, "-5e-324"},
		{2 * DBL_TRUE_MIN, "1e-323"},
		{3 * DBL_TRUE_MIN, "1.5e-323"},
		{1e-320, "1e-320"},
		{DBL_MIN - DBL_TRUE_MIN, "2.225073858507201e-308"},
		{DBL_EPSILON, "2.220446049250313e-16"},
		{1.0 + DBL_EPSILON, "1.0000000000000002"},
		{5e-324 * 1e0, "5e-324"},
		{HUGE_VAL, "inf"},
		{-HUGE_VAL, "-inf"},
		{(double)NAN, "nan"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		char buf[POPC_DOUBLE_TEXT_MAX + 1];
		size_t n = popc_format_double(cases[i].v, buf);
		if (strcmp(buf, cases[i].text) != 0 || n != strlen(buf)) {
			print_error("format(%.17g) = \"%s\" (%zu), want \"%s\"\n", cases[i].v, buf, n,
				    cases[i].text);
			fail();
		}
		if (isfinite(cases[i].v))
			expect_same_bits(parse_all(buf), cases[i].v, buf);
	}
}

/* Powers of ten: 1e-323 .. 1e308 read as glibc reads them, and write back as
 * one digit in the %g layout. */
static void test_powers_of_ten(void **state)
{
	(void)state;
	for (int k = -323; k <= 308; k++) {
		char text[64], want[64], buf[POPC_DOUBLE_TEXT_MAX + 1];
		snprintf(text, sizeof text, "1e%d", k);
		double v = strtod(text, NULL);
		expect_same_bits(parse_all(text), v, text);
		popc_format_double(v, buf);
		if (k >= -4 && k < 17) {
			if (k < 0) {
				snprintf(want, sizeof want, "0.%0*d", -k, 1);
			} else {
				want[0] = '1';
				memset(want + 1, '0', (size_t)k);
				want[k + 1] = '\0';
			}
		} else {
			snprintf(want, sizeof want, "1e%+03d", k);
		}
		if (strcmp(buf, want) != 0) {
			print_error("format(%s) = \"%s\", want \"%s\"\n", text, buf, want);
			fail();
		}
	}
}

/* 2^-1075 (the midpoint between 0 and DBL_TRUE_MIN) in full. */
static const char half_true_min[] =
	"2.4703282292062327208828439643411068618252990130716238221279284125033775363510437593264991"
	"818081799618989828234772285886546332835517796989819938739800539093906315035659515570226392"
	"290858392449105184435931802849936536152500319370457678249219365623669863658480757001585769"
	"269903706311928279558551332927834338409351978015531246597263579574622766465272827220056374"
	"006485499977096599470454020828166226237857393450736339007967761930577506740176324673600968"
	"951340535537458516661134223766678604162159680461914467291840300530057530849048765391711386"
	"591646239524912623653881879636239373280423891018672348497668235089863388587925628302755995"
	"657524455507255189313690836254779186948667994968324049705821028513185451396213837722826145"
	"437693412532098591327667236328125e-324";

static void test_parse_table(void **state)
{
	(void)state;
	static const struct {
		const char *text;
		double want;
	} cases[] = {
		{"0", 0.0},
		{"-0", -0.0},
		{"-0.0e-10", -0.0},
		{"+1", 1.0},
		{".5", 0.5},
		{"5.", 5.0},
		{"0.1", 0.1},
		{"0.3", 0.3},
		{"1e-400", 0.0},
		{"-1e-400", -0.0},
		{"1e400", HUGE_VAL},
		{"-1e400", -HUGE_VAL},
		{"1e99999999999999999999999", HUGE_VAL},
		{"1e-99999999999999999999999", 0.0},
		{"0e99999", 0.0},
		{"9007199254740993", 9007199254740992.0},          /* 2^53 + 1: tie, to even */
		{"9007199254740995", 9007199254740996.0},          /* tie, to even (up) */
		{"9007199254740993.0000000000000001", 9007199254740994.0}, /* just above the tie */
		{"9007199254740992.9999999999999999", 9007199254740992.0}, /* just below */
		{"2.2250738585072011e-308", 2.2250738585072011e-308}, /* the PHP/Java hang value */
		{"2.2250738585072012e-308", DBL_MIN},
		{"2.2250738585072014e-308", DBL_MIN},
		{"4.9406564584124654e-324", DBL_TRUE_MIN},
		{"5e-324", DBL_TRUE_MIN},
		{"2.4703282292062327e-324", 0.0},
		{"2.4703282292062328e-324", DBL_TRUE_MIN},
		{"1.7976931348623157e308", DBL_MAX},
		{"1.7976931348623158e308", DBL_MAX},
		{"1.7976931348623159e308", HUGE_VAL},
		{"0.1000000000000000055511151231257827021181583404541015625", 0.1},
		{"0.30000000000000000000000000000000000001", 0.3},
		{"123456789012345678901234567890", 123456789012345678901234567890.0},
		{"0000000000000000000000000000000000001", 1.0},
		{"0.000000000000000000000000000000000000000001e42", 1.0},
		{"1.00000000000000011102230246251565404236316680908203125", 1.0}, /* tie */
		{"1.00000000000000011102230246251565404236316680908203126", 1.0 + DBL_EPSILON},
		{"1.00000000000000033306690738754696212708950042724609375", 1.0 + 2 * DBL_EPSILON},
		{"179769313486231580793728971405303415079934132710037826936173778980444968292764750946649"
		 "017977587207096330286416692887910946555547851940402630657488671505820681908902000708383"
		 "676273854845817711531764475730270069855571366959622842914819860834936475292719074168444"
		 "365510704342711559699508093042880177904174497791.9999999999999999999999999999999999",
		 DBL_MAX}, /* just below the overflow threshold */
		{"179769313486231580793728971405303415079934132710037826936173778980444968292764750946649"
		 "017977587207096330286416692887910946555547851940402630657488671505820681908902000708383"
		 "676273854845817711531764475730270069855571366959622842914819860834936475292719074168444"
		 "365510704342711559699508093042880177904174497792",
		 HUGE_VAL}, /* exactly DBL_MAX + ulp/2: ties to even, which is infinity */
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		expect_same_bits(parse_all(cases[i].text), cases[i].want, cases[i].text);
		/* glibc's strtod is correctly rounded: the table must agree. */
		expect_same_bits(strtod(cases[i].text, NULL), cases[i].want, cases[i].text);
	}

	/* The exact midpoint 2^-1075 rounds to even (0); a hair above to 5e-324;
	 * and a long run of digits beyond 800 still counts. */
	char buf[2048];
	expect_same_bits(parse_all(half_true_min), 0.0, "2^-1075");
	snprintf(buf, sizeof buf, "%.*s1e-324", (int)(sizeof half_true_min - 1 - 5), half_true_min);
	expect_same_bits(parse_all(buf), DBL_TRUE_MIN, "2^-1075 + tiny");
	snprintf(buf, sizeof buf, "%.*s%01000de-324", (int)(sizeof half_true_min - 1 - 5),
		 half_true_min, 1);
	expect_same_bits(parse_all(buf), DBL_TRUE_MIN, "2^-1075 + 10^-(1800 + 324)");
	snprintf(buf, sizeof buf, "%.*s%01000de-324", (int)(sizeof half_true_min - 1 - 5),
		 half_true_min, 0);
	expect_same_bits(parse_all(buf), 0.0, "2^-1075 with 1000 zeros");

	/* Subnormals, the smallest normal and their neighbours, via %.17g text. */
	for (uint64_t b = 0; b < 4096; b++) {
		uint64_t patterns[] = {b, (UINT64_C(1) << 52) - 2048 + b, (UINT64_C(0x7ff) << 52) - 1 - b};
		for (size_t j = 0; j < 3; j++) {
			double v = double_of(patterns[j]);
			char t[64];
			snprintf(t, sizeof t, "%.17g", v);
			expect_same_bits(parse_all(t), v, t);
		}
	}
}

static void test_parse_syntax(void **state)
{
	(void)state;
	static const struct {
		const char *text;
		size_t used;
		double want;
	} cases[] = {
		{"", 0, 0.0},      {"-", 0, 0.0},       {"+", 0, 0.0},       {".", 0, 0.0},
		{"-.", 0, 0.0},    {"e5", 0, 0.0},      {" 1", 0, 0.0},      {"nan", 0, 0.0},
		{"inf", 0, 0.0},   {"0x10", 1, 0.0},    {"1e", 1, 1.0},      {"1e+", 1, 1.0},
		{"1e-x", 1, 1.0},  {"1.5x", 3, 1.5},    {"1.5e3,", 5, 1500.0}, {"2E-2\n", 4, 0.02},
		{"-7,8", 2, -7.0}, {"1..2", 2, 1.0},    {"12.5.3", 4, 12.5}, {"1e+05;", 5, 1e5},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		double v = -123.0;
		const char *s = cases[i].text;
		size_t used = popc_parse_double(s, s + strlen(s), &v);
		if (used != cases[i].used) {
			print_error("parse(\"%s\") consumed %zu, want %zu\n", s, used, cases[i].used);
			fail();
		}
		if (used)
			expect_same_bits(v, cases[i].want, s);
		else
			expect_same_bits(v, -123.0, s); /* untouched on failure */
	}
	/* The end pointer bounds the text even without a NUL, also for the
	 * 8-digits-at-a-time loop. */
	const char *s = "123456.789012345678e5";
	double v;
	assert_int_equal(popc_parse_double(s, s + 3, &v), 3);
	expect_same_bits(v, 123.0, "bounded 123");
	for (size_t n = 8; n <= strlen(s); n++) {
		char copy[64];
		memcpy(copy, s, n);
		copy[n] = '\0';
		size_t used = popc_parse_double(s, s + n, &v);
		double want = strtod(copy, NULL);
		if (copy[n - 1] == 'e')
			assert_int_equal(used, n - 1);
		else
			assert_int_equal(used, n);
		expect_same_bits(v, want, copy);
	}
}

/* ---- (b) round trips ----------------------------------------------------- */

/* Every finite random bit pattern: format, parse back, same bits; glibc's
 * strtod must read our text to the same bits too. Where the shortest form has
 * 17 digits it must be exactly what printf("%.17g") writes. */
static void test_round_trip_random_bits(void **state)
{
	(void)state;
	rng_seed(UINT64_C(0x9e3779b97f4a7c15));
	long n = iterations(), checked = 0;
	for (long i = 0; i < n; i++) {
		uint64_t b = rng();
		/* A quarter of the draws near the extremes of the exponent range. */
		if ((i & 3) == 0)
			b = (b & UINT64_C(0x800fffffffffffff)) |
			    ((uint64_t)((b >> 52) & 1 ? 2046 - (rng() & 15) : (rng() & 15)) << 52);
		double v = double_of(b);
		if (!isfinite(v))
			continue;
		char buf[POPC_DOUBLE_TEXT_MAX + 1];
		size_t len = popc_format_double(v, buf);
		if (len > POPC_DOUBLE_TEXT_MAX || len != strlen(buf)) {
			print_error("format(%.17g): bad length %zu\n", v, len);
			fail();
		}
		expect_same_bits(parse_all(buf), v, buf);
		if ((i & 7) == 0) {
			expect_same_bits(strtod(buf, NULL), v, buf);
			if (significant_digits(buf) == 17) {
				char ref[64];
				snprintf(ref, sizeof ref, "%.17g", v);
				if (strcmp(ref, buf) != 0) {
					print_error("format(%s) = \"%s\" differs from %%.17g\n", ref, buf);
					fail();
				}
			}
		}
		checked++;
	}
	assert_true(checked > n / 2);
}

/* "Nice" decimals as a logger sees them (m * 10^e with up to 15 digits): the
 * output is that decimal, digit for digit. */
static void test_round_trip_nice_decimals(void **state)
{
	(void)state;
	rng_seed(12345);
	long n = iterations() / 4;
	for (long i = 0; i < n; i++) {
		int nd = 1 + (int)(rng() % 15);
		uint64_t m = rng() % UINT64_C(1000000000000000);
		uint64_t lim = 1;
		for (int j = 0; j < nd; j++)
			lim *= 10;
		m %= lim;
		int e = (int)(rng() % 61) - 30 - nd;
		if (i % 5 == 0)
			e = (int)(rng() % 600) - 300 - nd;
		char text[64], buf[POPC_DOUBLE_TEXT_MAX + 1];
		snprintf(text, sizeof text, "%s%llue%d", (rng() & 1) ? "-" : "",
			 (unsigned long long)m, e);
		double v = strtod(text, NULL);
		expect_same_bits(parse_all(text), v, text);
		popc_format_double(v, buf);
		expect_same_bits(parse_all(buf), v, buf);
		if (m == 0 || v == 0.0 || !isnormal(v))
			continue;
		char d1[64], d2[64];
		int x1, x2;
		decompose(text, d1, &x1);
		decompose(buf, d2, &x2);
		if (strcmp(d1, d2) != 0 || x1 != x2) {
			print_error("\"%s\" formatted as \"%s\"\n", text, buf);
			fail();
		}
	}
}

/* ---- (c) agreement with glibc's strtod ----------------------------------- */

/* Random decimal text: 1..40 digits (mostly up to 25) with a point somewhere,
 * sometimes leading zeros, and an exponent anywhere from -360 to 360. */
static size_t random_decimal(char *t)
{
	char *p = t;
	if (rng() & 1)
		*p++ = '-';
	uint64_t r = rng();
	int nd = (r & 7) == 0 ? 1 + (int)((r >> 3) % 40) : 1 + (int)((r >> 3) % 25);
	int point = (int)((r >> 9) % (unsigned)(nd + 1));
	int zeros = (r >> 16) % 8 == 0 ? (int)((r >> 19) % 30) : 0;
	for (int i = 0; i < zeros; i++)
		*p++ = '0';
	for (int i = 0; i < nd; i++) {
		if (i == point)
			*p++ = '.';
		*p++ = (char)('0' + rng() % 10);
	}
	int range = (r >> 24) % 4 == 0 ? 721 : 41;
	int e = (int)((r >> 26) % (unsigned)range) - range / 2;
	if ((r >> 40) % 8)
		p += sprintf(p, "e%d", e);
	*p = '\0';
	return (size_t)(p - t);
}

static void test_parse_matches_strtod_random(void **state)
{
	(void)state;
	rng_seed(777);
	long n = iterations();
	for (long i = 0; i < n; i++) {
		char t[128];
		size_t len = random_decimal(t);
		double v;
		size_t used = popc_parse_double(t, t + len, &v);
		if (used != len) {
			print_error("parse(\"%s\") consumed %zu of %zu\n", t, used, len);
			fail();
		}
		expect_same_bits(v, strtod(t, NULL), t);
	}
}

/* Hard cases: the exact decimal expansion of the midpoint between two
 * neighbouring doubles (computed exactly in long double, printed exactly by
 * glibc), cut to various lengths, with the last digit nudged up or down. These
 * go through the big-integer path. */
static void test_parse_midpoints(void **state)
{
	(void)state;
#if LDBL_MANT_DIG >= 64
	rng_seed(4242);
	long n = iterations() / 100;
	static char t[1200];
	for (long i = 0; i < n; i++) {
		uint64_t b = rng() & UINT64_C(0x7fffffffffffffff);
		if (i & 1)
			b = (b & UINT64_C(0x800fffffffffffff)) | ((rng() % 4) << 52); /* subnormal-ish */
		double lo = double_of(b), hi = double_of(b + 1);
		if (!isfinite(hi))
			continue;
		long double mid = ((long double)lo + (long double)hi) / 2;
		int len = snprintf(t, sizeof t, "%.800Le", mid);
		assert_true(len > 0 && len < (int)sizeof t);
		/* Mantissa part ends at 'e'. */
		char *e = strchr(t, 'e');
		char expo[16];
		snprintf(expo, sizeof expo, "%s", e);
		int mant_len = (int)(e - t);
		/* Strip trailing zeros: the exact expansion. */
		while (t[mant_len - 1] == '0')
			mant_len--;
		int cuts[] = {mant_len, 18, 19, 20, 21, 25, 40, mant_len - 1};
		for (size_t c = 0; c < sizeof cuts / sizeof cuts[0]; c++) {
			char s[1200];
			int cl = cuts[c] < mant_len ? cuts[c] : mant_len;
			memcpy(s, t, (size_t)cl);
			int tail = (int)(rng() % 3); /* 0: as is, 1: digit 9 appended, 2: last digit -1 */
			if (tail == 1)
				s[cl++] = '9';
			else if (tail == 2 && s[cl - 1] > '0' && s[cl - 1] <= '9')
				s[cl - 1]--;
			strcpy(s + cl, expo);
			expect_same_bits(parse_all(s), strtod(s, NULL), s);
		}
	}
#else
	skip();
#endif
}

/* ---- (d) shortest --------------------------------------------------------- */

/* For a sample of random doubles: with n = our digit count, no decimal with
 * n - 1 digits reads back as v (checked with the nearest one, %.{n-2}e), and
 * when the nearest n-digit decimal reads back, ours is that one. */
static void test_shortest(void **state)
{
	(void)state;
	rng_seed(99);
	long n = iterations() / 20;
	for (long i = 0; i < n; i++) {
		double v;
		if (i & 1) {
			v = double_of(rng() & UINT64_C(0x7fffffffffffffff));
		} else {
			/* Short decimals with noise in the last bits: lengths 1..17. */
			char t[40];
			snprintf(t, sizeof t, "%.*g", 1 + (int)(rng() % 17),
				 double_of((rng() >> 2) | UINT64_C(0x3000000000000000)));
			v = strtod(t, NULL);
			uint64_t b = bits_of(v) + (rng() % 3) - 1;
			v = double_of(b);
		}
		if (!isfinite(v) || v == 0.0)
			continue;
		char buf[POPC_DOUBLE_TEXT_MAX + 1], ref[64];
		popc_format_double(v, buf);
		int nd = significant_digits(buf);
		if (nd > 1) {
			snprintf(ref, sizeof ref, "%.*e", nd - 2, v);
			if (bits_of(strtod(ref, NULL)) == bits_of(v)) {
				print_error("\"%s\" is not shortest: \"%s\" reads back too\n", buf, ref);
				fail();
			}
		}
		snprintf(ref, sizeof ref, "%.*e", nd - 1, v);
		if (bits_of(strtod(ref, NULL)) == bits_of(v)) {
			char d1[64], d2[64];
			int x1, x2;
			decompose(ref, d1, &x1);
			decompose(buf, d2, &x2);
			if (strcmp(d1, d2) != 0 || x1 != x2) {
				print_error("\"%s\" is not the nearest: \"%s\"\n", buf, ref);
				fail();
			}
		}
	}
}

/* The shortest-digit checks of test_shortest for a fixed double. */
static void check_shortest(double v)
{
	char buf[POPC_DOUBLE_TEXT_MAX + 1], ref[64];
	popc_format_double(v, buf);
	expect_same_bits(parse_all(buf), v, buf);
	int nd = significant_digits(buf);
	if (nd > 1) {
		snprintf(ref, sizeof ref, "%.*e", nd - 2, v);
		if (bits_of(strtod(ref, NULL)) == bits_of(v)) {
			print_error("\"%s\" is not shortest: \"%s\" reads back too\n", buf, ref);
			fail();
		}
	}
}

/* Where the rounding interval is widest relative to the value (the smallest
 * subnormals) or asymmetric (the bottom of every binade). */
static void test_shortest_subnormals_and_binades(void **state)
{
	(void)state;
	for (uint64_t t = 1; t <= 200000; t++)
		check_shortest(double_of(t));
	for (uint64_t e = 1; e < 0x7ff; e++)
		for (uint64_t d = 0; d < 3; d++) {
			check_shortest(double_of((e << 52) + d));
			check_shortest(double_of((e << 52) - 1 - d));
		}
}

/* popc_format_double_point: the table of layouts, and on random bits the
 * shortest form's digits with one '.', reading back to the same double. */
static void test_format_point(void **state)
{
	(void)state;
	static const struct {
		double v;
		const char *text;
	} table[] = {
		{0.0, "0.0"},	    {-0.0, "-0.0"},	   {5.0, "5.0"},	{-1000.0, "-1000.0"},
		{0.5, "0.5"},	    {-1.5, "-1.5"},	   {1e-5, "1.0e-05"},	{1e17, "1.0e+17"},
		{1.5e17, "1.5e+17"}, {5e-324, "5.0e-324"}, {1e-4, "0.0001"},	{123456.0, "123456.0"},
		{-2.2250738585072014e-308, "-2.2250738585072014e-308"},
		{9007199254740993.0, "9007199254740992.0"},
	};
	for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
		char buf[POPC_DOUBLE_TEXT_MAX + 1];
		size_t n = popc_format_double_point(table[i].v, buf);
		if (n != strlen(buf) || strcmp(buf, table[i].text) != 0) {
			print_error("format_point(%.17g) = \"%s\" (%zu), want \"%s\"\n", table[i].v, buf,
				    n, table[i].text);
			fail();
		}
	}
	char buf[POPC_DOUBLE_TEXT_MAX + 1];
	popc_format_double_point((double)NAN, buf);
	assert_string_equal(buf, "nan");
	popc_format_double_point(-(double)INFINITY, buf);
	assert_string_equal(buf, "-inf");

	rng_seed(UINT64_C(0x243f6a8885a308d3));
	long n = iterations() / 8;
	for (long i = 0; i < n; i++) {
		uint64_t b = rng();
		if ((i & 1) == 0) /* half of them integers below 2^53, as counts of a step */
			b = bits_of((double)(int64_t)(b >> (11 + (rng() & 31))) * ((i & 2) ? 1 : -1));
		double v = double_of(b);
		if (!isfinite(v))
			continue;
		char shortest[POPC_DOUBLE_TEXT_MAX + 1], point[POPC_DOUBLE_TEXT_MAX + 3];
		size_t ns = popc_format_double(v, shortest);
		size_t np = popc_format_double_point(v, point);
		const char *dot = strchr(point, '.');
		if (np > POPC_DOUBLE_TEXT_MAX || !dot || strchr(dot + 1, '.') ||
		    np != ns + (strchr(shortest, '.') ? 0u : 2u)) {
			print_error("format_point(%s) = \"%s\"\n", shortest, point);
			fail();
		}
		expect_same_bits(parse_all(point), v, point);
	}
}

/* An independent layout of the shortest form: the digits of the first
 * "%.{p}e" (p = 0, 1, ...) that strtod reads back to v, laid out by the
 * rules of numfmt.h (plain for a decimal exponent in [-4, 17), else
 * d.ddde+XX), with point's ".0" where there is no point. At the bottom of a
 * binade the nearest p-digit decimal can miss the interval's narrow lower
 * half while another p-digit one is in it, so the caller skips those (the
 * shortest checks above cover them). */
static void reference_layout(double v, int point, char *out)
{
	char e_text[64];
	for (int p = 0; p <= 16; p++) {
		snprintf(e_text, sizeof e_text, "%.*e", p, v);
		if (bits_of(strtod(e_text, NULL)) == bits_of(v))
			break;
	}
	char digits[32];
	int x;
	decompose(e_text, digits, &x);
	int n = (int)strlen(digits);
	char *o = out;
	if (signbit(v))
		*o++ = '-';
	if (x >= -4 && x < 17) {
		if (x < 0) {
			o += sprintf(o, "0.");
			for (int i = 0; i < -x - 1; i++)
				*o++ = '0';
			o += sprintf(o, "%s", digits);
		} else {
			for (int i = 0; i <= x || i < n; i++) {
				if (i == x + 1)
					*o++ = '.';
				*o++ = i < n ? digits[i] : '0';
			}
			if (x >= n - 1 && point)
				o += sprintf(o, ".0");
		}
	} else {
		*o++ = digits[0];
		if (n > 1)
			o += sprintf(o, ".%s", digits + 1);
		else if (point)
			o += sprintf(o, ".0");
		o += sprintf(o, "e%c%02d", x < 0 ? '-' : '+', x < 0 ? -x : x);
	}
	*o = '\0';
}

static void expect_layout(double v)
{
	char ref[64], buf[POPC_DOUBLE_TEXT_MAX + 1];
	for (int point = 0; point <= 1; point++) {
		reference_layout(v, point, ref);
		size_t n = point ? popc_format_double_point(v, buf) : popc_format_double(v, buf);
		if (n != strlen(ref) || strcmp(buf, ref) != 0) {
			print_error("format%s(%.17g) = \"%s\", want \"%s\"\n", point ? "_point" : "", v,
				    buf, ref);
			fail();
		}
	}
}

/* The whole text against reference_layout: random bit patterns, short
 * decimals at every decimal exponent from -330 to 310 with 1 to 17 digits
 * (every layout branch and every place of the point), and integers whose
 * 4-digit groups take every value 0..9999 (write_decimal makes 8 digits at
 * a time in lanes of 4, 2 and 1 digit: each lane sees all its values). */
static void test_layout_reference(void **state)
{
	(void)state;
	rng_seed(UINT64_C(0x6a09e667f3bcc908));
	long n = iterations() / 20;
	for (long i = 0; i < n; i++) {
		double v = double_of(rng());
		if (isfinite(v) && (bits_of(v) & UINT64_C(0x000fffffffffffff)) != 0)
			expect_layout(v);
	}
	for (int x = -330; x <= 310; x++)
		for (int nd = 1; nd <= 17; nd++) {
			char t[64];
			uint64_t m = rng() % UINT64_C(100000000000000000);
			snprintf(t, sizeof t, "%s%.*e", (rng() & 1) ? "-" : "", nd - 1,
				 (double)(m | 1) / 1e17 * 9.0 + 1.0);
			char *e = strchr(t, 'e');
			snprintf(e, 16, "e%d", x);
			double v = strtod(t, NULL);
			if (isfinite(v) && v != 0.0 && (bits_of(v) & UINT64_C(0x000fffffffffffff)) != 0)
				expect_layout(v);
		}
	for (uint64_t h = 0; h < 10000; h++) {
		uint64_t l = (h * 7919) % 10000;
		uint64_t y = h * 10000 + l, z = l * 10000 + h; /* each < 10^8 */
		/* integers below 2^53 ~ 9.007e15, exact as doubles */
		double ints[] = {(double)y, -(double)(z * 10000000 + y), (double)(z * 1000 + 7),
				 (double)((h < 9000 ? y : z % 90000000) * 100000000 + z)};
		for (size_t k = 0; k < sizeof ints / sizeof ints[0]; k++) {
			char ref[64], buf[POPC_DOUBLE_TEXT_MAX + 1];
			snprintf(ref, sizeof ref, "%.0f", ints[k]); /* exact below 2^53 */
			popc_format_double(ints[k], buf);
			if (strcmp(buf, ref) != 0) {
				print_error("format(%s) = \"%s\"\n", ref, buf);
				fail();
			}
		}
	}
}

/* ---- (e) the digit scanner's own paths ----------------------------------- */

/* %.17g texts of random doubles (the form a C logger writes), and the same
 * digits behind runs of zeros (0.000ddd, 000ddd.d, d.ddd000...): the scanner
 * reads digits 8 at a time with a partial last step and skips zero runs 8 at
 * a time, so every length and alignment must agree with strtod bitwise. */
static void test_parse_digit_runs(void **state)
{
	(void)state;
	rng_seed(UINT64_C(0x5deece66d));
	long n = iterations() / 4;
	for (long i = 0; i < n; i++) {
		uint64_t b = rng();
		if (i & 1) /* magnitudes of a log's cells, 1e-12 to 1e6 */
			b = (b & UINT64_C(0x800fffffffffffff)) | ((uint64_t)(983 + rng() % 63) << 52);
		double v = double_of(b);
		if (!isfinite(v))
			continue;
		char t[600];
		int len = snprintf(t, sizeof t, "%.17g", v);
		size_t used;
		double got;
		if ((used = popc_parse_double(t, t + len, &got)) != (size_t)len) {
			print_error("parse(\"%s\") consumed %zu of %d\n", t, used, len);
			fail();
		}
		expect_same_bits(got, v, t);
		/* the 17 significant digits behind zeros, before a point or after */
		char digits[32];
		snprintf(digits, sizeof digits, "%017llu",
			 (unsigned long long)(rng() % UINT64_C(100000000000000000)));
		int zeros = (int)(rng() % 40), trail = (int)(rng() % 24), form = (int)(rng() % 4);
		char *p = t;
		if (rng() & 1)
			*p++ = '-';
		if (form == 0) { /* 0.000ddd */
			p += sprintf(p, "0.");
			memset(p, '0', (size_t)zeros), p += zeros;
			p += sprintf(p, "%s", digits);
		} else if (form == 1) { /* 000ddd.ddd000 */
			memset(p, '0', (size_t)zeros), p += zeros;
			p += sprintf(p, "%.9s.%s", digits, digits + 9);
			memset(p, '0', (size_t)trail), p += trail;
		} else if (form == 2) { /* .000ddd000e-X */
			*p++ = '.';
			memset(p, '0', (size_t)zeros), p += zeros;
			p += sprintf(p, "%s", digits);
			memset(p, '0', (size_t)trail), p += trail;
			p += sprintf(p, "e-%d", (int)(rng() % 330));
		} else { /* ddd000.000e+X: zeros on both sides of the point */
			p += sprintf(p, "%s", digits);
			memset(p, '0', (size_t)trail), p += trail;
			*p++ = '.';
			memset(p, '0', (size_t)zeros), p += zeros;
			p += sprintf(p, "e+%d", (int)(rng() % 300));
		}
		*p = '\0';
		expect_same_bits(parse_all(t), strtod(t, NULL), t);
	}
	/* An integer part of more than 19 digits wraps the digit accumulator
	 * modulo 2^64, to 0 for 2^64 itself: the count of significant digits
	 * must not take such a part for zeros. */
	const char *wrap[] = {
		"18446744073709551616",      "18446744073709551616.0000001",
		"36893488147419103232.00012", "18446744073709551616e-10",
		"00000000000000000000000018446744073709551616.5",
		"0.00000000000000000000000000000000000000001",
		"0000000000000000000000000.0000000000000000000000001234567890123456789012",
		"9007199254740993",           "9007199254740993.000000000000000000000000001",
		"0.000000000000000000000000000000000000000000000000000000000000000000000000000",
	};
	for (size_t i = 0; i < sizeof wrap / sizeof wrap[0]; i++)
		expect_same_bits(parse_all(wrap[i]), strtod(wrap[i], NULL), wrap[i]);
}

/* popc_parse_double_row against popc_parse_double cell by cell: a row of
 * plain numbers is read whole, bitwise as the cells one by one; a row with
 * any other cell (blank, quote, text after a number, inf, an underflow, a NUL
 * byte, too few or too many cells) stops at or before that cell. */
static void test_parse_row(void **state)
{
	(void)state;
	rng_seed(99);
	const char delims[] = {',', ';', '\t', '|'};
	const char *odd[] = {" 1", "1 ", "\"1\"", "1x", "1e", "inf", "1e400", "-1e999",
			     "1e-400", "0.0000001e-330", "", "-", ".", "nan", "1,5", "\0011" /* 0x01 '1' */};
	long n = iterations() / 20;
	for (long i = 0; i < n; i++) {
		const char delim = delims[rng() % 4];
		const int cells = 1 + (int)(rng() % 14);
		char row[1024];
		char *p = row;
		double want[16];
		int bad = -1; /* the first cell that is no plain number */
		int shifted = 0;
		for (int c = 0; c < cells; c++) {
			if (c)
				*p++ = delim;
			char *cell = p;
			if (rng() % 16 == 0) {
				const char *o = odd[rng() % (sizeof odd / sizeof odd[0])];
				p += sprintf(p, "%s", o);
				/* with a delimiter inside ("1,5" split at ',') the
				 * cells shift: two numbers, maybe a whole row */
				shifted |= strchr(o, delim) != NULL;
				if (bad < 0)
					bad = c;
				continue;
			}
			uint64_t b = rng();
			if (rng() & 1)
				b = (b & UINT64_C(0x800fffffffffffff)) | ((uint64_t)(983 + rng() % 63) << 52);
			double v = double_of(b);
			if (!isfinite(v))
				v = 0.0;
			if (rng() & 1)
				popc_format_double(v, cell);
			else
				sprintf(cell, "%.17g", v);
			p += strlen(cell);
			want[c] = strtod(cell, NULL);
		}
		*p = '\0';
		/* sometimes a NUL byte inside the row, or a row one cell short or
		 * long */
		int shape = (int)(rng() % 8), n_read = cells;
		size_t len = (size_t)(p - row);
		if (shape == 0 && len > 1) {
			size_t at = rng() % len;
			int cell = 0; /* the cell it falls in (or ends, for a delimiter) */
			for (size_t k = 0; k < at; k++)
				cell += row[k] == delim;
			row[at] = '\0';
			bad = bad < 0 || cell < bad ? cell : bad;
		} else if (shape == 1) {
			n_read = cells + 1;
			bad = bad < 0 ? cells : bad;
		} else if (shape == 2 && cells > 1) {
			n_read = cells - 1;
			bad = bad < 0 ? cells - 1 : bad;
		}
		double got[16];
		int ok = popc_parse_double_row(row, row + len, delim, got, n_read);
		if (bad < 0) {
			if (ok != n_read) {
				print_error("row \"%s\": %d of %d cells\n", row, ok, n_read);
				fail();
			}
			for (int c = 0; c < cells; c++)
				expect_same_bits(got[c], want[c], row);
		} else {
			if (!shifted && (ok == n_read || ok > bad)) {
				print_error("row \"%.200s\" (cell %d is odd, shape %d): %d of %d cells\n",
					    row, bad, shape, ok, n_read);
				fail();
			}
			for (int c = 0; c < ok && c < bad; c++)
				expect_same_bits(got[c], want[c], row);
		}
	}
	/* a delimiter that can stand in a number is refused */
	double v[2];
	const char e_row[] = "1e5e2", point_row[] = "1.5", comma_row[] = "1,5";
	assert_int_equal(popc_parse_double_row(e_row, e_row + 5, 'e', v, 2), 0);
	assert_int_equal(popc_parse_double_row(point_row, point_row + 3, '.', v, 2), 0);
	assert_int_equal(popc_parse_double_row(comma_row, comma_row + 3, ',', v, 2), 2);
	assert_true(v[0] == 1.0 && v[1] == 5.0);
}

/* popc_parse_double_line_skip with memos and no skip against popc_parse_double_line without memos,
 * line after line of one text: the same count, the same line end and the same
 * bits for every cell, while the memos hit. The cells come from small pools
 * per column so that most repeat the cell above, among them cells that share
 * a prefix or differ only in their last byte, their sign or their terminator
 * (the last column's "\n" against "\r\n"), cells longer than the memo's 32
 * bytes, odd cells (an underflow, an infinity, text after a number, a NUL
 * byte) and lines the text's end cuts. */
static void test_parse_line_memo(void **state)
{
	(void)state;
	rng_seed(2323);
	static const char *pool[] = {
		"1.5", "1.55", "1.5e1", "-1.5", "15", "1.50", "0.00012345678901234567",
		"0.00012345678901234568", "-0.00012345678901234567", "1234567.125",
		"0.0000000000000000000000012345678901234567",   /* 42 bytes: beyond the memo */
		"0.00000000000000000000012345678901234567",     /* 40 */
		"123456789012345678901234567890.5",              /* 32: the cell and its terminator are 33 */
		"12345678901234567890123456789.5",               /* 31: 32 with its terminator */
		"0", "-0", "0.0", "4", "1e-400", "1e400", "1.5x", "2\0012", "",
	};
	const size_t n_pool = sizeof pool / sizeof pool[0];
	const char delims[] = {',', ';', '\t'};
	long hits = 0;
	for (int round = 0; round < 40; round++) {
		const char delim = delims[round % 3];
		const int cells = 1 + (int)(rng() % 12);
		size_t sub[12]; /* each column's own few cells (a quantized signal) */
		for (int c = 0; c < cells; c++)
			sub[c] = rng() % 18; /* a good cell; the odd ones (18 on) come rarely */
		static char text[1 << 16];
		size_t len = 0;
		while (len < sizeof text - 1024) {
			for (int c = 0; c < cells; c++) {
				if (c)
					text[len++] = delim;
				size_t k = rng() % 8 == 0 ? rng() % n_pool : (sub[c] + rng() % 3 / 2) % n_pool;
				const size_t cl = k == 21 ? 3 : strlen(pool[k]); /* "2\0012" holds a NUL */
				memcpy(text + len, pool[k], cl);
				len += cl;
			}
			if (rng() % 4 == 0)
				text[len++] = '\r';
			text[len++] = '\n';
		}
		popc_parse_memo memo[12];
		memset(memo, 0, sizeof memo);
		for (size_t at = 0; at < len;) {
			/* the text's end at most a few bytes past the line's, sometimes
			 * before it, so that memos near the end and cut lines are met */
			const char *nl = memchr(text + at, '\n', len - at);
			size_t end = rng() % 3 ? len : (size_t)(nl - text) + 1 - rng() % 3;
			if (end <= at)
				end = len;
			double want[12], got[12];
			const char *want_end = NULL, *got_end = NULL;
			int w = popc_parse_double_line(text + at, text + end, delim, want, cells, &want_end);
			popc_parse_memo had[12]; /* a memo the line leaves as it was: a hit */
			memcpy(had, memo, sizeof had);
			int g = popc_parse_double_line_skip(text + at, text + end, delim, got, cells,
							    &got_end, memo, NULL);
			if (g != w || (w == cells && got_end != want_end)) {
				print_error("line at %zu (delimiter %d, %d cells): %d cells with memos, %d "
					    "without\n",
					    at, delim, cells, g, w);
				fail();
			}
			for (int c = 0; c < w; c++) {
				expect_same_bits(got[c], want[c], text + at);
				hits += had[c].len && memcmp(&had[c], &memo[c], sizeof had[c]) == 0;
			}
			at = (size_t)(nl - text) + 1;
		}
	}
	assert_true(hits > 20000); /* the memos were used */
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_format_table),
		cmocka_unit_test(test_powers_of_ten),
		cmocka_unit_test(test_parse_table),
		cmocka_unit_test(test_parse_syntax),
		cmocka_unit_test(test_round_trip_random_bits),
		cmocka_unit_test(test_round_trip_nice_decimals),
		cmocka_unit_test(test_parse_matches_strtod_random),
		cmocka_unit_test(test_parse_midpoints),
		cmocka_unit_test(test_shortest),
		cmocka_unit_test(test_shortest_subnormals_and_binades),
		cmocka_unit_test(test_format_point),
		cmocka_unit_test(test_layout_reference),
		cmocka_unit_test(test_parse_digit_runs),
		cmocka_unit_test(test_parse_row),
		cmocka_unit_test(test_parse_line_memo),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
