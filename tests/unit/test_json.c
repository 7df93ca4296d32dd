/* Tests for json.h: RFC 8259 string escaping (every control character, the
 * quote and backslash, UTF-8 passed through, invalid UTF-8 as U+FFFD),
 * numbers (shortest round trip, null for NaN and infinities), nesting, and
 * CSV rows as objects (kinds, empty cells, quoted cells, short rows). The
 * same output parsed by python3's json module: tests/cli/test_json.sh. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/util/json.h"

/* What fn writes, as a string the caller frees. */
static char *capture(void (*fn)(popc_json *j, const void *arg), const void *arg)
{
	char *text = NULL;
	size_t n = 0;
	FILE *f = open_memstream(&text, &n);
	assert_non_null(f);
	popc_json j;
	popc_json_init(&j, f);
	fn(&j, arg);
	assert_int_equal(fclose(f), 0);
	return text;
}

typedef struct bytes {
	const char *s;
	size_t n;
} bytes;

static void write_string(popc_json *j, const void *arg)
{
	const bytes *b = arg;
	popc_json_string(j, b->s, b->n);
}

static void test_strings(void **state)
{
	(void)state;
	static const struct {
		bytes in;
		const char *out;
	} table[] = {
		{{"", 0}, "\"\""},
		{{"plain", 5}, "\"plain\""},
		{{"a\"b\\c/d", 7}, "\"a\\\"b\\\\c/d\""},
		{{"\b\f\n\r\t", 5}, "\"\\b\\f\\n\\r\\t\""},
		{{"\x00\x01\x0b\x1f\x7f", 5}, "\"\\u0000\\u0001\\u000b\\u001f\x7f\""},
		{{"\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80", 11}, "\"\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\""},
		{{"\xff", 1}, "\"\\ufffd\""},                  /* never UTF-8 */
		{{"\xc3", 1}, "\"\\ufffd\""},                  /* cut sequence */
		{{"\xc0\xaf", 2}, "\"\\ufffd\\ufffd\""},       /* overlong '/' */
		{{"\xed\xa0\x80", 3}, "\"\\ufffd\\ufffd\\ufffd\""}, /* a surrogate */
		{{"\xf4\x90\x80\x80", 4}, "\"\\ufffd\\ufffd\\ufffd\\ufffd\""}, /* > U+10FFFF */
	};
	for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
		char *got = capture(write_string, &table[i].in);
		if (strcmp(got, table[i].out) != 0) {
			print_error("case %zu: got %s, want %s\n", i, got, table[i].out);
			fail();
		}
		free(got);
	}
	/* every control character escaped, every other ASCII byte itself */
	for (int c = 1; c < 0x80; c++) {
		char in = (char)c;
		bytes b = {&in, 1};
		char *got = capture(write_string, &b);
		if (c < 0x20)
			assert_true(got[1] == '\\' && strlen(got) >= 4);
		else if (c == '"' || c == '\\')
			assert_true(got[1] == '\\' && got[2] == c && strlen(got) == 4);
		else
			assert_true(got[1] == c && strlen(got) == 3);
		free(got);
	}
}

static void write_numbers(popc_json *j, const void *arg)
{
	(void)arg;
	popc_json_begin_array(j);
	popc_json_number(j, 0.0);
	popc_json_number(j, -0.0);
	popc_json_number(j, 0.1);
	popc_json_number(j, 1e-5);
	popc_json_number(j, 1.5e17);
	popc_json_number(j, 5e-324);
	popc_json_number(j, (double)NAN);
	popc_json_number(j, (double)INFINITY);
	popc_json_number(j, -(double)INFINITY);
	popc_json_integer(j, -9007199254740993LL);
	popc_json_null(j);
	popc_json_end_array(j);
}

static void test_numbers(void **state)
{
	(void)state;
	char *got = capture(write_numbers, NULL);
	assert_string_equal(got, "[0,-0,0.1,1e-05,1.5e+17,5e-324,null,null,null,-9007199254740993,null]");
	free(got);
}

static void write_nested(popc_json *j, const void *arg)
{
	(void)arg;
	popc_json_begin_object(j);
	popc_json_key(j, "a");
	popc_json_integer(j, 1);
	popc_json_key(j, "b");
	popc_json_begin_array(j);
	popc_json_begin_object(j);
	popc_json_end_object(j);
	popc_json_cstring(j, "x");
	popc_json_begin_array(j);
	popc_json_end_array(j);
	popc_json_end_array(j);
	popc_json_key(j, "k\"ey");
	popc_json_null(j);
	popc_json_end_object(j);
}

static void test_nesting(void **state)
{
	(void)state;
	char *got = capture(write_nested, NULL);
	assert_string_equal(got, "{\"a\":1,\"b\":[{},\"x\",[]],\"k\\\"ey\":null}");
	free(got);
}

static char *csv_object(int n, const char *const *names, const popc_json_kind *kinds,
			const char *row)
{
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	assert_non_null(f);
	popc_json_csv_object(f, n, names, kinds, row, strlen(row));
	assert_int_equal(fclose(f), 0);
	/* the keyed writer (names escaped once, for many rows) gives the same bytes */
	char *keys = popc_json_csv_keys(n, names), *keyed = NULL;
	assert_non_null(keys);
	f = open_memstream(&keyed, &len);
	assert_non_null(f);
	popc_json_csv_object_keyed(f, n, keys, kinds, row, strlen(row));
	assert_int_equal(fclose(f), 0);
	if (strcmp(keyed, text) != 0) {
		print_error("keyed: got %s want %s", keyed, text);
		fail();
	}
	free(keys);
	free(keyed);
	return text;
}

static void test_csv_rows(void **state)
{
	(void)state;
	const char *names[] = {"run", "axis", "n", "x"};
	const popc_json_kind kinds[] = {POPC_JSON_TEXT, POPC_JSON_AUTO, POPC_JSON_NUMBER,
					POPC_JSON_NUMBER};
	static const struct {
		const char *row, *out;
	} table[] = {
		{"007,improved,3,0.1\n", "{\"run\":\"007\",\"axis\":\"improved\",\"n\":3,\"x\":0.1}\n"},
		/* a JSON number stays its text; another number text is reformatted */
		{"1,1e-6,-0,.5\n", "{\"run\":\"1\",\"axis\":1e-6,\"n\":-0,\"x\":0.5}\n"},
		{"1,+2,1.,1E+3", "{\"run\":\"1\",\"axis\":2,\"n\":1,\"x\":1E+3}\n"},
		/* a fraction is a JSON number too: its text as given, trailing zeros kept */
		{"6,0.10,2.50e-3,-1.5\n", "{\"run\":\"6\",\"axis\":0.10,\"n\":2.50e-3,\"x\":-1.5}\n"},
		/* empty cells and missing ones are null; not a number in a NUMBER column: null */
		{"2,,,\n", "{\"run\":\"2\",\"axis\":null,\"n\":null,\"x\":null}\n"},
		{"3,a\n", "{\"run\":\"3\",\"axis\":\"a\",\"n\":null,\"x\":null}\n"},
		{"4,inf,nan,x\n", "{\"run\":\"4\",\"axis\":\"inf\",\"n\":null,\"x\":null}\n"},
		/* a number that would read as infinity is no number: a string in an
		 * AUTO column, null in a NUMBER one; the largest finite ones and
		 * underflows to zero stay their text (the grammar alone decides
		 * below 10^308, the text is read above) */
		{"7,1e309,1.7976931348623157e308,1.8e308\n",
		 "{\"run\":\"7\",\"axis\":\"1e309\",\"n\":1.7976931348623157e308,\"x\":null}\n"},
		{"8,-1E+400,9e307,1e-400\n",
		 "{\"run\":\"8\",\"axis\":\"-1E+400\",\"n\":9e307,\"x\":1e-400}\n"},
		/* either side of DBL_MAX's rounding boundary (1.797693134862315807...e308) */
		{"9,17976931348623158e292,0e99999999999,17976931348623159e292\n",
		 "{\"run\":\"9\",\"axis\":17976931348623158e292,\"n\":0e99999999999,\"x\":null}\n"},
		/* 309 integer digits: read to see, finite (DBL_MAX) */
		{"10,17976931348623157000000000000000000000000000000000000000000000000000000000000"
		 "00000000000000000000000000000000000000000000000000000000000000000000000000000000"
		 "00000000000000000000000000000000000000000000000000000000000000000000000000000000"
		 "000000000000000000000000000000000000000000000000000000000000000000000000,1e308,-"
		 "1e-99999999999\n",
		 "{\"run\":\"10\",\"axis\":1797693134862315700000000000000000000000000000000000000"
		 "00000000000000000000000000000000000000000000000000000000000000000000000000000000"
		 "00000000000000000000000000000000000000000000000000000000000000000000000000000000"
		 "00000000000000000000000000000000000000000000000000000000000000000000000000000000"
		 "00000000000000,\"n\":1e308,\"x\":-1e-99999999999}\n"},
		/* RFC 4180 quotes */
		{"\"a,\"\"b\",\"1\",5,6\r\n", "{\"run\":\"a,\\\"b\",\"axis\":1,\"n\":5,\"x\":6}\n"},
		/* more cells than names: ignored */
		{"5,6,7,8,9\n", "{\"run\":\"5\",\"axis\":6,\"n\":7,\"x\":8}\n"},
	};
	for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
		char *got = csv_object(4, names, kinds, table[i].row);
		if (strcmp(got, table[i].out) != 0) {
			print_error("row %zu: got %s want %s", i, got, table[i].out);
			fail();
		}
		free(got);
	}
	/* names that need escapes, in both writers (csv_object compares them) */
	const char *odd[] = {"a\"b", "c\\d\te"};
	char *got = csv_object(2, odd, kinds, "1,x\n");
	assert_string_equal(got, "{\"a\\\"b\":\"1\",\"c\\\\d\\te\":\"x\"}\n");
	free(got);
	char header[] = "run,a.b,n\n";
	const char *split[8];
	assert_int_equal(popc_json_csv_names(header, split, 8), 3);
	assert_string_equal(split[0], "run");
	assert_string_equal(split[1], "a.b");
	assert_string_equal(split[2], "n");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_strings),
		cmocka_unit_test(test_numbers),
		cmocka_unit_test(test_nesting),
		cmocka_unit_test(test_csv_rows),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
