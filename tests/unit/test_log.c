/* CSV log: bitwise round trip writer -> reader, and the reader's errors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/log/log.h"
#include "popc/log/log_reader.h"

#include "test_tmpdir.h"

static int setup(void **state)
{
	(void)state;
	return test_tmpdir_make("log");
}

static int teardown(void **state)
{
	(void)state;
	return test_tmpdir_remove();
}

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static uint64_t next_u64(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return rng;
}

/* A finite double from random bits (every exponent, subnormals, -0 included). */
static double random_double(void)
{
	for (;;) {
		uint64_t b = next_u64();
		double d;
		memcpy(&d, &b, sizeof d);
		if (isfinite(d))
			return d;
	}
}

static int same_bits(double a, double b)
{
	return memcmp(&a, &b, sizeof a) == 0;
}

static void test_round_trip_bitwise(void **state)
{
	(void)state;
	char path[512];
	snprintf(path, sizeof path, "%s/rt.csv", tmpdir);
	popc_scene s;
	popc_scene_defaults(&s);
	popc_log_writer w;
	popc_error err;
	const unsigned cols = POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TIMING;
	assert_int_equal(popc_log_open(&w, path, cols, &err), 0);
	assert_int_equal(popc_log_write_header(&w, "sim", &s, NULL, &err), 0);
	enum { N = 20000 };
	static popc_log_row rows[N];
	const double edge[] = {0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
			       -1.7976931348623157e308, 0.1, 1e-5, 1e22, 1e23, 9007199254740993.0};
	for (int i = 0; i < N; i++) {
		popc_log_row *r = &rows[i];
		r->tick.t_s = i * 1e-3;
		r->tick.x_m = i < 12 ? edge[i] : random_double();
		r->tick.count = (long long)(next_u64() >> 2) * ((i & 1) ? -1 : 1);
		r->x_true_m = random_double();
		r->tick.v_mps = random_double();
		r->tick.f_e_N = random_double();
		r->tick.f_pc_N = random_double();
		r->tick.f_c_N = random_double();
		r->tick.W_J = random_double();
		r->tick.E_ref_J = random_double();
		r->tick.flags = (unsigned)(next_u64() & 31);
		r->dt_s = random_double();
		r->rtt_s = random_double();
		assert_int_equal(popc_log_write_row(&w, r, &err), 0);
	}
	assert_int_equal(popc_log_write_comment(&w, "stop", "completed", &err), 0);
	assert_int_equal(popc_log_close(&w, &err), 0);

	popc_log_reader rd;
	assert_int_equal(popc_log_reader_open(&rd, path, NULL, &err), 0);
	assert_string_equal(popc_log_reader_header(&rd, "source"), "sim");
	assert_string_equal(popc_log_reader_header(&rd, "variant"), "ref-energy");
	assert_true(strtod(popc_log_reader_header(&rd, "encoder.resolution"), NULL) == 1e-5);
	popc_scene back;
	popc_scene_defaults(&back);
	back.enc_resolution_m = 1.0;
	assert_int_equal(popc_log_reader_scene(&rd, &back, &err), 0);
	assert_true(back.enc_resolution_m == 1e-5);
	const char *names[] = {"t", "x", "count", "x_true", "v", "f_e", "f_pc", "f_c", "W", "E_ref", "flags", "dt", "rtt"};
	int idx[13];
	for (int j = 0; j < 13; j++)
		assert_int_equal(popc_log_reader_require(&rd, names[j], &idx[j], &err), 0);
	double v[POPC_LOG_MAX_COLUMNS];
	for (int i = 0; i < N; i++) {
		assert_int_equal(popc_log_reader_next(&rd, v, &err), 1);
		const popc_log_row *r = &rows[i];
		const double want[13] = {r->tick.t_s, r->tick.x_m, 0, r->x_true_m, r->tick.v_mps,
					 r->tick.f_e_N, r->tick.f_pc_N, r->tick.f_c_N, r->tick.W_J,
					 r->tick.E_ref_J, (double)r->tick.flags, r->dt_s, r->rtt_s};
		for (int j = 0; j < 13; j++) {
			if (j == 2)
				continue;
			if (!same_bits(v[idx[j]], want[j]))
				fail_msg("row %d column %s: %.17g read back as %.17g", i, names[j], want[j],
					 v[idx[j]]);
		}
		/* counts are exact as long as they fit 53 bits; 62-bit random counts round
		 * like any double: compare through the same conversion */
		assert_true(same_bits(v[idx[2]], (double)r->tick.count));
	}
	assert_int_equal(popc_log_reader_next(&rd, v, &err), 0);
	assert_string_equal(rd.stop_reason, "completed");
	popc_log_reader_close(&rd);
}

static const char *write_file(const char *name, const char *text)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/%s", tmpdir, name);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(text, f);
	fclose(f);
	return path;
}

/* Reads every row; returns the first error status, with its message. */
static int read_all(const char *path, const popc_log_reader_options *opt, const char *require,
		    popc_error *err)
{
	popc_log_reader r;
	int st = popc_log_reader_open(&r, path, opt, err);
	if (st)
		return st;
	int idx;
	if (require && (st = popc_log_reader_require(&r, require, &idx, err)) != 0) {
		popc_log_reader_close(&r);
		return st;
	}
	double v[POPC_LOG_MAX_COLUMNS];
	while ((st = popc_log_reader_next(&r, v, err)) == 1)
		;
	popc_log_reader_close(&r);
	return st;
}

static void test_reader_errors(void **state)
{
	(void)state;
	const struct {
		const char *text, *require, *must_contain[2];
	} cases[] = {
		{"", NULL, {"empty file", NULL}},
		{"# only\n# comments\n", NULL, {"only comments", NULL}},
		{"t,x\n0,1\n0.001,2\n0.002", NULL, {":4:", "truncated last line"}},
		{"t,x\n0,1\n0.001\n", NULL, {":3:", "short row"}},
		{"t,x\n0,1\n0.001,abc\n", NULL, {":3: column 2 (x)", "not a finite number 'abc'"}},
		{"t,x\n0,1\n0.001,nan\n", NULL, {":3: column 2 (x)", "NaN is not allowed"}},
		{"t,x\n0,1\n0.001,inf\n", NULL, {":3: column 2", NULL}},
		{"t,x\n0,1\n0.001,\n", NULL, {":3: column 2", "empty cell"}},
		{"t,x\n0,1\n0.001,2,3\n", NULL, {":3:", "more than 2 cells"}},
		{"t,x\n0,1\n0,2\n", NULL, {":3: column 1 (t)", "does not increase"}},
		{"t,x\n0,1\n", "f_c", {"missing column 'f_c'", "--column f_c=HEADER"}},
		/* a repeated column name: both columns and the line named */
		{"t,x,x\n0,1,2\n", NULL, {":1: column 3 (x)", "repeats the name of column 2 (line 1)"}},
		{"# a = 1\n\"t\";x;f_c;x\n0;1;2;3\n", NULL, {":2: column 4 (x)", "column 2 (line 2)"}},
		/* a byte order mark is skipped only at the very start of the file */
		{"t,x\n\xEF\xBB\xBF" "0,1\n", NULL, {":2: column 1 (t)", "not a finite number"}},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_file("bad.csv", cases[i].text);
		popc_error err = {{0}};
		int st = read_all(path, NULL, cases[i].require, &err);
		if (st != POPC_ERR_INVALID)
			fail_msg("case %zu: status %d, expected an error", i, st);
		for (int j = 0; j < 2 && cases[i].must_contain[j]; j++)
			if (!strstr(err.msg, cases[i].must_contain[j]))
				fail_msg("case %zu: '%s' lacks '%s'", i, err.msg, cases[i].must_contain[j]);
	}
	popc_error err;
	assert_int_equal(read_all("/nonexistent.csv", NULL, NULL, &err), POPC_ERR_IO);
}

/* A UTF-8 byte order mark (Excel's "CSV UTF-8") before the first line is
 * skipped: before the column names, and before a header comment. */
static void test_reader_bom(void **state)
{
	(void)state;
	const char *texts[] = {"\xEF\xBB\xBFt,x\r\n0,1e-5\r\n0.001,2e-5\r\n",
			       "\xEF\xBB\xBF# variant = none\nt,x\n0,1e-5\n0.001,2e-5\n"};
	for (int i = 0; i < 2; i++) {
		const char *path = write_file("bom.csv", texts[i]);
		popc_log_reader r;
		popc_error err;
		assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
		assert_int_equal(r.n_cols, 2);
		assert_string_equal(r.col_name[0], "t");
		assert_int_equal(popc_log_reader_column(&r, "t"), 0);
		if (i == 1)
			assert_string_equal(popc_log_reader_header(&r, "variant"), "none");
		double v[POPC_LOG_MAX_COLUMNS];
		assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
		assert_true(v[0] == 0.0 && v[1] == 1e-5);
		assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
		assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
		popc_log_reader_close(&r);
	}
}

/* Comments after the rows: a [section] there qualifies the keys after it
 * (it was kept in a 4-byte buffer: "[controller]" made "con.key"), and the
 * header's last section does not swallow the trailing "# stop". */
static void test_reader_trailing_sections(void **state)
{
	(void)state;
	const char *path = write_file("trail.csv", "# [integrator]\n# method = exact\nt,x\n0,1e-5\n"
						  "# [controller]\n# note = kept\n# stop = completed\n");
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	assert_string_equal(popc_log_reader_header(&r, "integrator.method"), "exact");
	double v[POPC_LOG_MAX_COLUMNS];
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
	assert_non_null(popc_log_reader_header(&r, "controller.note"));
	assert_string_equal(popc_log_reader_header(&r, "controller.note"), "kept");
	assert_string_equal(r.stop_reason, "completed");
	popc_log_reader_close(&r);
}

/* A foreign log: other names, another order, ';' and CRLF, a header comment. */
static void test_foreign_log_mapping(void **state)
{
	(void)state;
	const char *path = write_file("dev.csv", "% recorded on a PHANTOM\r\ntime_s;force;pos_m\r\n"
						 "0;0.5;-1e-5\r\n0.001;0.25;2e-5\r\n");
	popc_log_reader_options opt = {.comment = '%'};
	char m1[] = "t=time_s", m2[] = "x=pos_m", m3[] = "f_c=force";
	popc_error err;
	assert_int_equal(popc_log_reader_add_mapping(&opt, m1, &err), 0);
	assert_int_equal(popc_log_reader_add_mapping(&opt, m2, &err), 0);
	assert_int_equal(popc_log_reader_add_mapping(&opt, m3, &err), 0);
	popc_log_reader r;
	assert_int_equal(popc_log_reader_open(&r, path, &opt, &err), 0);
	assert_int_equal(r.delimiter, ';');
	int t, x, f;
	assert_int_equal(popc_log_reader_require(&r, "t", &t, &err), 0);
	assert_int_equal(popc_log_reader_require(&r, "x", &x, &err), 0);
	assert_int_equal(popc_log_reader_require(&r, "f_c", &f, &err), 0);
	assert_int_equal(t, 0);
	assert_int_equal(f, 1);
	assert_int_equal(x, 2);
	double v[POPC_LOG_MAX_COLUMNS];
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_true(v[x] == -1e-5 && v[f] == 0.5);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_true(v[t] == 0.001 && v[x] == 2e-5);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
	popc_log_reader_close(&r);
	/* a mapping to a header the file lacks is named */
	popc_log_reader_options bad = {0};
	char m4[] = "x=position";
	assert_int_equal(popc_log_reader_add_mapping(&bad, m4, &err), 0);
	assert_int_equal(popc_log_reader_open(&r, path, &bad, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "no column 'position'"));
	char m5[] = "novalue";
	assert_int_equal(popc_log_reader_add_mapping(&bad, m5, &err), POPC_ERR_INVALID);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_round_trip_bitwise),
		cmocka_unit_test(test_reader_errors),
		cmocka_unit_test(test_reader_bom),
		cmocka_unit_test(test_reader_trailing_sections),
		cmocka_unit_test(test_foreign_log_mapping),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
