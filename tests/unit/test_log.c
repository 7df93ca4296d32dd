/* CSV log: the column table, bitwise round trip writer -> reader of every
 * column, and the reader's errors. */
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "popc/log/log.h"
#include "popc/log/log_reader.h"
#include "popc/util/numfmt.h"

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

/* The column sets an axis can log: every combination of the fill bits. */
static const unsigned column_sets[] = {
	POPC_LOG_COL_ALWAYS, POPC_LOG_COL_X_TRUE, POPC_LOG_COL_TIMING,
	POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TIMING, POPC_LOG_COL_ADMITTANCE,
	POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TELEOP | POPC_LOG_COL_SLAVE_TRUE,
	/* a teleoperation run whose slave is a Modbus drive (issue 26) */
	POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TIMING | POPC_LOG_COL_TELEOP,
	POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TELEOP | POPC_LOG_COL_SLAVE_TRUE | POPC_LOG_COL_DRIFT,
};
enum { N_SETS = sizeof column_sets / sizeof column_sets[0] };

/* A random value a column of this format holds exactly: any finite double,
 * a count of up to 62 bits (an integer double: every digit is written), a
 * 32-bit flag word. */
static double random_cell(popc_log_cell_format format)
{
	switch (format) {
	case POPC_LOG_CELL_COUNT: {
		uint64_t u = next_u64();
		double c = (double)(long long)(u >> 2);
		return (u & 1) ? -c : c;
	}
	case POPC_LOG_CELL_FLAGS: return (double)(uint32_t)next_u64();
	case POPC_LOG_CELL_DOUBLE: break;
	}
	return random_double();
}

/* The table itself: names unique and found, every column described, and
 * each popc_log_row field reached by get and set. */
static void test_column_table(void **state)
{
	(void)state;
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
		const popc_log_column *c = &popc_log_columns[id];
		assert_non_null(c->name);
		assert_true(c->name[0] != '\0');
		assert_int_equal(popc_log_column_find(c->name), id);
		assert_non_null(c->unit);
		if (c->format == POPC_LOG_CELL_DOUBLE && c->unit[0] == '\0')
			fail_msg("column %s: a number without a unit", c->name);
		assert_non_null(c->meaning);
		assert_true(strlen(c->meaning) > 5);
		assert_true((c->fill & ~(unsigned)(POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TIMING |
					     POPC_LOG_COL_ADMITTANCE | POPC_LOG_COL_TELEOP |
					     POPC_LOG_COL_SLAVE_TRUE | POPC_LOG_COL_DRIFT)) == 0);
		/* set then get: the same value, and no other column moved */
		popc_log_row row;
		memset(&row, 0, sizeof row);
		const double v = c->format == POPC_LOG_CELL_DOUBLE ? -1.25e-3 : 77.0;
		popc_log_row_set(&row, (popc_log_column_id)id, v);
		for (int k = 0; k < POPC_LOG_N_COLUMNS; k++)
			if (!same_bits(popc_log_row_get(&row, (popc_log_column_id)k), k == id ? v : 0.0))
				fail_msg("set %s moved column %s", c->name, popc_log_columns[k].name);
	}
	assert_int_equal(popc_log_column_find("T"), -1);
	assert_int_equal(popc_log_column_find(""), -1);
	assert_int_equal(popc_log_column_find("x "), -1);
	/* the time column is first: the reader checks that it increases */
	assert_int_equal(POPC_LOG_COLUMN_T, 0);
	assert_string_equal(popc_log_columns[POPC_LOG_COLUMN_T].name, "t");
}

/* The line of column names popc writes is the table's names joined, for
 * every column set, and each name's place is popc_log_column_index. Today's
 * lines are spelt out too: a reordered table would change every log. */
static void test_column_names_line(void **state)
{
	(void)state;
	static const char *const expected[N_SETS] = {
		"t,x,count,v,f_e,f_pc,f_c,W,E_ref,flags",
		"t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port",
		"t,x,count,v,f_e,f_pc,f_c,W,E_ref,flags,dt,rtt",
		"t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port,dt,rtt",
		"t,x,count,v,f_e,f_pc,f_c,W,E_ref,flags,f_count,f_meas,x_cmd,v_ve,v_pc",
		/* one name line, split in two (the parentheses tell clang that the
		 * concatenation is meant, not a missing comma) */
		("t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port,xs,xs_true,xs_cmd,fs_count,fs,"
		 "vs_rx,vs_pc,vs_c,Ws,Em_in,Em_out,Em_rx,Es_in,Es_out,Es_rx,fwd_age,bwd_age"),
		("t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port,dt,rtt,xs,xs_cmd,fs_count,fs,"
		 "vs_rx,vs_pc,vs_c,Ws,Em_in,Em_out,Em_rx,Es_in,Es_out,Es_rx,fwd_age,bwd_age"),
		("t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port,xs,xs_true,xs_cmd,fs_count,fs,"
		 "vs_rx,vs_pc,vs_c,Ws,Em_in,Em_out,Em_rx,Es_in,Es_out,Es_rx,fwd_age,bwd_age,xm_rx,vs_dc"),
	};
	for (int k = 0; k < N_SETS; k++) {
		const unsigned set = column_sets[k];
		char joined[POPC_LOG_NAMES_LINE_MAX] = "";
		int place[POPC_LOG_N_COLUMNS], n = 0;
		for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
			place[id] = -1;
			if ((popc_log_columns[id].fill & ~set) != 0)
				continue;
			if (n > 0)
				strcat(joined, ",");
			strcat(joined, popc_log_columns[id].name);
			place[id] = n++;
		}
		assert_string_equal(joined, expected[k]);
		char names[POPC_LOG_NAMES_LINE_MAX];
		assert_int_equal(popc_log_column_names(set, names, sizeof names), strlen(joined));
		assert_string_equal(names, joined);
		for (int id = 0; id < POPC_LOG_N_COLUMNS; id++)
			assert_int_equal(popc_log_column_index(set, (popc_log_column_id)id), place[id]);

		/* the writer's header: the same line after the comments */
		char path[512];
		snprintf(path, sizeof path, "%s/names%d.csv", tmpdir, k);
		popc_scene s;
		popc_scene_defaults(&s);
		popc_log_writer w;
		popc_error err;
		assert_int_equal(popc_log_open(&w, path, set, &err), 0);
		assert_int_equal(popc_log_write_header(&w, "sim", &s, NULL, &err), 0);
		assert_int_equal(popc_log_close(&w, &err), 0);
		FILE *f = fopen(path, "r");
		assert_non_null(f);
		char line[1024];
		while (fgets(line, sizeof line, f) && line[0] == '#')
			;
		fclose(f);
		line[strcspn(line, "\n")] = '\0';
		assert_string_equal(line, joined);
	}
	/* a buffer too small holds the names that fit, terminated */
	char small[8];
	assert_int_equal(popc_log_column_names(POPC_LOG_COL_ALWAYS, small, sizeof small), 3);
	assert_string_equal(small, "t,x");
	assert_int_equal(popc_log_column_index(POPC_LOG_COL_ALWAYS, POPC_LOG_N_COLUMNS), -1);
}

/* Every column of the table, for every column set, written and read back
 * bitwise: edge values, then random ones of the column's format. */
static void test_round_trip_bitwise(void **state)
{
	(void)state;
	enum { N = 20000 };
	static popc_log_row rows[N];
	const double edge[] = {0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
			       -1.7976931348623157e308, 0.1, 1e-5, 1e22, 1e23, 9007199254740993.0};
	enum { N_EDGE = sizeof edge / sizeof edge[0] };
	for (int k = 0; k < N_SETS; k++) {
		const unsigned set = column_sets[k];
		char path[512];
		snprintf(path, sizeof path, "%s/rt%d.csv", tmpdir, k);
		popc_scene s;
		popc_scene_defaults(&s);
		popc_log_writer w;
		popc_error err;
		assert_int_equal(popc_log_open(&w, path, set, &err), 0);
		assert_int_equal(popc_log_write_header(&w, "sim", &s, NULL, &err), 0);
		for (int i = 0; i < N; i++) {
			popc_log_row *r = &rows[i];
			memset(r, 0, sizeof *r);
			for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
				const popc_log_cell_format format = popc_log_columns[id].format;
				double v = random_cell(format);
				if (id == POPC_LOG_COLUMN_T)
					v = i * 1e-3; /* time increases */
				else if (i < N_EDGE && format == POPC_LOG_CELL_DOUBLE)
					v = edge[i];
				popc_log_row_set(r, (popc_log_column_id)id, v);
			}
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
		int idx[POPC_LOG_N_COLUMNS], n_written = 0;
		for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
			idx[id] = popc_log_reader_column(&rd, popc_log_columns[id].name);
			assert_int_equal(idx[id], popc_log_column_index(set, (popc_log_column_id)id));
			n_written += idx[id] >= 0;
		}
		assert_int_equal(rd.n_cols, n_written);
		double v[POPC_LOG_MAX_COLUMNS];
		for (int i = 0; i < N; i++) {
			assert_int_equal(popc_log_reader_next(&rd, v, &err), 1);
			for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
				if (idx[id] < 0)
					continue;
				const double want = popc_log_row_get(&rows[i], (popc_log_column_id)id);
				if (!same_bits(v[idx[id]], want))
					fail_msg("set %u row %d column %s: %.17g read back as %.17g", set, i,
						 popc_log_columns[id].name, want, v[idx[id]]);
			}
		}
		assert_int_equal(popc_log_reader_next(&rd, v, &err), 0);
		assert_string_equal(rd.stop_reason, "completed");
		popc_log_reader_close(&rd);
	}
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


/* The writer's cell cache (log_writer.c: a column's recent texts by a hash
 * of the bits) gives every cell the text popc_format_double_point gives it:
 * each double cell drawn from a pool of 300 values per column, so that
 * values repeat, evict each other from their slots and come back, among
 * them +0.0 (every slot's first text), -0.0, subnormals, a NaN and the
 * infinities (never logged, but the writer must write them as they are).
 * Every line is compared with the text made cell by cell. */
static void test_writer_cell_cache(void **state)
{
	(void)state;
	enum { N = 6000, POOL = 300 };
	static double pool[POPC_LOG_N_COLUMNS][POOL];
	const double odd[] = {0.0, -0.0, 5e-324, -2.2250738585072014e-308, (double)NAN, (double)INFINITY,
			      -(double)INFINITY, 1e17, 0.1, 1.0};
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++)
		for (int j = 0; j < POOL; j++)
			pool[id][j] = j < (int)(sizeof odd / sizeof odd[0]) ? odd[j]
				      : (j & 1)			     ? random_double()
								     : (double)(j - 150) * 1e-5;
	const unsigned set = POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TIMING;
	char path[512];
	snprintf(path, sizeof path, "%s/cache.csv", tmpdir);
	popc_scene s;
	popc_scene_defaults(&s);
	popc_log_writer w;
	popc_error err;
	assert_int_equal(popc_log_open(&w, path, set, &err), 0);
	assert_int_equal(popc_log_write_header(&w, "sim", &s, NULL, &err), 0);
	static char want[N][POPC_LOG_N_COLUMNS * (POPC_DOUBLE_TEXT_MAX + 1) + 1];
	for (int i = 0; i < N; i++) {
		popc_log_row r;
		memset(&r, 0, sizeof r);
		char *o = want[i];
		for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
			if (!popc_log_column_written(popc_log_columns[id].fill, set))
				continue;
			const popc_log_cell_format format = popc_log_columns[id].format;
			/* mostly the first few values of the pool (hits), now and
			 * then any of them (misses, evictions) */
			uint64_t u = next_u64();
			double v = format == POPC_LOG_CELL_DOUBLE ? pool[id][(u & 3) ? u % 12 : u % POOL]
								  : (double)(u % 1000);
			popc_log_row_set(&r, (popc_log_column_id)id, v);
			if (o != want[i])
				*o++ = ',';
			if (format == POPC_LOG_CELL_DOUBLE)
				o += popc_format_double_point(v, o);
			else
				o += sprintf(o, "%d", (int)v);
		}
		assert_int_equal(popc_log_write_row(&w, &r, &err), 0);
	}
	assert_int_equal(popc_log_close(&w, &err), 0);
	FILE *f = fopen(path, "r");
	assert_non_null(f);
	static char line[4096];
	while (fgets(line, sizeof line, f) && line[0] == '#')
		; /* the names line */
	for (int i = 0; i < N; i++) {
		assert_non_null(fgets(line, sizeof line, f));
		line[strcspn(line, "\n")] = '\0';
		if (strcmp(line, want[i]) != 0) {
			print_error("row %d: \"%s\", want \"%s\"\n", i, line, want[i]);
			fail();
		}
	}
	assert_null(fgets(line, sizeof line, f));
	fclose(f);
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
		/* a foreign log's last line may lack its newline (RFC 4180), but
		 * not cells */
		{"t,x\n0,1\n0.001,2\n0.002", NULL, {":4:", "truncated last line"}},
		{"t,x\n0,1\n0.001\n", NULL, {":3:", "short row"}},
		{"t,x\n0,1\n0.001,abc\n", NULL, {":3: column 2 (x)", "not a finite number 'abc'"}},
		{"t,x\n0,1\n0.001,nan\n", NULL, {":3: column 2 (x)", "NaN is not allowed"}},
		{"t,x\n0,1\n0.001,inf\n", NULL, {":3: column 2", NULL}},
		{"t,x\n0,1\n0.001,\n", NULL, {":3: column 2", "empty cell"}},
		{"t,x\n0,1\n0.001,2,3\n", NULL, {":3:", "3 cells, expected 2 (more cells than columns)"}},
		{"t,x\n0,1\n0,2\n", NULL, {":3: column 1 (t)", "does not increase"}},
		{"t,x\n0,1\n", "f_c", {"missing column 'f_c'", "--column f_c=HEADER"}},
		/* a repeated column name: both columns and the line named */
		{"t,x,x\n0,1,2\n", NULL, {":1: column 3 (x)", "repeats the name of column 2 (line 1)"}},
		{"# a = 1\n\"t\";x;f_c;x\n0;1;2;3\n", NULL, {":2: column 4 (x)", "column 2 (line 2)"}},
		/* a popc log's header key given twice: both lines named (the scene
		 * took the last, a header lookup the first) */
		{"# format = 1\n# [run]\n# rate = 1000\n# rate = 2000\nt,x\n0,1\n", NULL,
		 {":4: header key run.rate given twice", "(first on line 3)"}},
		{"# format = 1\n# variant = none\n# variant = hold\nt,x\n0,1\n", NULL,
		 {":3: header key variant given twice (first on line 2)", NULL}},
		/* CR-only line ends: the whole file is one line */
		{"# format = 1\r# source = sim\rt,x\r0,1\r", NULL, {":1: a carriage return (CR) inside the line", "CR-only"}},
		{"t,x\r0,1\r0.001,2\r", NULL, {":1: a carriage return (CR) inside the line", NULL}},
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

/* Writes len bytes (NUL bytes included) to a file in the test directory. */
static const char *write_bytes(const char *name, const char *bytes, size_t len)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/%s", tmpdir, name);
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	assert_int_equal(fwrite(bytes, 1, len, f), len);
	fclose(f);
	return path;
}

/* Rows of plain numbers are read in one pass (popc_parse_double_row); every
 * other row goes through the split, which checks it: both give the same
 * values, and a NUL byte anywhere (a row, a cell read or not, a comment, a
 * cut last line) is refused naming its line, as before the one-pass path. */
static void test_reader_one_pass_and_split(void **state)
{
	(void)state;
	/* the same numbers written plainly and as the split's cases: quoted,
	 * blanks around, a sign, no integer digit, an exponent */
	const char *text = "t,x,f\n"
			   "0,0.5,-1.25e-3\n"
			   "\"0.001\",\"0.5\",-1.25e-3\n"
			   "0.002, 0.5 ,\t-0.00125\n"
			   "+0.003,.5,\"-1.25E-3\"\n"
			   "# a comment between rows\n"
			   "\n"
			   "0.004,5e-1,-125e-5\n";
	const char *path = write_file("mixed.csv", text);
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	assert_true(r.fast_rows);
	double v[POPC_LOG_MAX_COLUMNS];
	const double t[] = {0, 0.001, 0.002, 0.003, 0.004};
	for (int row = 0; row < 5; row++) {
		if (popc_log_reader_next(&r, v, &err) != 1)
			fail_msg("row %d: %s", row, err.msg);
		/* the first row is plain, the second not: the split reads the
		 * rows from there on (the one-pass attempt would fail on each) */
		assert_int_equal(r.fast_rows, row == 0);
		assert_true(v[0] == t[row]);
		assert_true(v[1] == 0.5);
		assert_true(v[2] == -1.25e-3);
	}
	assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
	popc_log_reader_close(&r);
	/* comments and blank lines between rows keep the one-pass path */
	path = write_file("comments.csv", "t,x\n0,1\n# c\n\n \n0.001,2\n# stop = x\n");
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_true(v[0] == 0.001 && v[1] == 2.0);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
	assert_true(r.fast_rows);
	popc_log_reader_close(&r);
	/* a column nobody reads may hold text, on either path */
	path = write_file("text.csv", "t,x,note\n0,1,2\n0.001,2,\"a, b\"\n0.002,3,c\n");
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	int cols[] = {0, 1};
	assert_int_equal(popc_log_reader_use_columns(&r, cols, 2), 0);
	for (int row = 0; row < 3; row++) {
		assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
		assert_true(v[1] == row + 1 && isnan(v[2]));
	}
	popc_log_reader_close(&r);

	const struct {
		const char *bytes;
		size_t len;
		const char *must_contain;
	} nul[] = {
		{"t,x\n0,1\n0.001,2\0" "5\n", 18, ":3: a NUL byte in the line"},
		{"t,x\n0,1\n0.001\0,2\n", 17, ":3: a NUL byte in the line"},
		{"t,x\n0,1\n\0" "0.001,2\n", 17, ":3: a NUL byte in the line"},
		{"t,x\n0,1\n# a\0 comment\n0.001,2\n", 30, ":3: a NUL byte in the line"},
		{"# format = 1\nt,x\n0,1\n0.001,2\0", 29, ":4: a NUL byte in the line"},
	};
	for (size_t i = 0; i < sizeof nul / sizeof nul[0]; i++) {
		path = write_bytes("nul.csv", nul[i].bytes, nul[i].len);
		int st = read_all(path, NULL, NULL, &err);
		if (st != POPC_ERR_INVALID || !strstr(err.msg, nul[i].must_contain))
			fail_msg("NUL case %zu: status %d, '%s'", i, st, st ? err.msg : "");
	}
	/* in a column nobody reads too */
	path = write_bytes("nul.csv", "t,x,note\n0,1,a\n0.001,2,b\0c\n", 27);
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	assert_int_equal(popc_log_reader_use_columns(&r, cols, 2), 0);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_int_equal(popc_log_reader_next(&r, v, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, ":3: a NUL byte in the line"));
	popc_log_reader_close(&r);
	/* errors a one-pass row leaves to the split: its messages */
	const struct {
		const char *text, *must_contain;
	} bad[] = {
		{"t,x\n0,1\n0.001,1e-400\n", ":3: column 2 (x): below the smallest double"},
		{"t,x\n0,1\n0.001,1e400\n", ":3: column 2 (x): not a finite number '1e400'"},
		{"t,x\n0,1\n0.001,2,\n", ":3: 3 cells, expected 2 (more cells than columns)"},
		{"t,x\n0,1\n0.001;2\n", ":3: 1 cells, expected 2 (short row)"},
		{"t,x\n0,1\n0.001,2e\n", ":3: column 2 (x): not a finite number '2e'"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		path = write_file("bad.csv", bad[i].text);
		int st = read_all(path, NULL, NULL, &err);
		if (st != POPC_ERR_INVALID || !strstr(err.msg, bad[i].must_contain))
			fail_msg("case %zu: status %d, '%s'", i, st, st ? err.msg : "");
	}
}

/* Rows read straight from the block buffer end where the parse finds their
 * newline; a row the 1 MiB buffer cuts is read whole after a refill. A file
 * of about 3 MiB (rows of every length cut at some byte of every kind: a
 * digit, a point, an exponent, a delimiter, a CR of a CR LF) reads back
 * bitwise, on the right line numbers. */
/* A column checked but not read (popc_log_reader_check_columns): its cells
 * are NaN and are not parsed, on the one pass as on the split; a cell of
 * other characters than a number's, or an empty one, is still an error
 * naming its line and column, on either path; a cell of a number's
 * characters that makes no finite number is let through (documented). The
 * columns read keep their values, and repeated cells (the memos) read as
 * the first. */
static void test_reader_checked_columns(void **state)
{
	(void)state;
	const char *plain = "t,x,x_true,f\n"
			    "0,0.5,0.123456789012345678,1.5\n"
			    "0.001,0.5,1e999,1.5\n"
			    "0.002,0.5,1.2.3,-2.5\n"
			    "0.003,0.25,-0.5e-3,-2.5\n";
	/* the same rows through the split: a quoted cell in the first row */
	const char *quoted = "t,x,x_true,f\n"
			     "\"0\",0.5,0.123456789012345678,1.5\n"
			     "0.001,0.5,1e999,1.5\n"
			     "0.002,0.5,1.2.3,-2.5\n"
			     "0.003,0.25,-0.5e-3,-2.5\n";
	const char *texts[] = {plain, quoted};
	const double x[] = {0.5, 0.5, 0.5, 0.25}, f[] = {1.5, 1.5, -2.5, -2.5};
	for (int k = 0; k < 2; k++) {
		const char *path = write_file("checked.csv", texts[k]);
		popc_log_reader r;
		popc_error err;
		assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
		int cols[] = {0, 1, 2, 3}, checked[] = {2};
		assert_int_equal(popc_log_reader_use_columns(&r, cols, 4), 0);
		assert_int_equal(popc_log_reader_check_columns(&r, checked, 1), 0);
		double v[POPC_LOG_MAX_COLUMNS];
		for (int row = 0; row < 4; row++) {
			if (popc_log_reader_next(&r, v, &err) != 1)
				fail_msg("text %d, row %d: %s", k, row, err.msg);
			assert_true(v[1] == x[row] && v[3] == f[row] && isnan(v[2]));
		}
		assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
		assert_int_equal(r.fast_rows, k == 0);
		popc_log_reader_close(&r);
	}
	const char *bad[] = {"0,1,x,2\n", "0,1,,2\n", "0,1,nan,2\n", "0,1,inf,2\n",
			     "0,1,0x10,2\n", "\"0\",1,x,2\n", "\"0\",1,,2\n"};
	for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
		char text[128];
		snprintf(text, sizeof text, "t,x,x_true,f\n0.5,1,1,2\n%s", bad[k]);
		const char *path = write_file("checked_bad.csv", text);
		popc_log_reader r;
		popc_error err;
		assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
		int checked[] = {2};
		assert_int_equal(popc_log_reader_check_columns(&r, checked, 1), 0);
		double v[POPC_LOG_MAX_COLUMNS];
		assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
		int st = popc_log_reader_next(&r, v, &err);
		if (st != POPC_ERR_INVALID || !strstr(err.msg, ":3: column 3 (x_true): "))
			fail_msg("\"%s\": %d, %s", bad[k], st, err.msg);
		popc_log_reader_close(&r);
	}
	/* out of range, and the time column stays read */
	const char *path = write_file("checked_t.csv", "t,x\n0,1\n0.001,2\n");
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	int oob[] = {2}, t_and_x[] = {0, 1};
	assert_int_equal(popc_log_reader_check_columns(&r, oob, 1), POPC_ERR_INVALID);
	assert_int_equal(popc_log_reader_check_columns(&r, t_and_x, 2), 0);
	double v[POPC_LOG_MAX_COLUMNS];
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_true(v[0] == 0.001 && isnan(v[1]));
	popc_log_reader_close(&r);
}

static void test_reader_rows_across_blocks(void **state)
{
	(void)state;
	char path[512];
	snprintf(path, sizeof path, "%s/blocks.csv", tmpdir);
	FILE *f = fopen(path, "wb");
	assert_non_null(f);
	fputs("# format = 1\nt,x,f\n", f);
	const long rows = 60000;
	uint64_t state_rng = 88172645463325252u;
	for (long k = 0; k < rows; k++) {
		state_rng ^= state_rng << 13, state_rng ^= state_rng >> 7, state_rng ^= state_rng << 17;
		double x = (double)(state_rng >> 11) * 0x1p-53 * (k % 7 == 0 ? 1e-300 : 1.0);
		fprintf(f, "%ld,%.17g,%.*e%s", k, x, (int)(k % 17), -x * 3.0, k % 5 ? "\n" : "\r\n");
	}
	fputs("# stop = completed\n", f);
	fclose(f);
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	double v[POPC_LOG_MAX_COLUMNS];
	state_rng = 88172645463325252u;
	for (long k = 0; k < rows; k++) {
		if (popc_log_reader_next(&r, v, &err) != 1)
			fail_msg("row %ld: %s", k, err.msg);
		state_rng ^= state_rng << 13, state_rng ^= state_rng >> 7, state_rng ^= state_rng << 17;
		double x = (double)(state_rng >> 11) * 0x1p-53 * (k % 7 == 0 ? 1e-300 : 1.0);
		char text[64];
		snprintf(text, sizeof text, "%.*e", (int)(k % 17), -x * 3.0);
		if (v[0] != (double)k || v[1] != x || memcmp(&v[2], &(double){strtod(text, NULL)}, 8))
			fail_msg("row %ld read as %.17g, %.17g, %.17g", k, v[0], v[1], v[2]);
		assert_int_equal(r.lineno, k + 3);
	}
	assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
	assert_int_equal(popc_log_reader_unfinished(&r), 0);
	assert_true(r.fast_rows);
	popc_log_reader_close(&r);
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

/* A log written under a file size limit of limit bytes (RLIMIT_FSIZE, with
 * SIGXFSZ ignored: the write past it fails with EFBIG, as on a full disk):
 * rows until the writer fails, then the stop line as popc_run writes it.
 * Returns the rows the writer took before it failed. */
static long write_until_full(const char *path, rlim_t limit, popc_error *err)
{
	popc_scene s;
	popc_scene_defaults(&s);
	popc_log_writer w;
	assert_int_equal(popc_log_open(&w, path, POPC_LOG_COL_X_TRUE, err), 0);
	struct rlimit old, lim;
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
	lim = old;
	lim.rlim_cur = limit;
	void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
	int st = popc_log_write_header(&w, "sim", &s, NULL, err);
	long rows = 0;
	for (; !st && rows < 1000000; rows++) {
		popc_log_row r;
		memset(&r, 0, sizeof r);
		r.tick.t_s = (double)rows * 1e-3;
		r.tick.x_m = r.x_true_m = 0.1 * sin((double)rows) + 1e-17 * (double)rows;
		r.tick.count = rows * 12345;
		/* 17 digits a cell, about 200 bytes a row as in a real log, so that
		 * the ~90-byte stop line fits in the part of a row cut away at
		 * about half the limits */
		r.tick.v_mps = r.tick.f_e_N = r.tick.f_pc_N = r.tick.f_c_N = 0.1 / 3.0;
		r.tick.W_J = r.tick.E_ref_J = 1.0 / 3.0 + (double)rows;
		st = popc_log_write_row(&w, &r, err);
	}
	assert_int_equal(st, POPC_ERR_IO);
	assert_non_null(strstr(err->msg, "write failed: File too large"));
	popc_error e2;
	char reason[POPC_ERROR_MSG_MAX + 32];
	snprintf(reason, sizeof reason, "log write failed: %s", err->msg);
	assert_int_equal(popc_log_write_comment(&w, "stop", reason, &e2), POPC_ERR_IO);
	assert_int_equal(popc_log_close(&w, &e2), POPC_ERR_IO);
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
	signal(SIGXFSZ, old_handler);
	return rows;
}

/* A log cut by a full disk is a valid prefix: whole lines only, within the
 * limit, its rows read back in full, then the stop line where it fitted (at
 * some limits it does, at others not: both are seen). Old popc (46f30c1)
 * left the row cut at the limit, which the reader refused. */
static void test_writer_full_disk(void **state)
{
	(void)state;
	int with_stop = 0, without_stop = 0;
	for (rlim_t limit = 5000; limit < 5000 + 4 * 160; limit += 37) {
		char path[512];
		snprintf(path, sizeof path, "%s/full.csv", tmpdir);
		popc_error err;
		long written = write_until_full(path, limit, &err);
		struct stat sb;
		assert_int_equal(stat(path, &sb), 0);
		assert_true(sb.st_size > 0 && (rlim_t)sb.st_size <= limit);
		FILE *f = fopen(path, "rb");
		assert_non_null(f);
		assert_int_equal(fseek(f, -1, SEEK_END), 0);
		assert_int_equal(fgetc(f), '\n'); /* whole lines only */
		fclose(f);
		popc_log_reader r;
		assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
		double v[POPC_LOG_MAX_COLUMNS];
		int got;
		long long rows = 0;
		while ((got = popc_log_reader_next(&r, v, &err)) == 1) {
			assert_true(v[0] == (double)rows * 1e-3);
			rows++;
		}
		assert_int_equal(got, 0);
		/* every row that reached the file whole is read (the writer's
		 * buffer held the others when the write failed) */
		assert_true(rows > 0 && rows <= written);
		if (r.stop_reason[0]) {
			assert_non_null(strstr(r.stop_reason, "log write failed: "));
			assert_non_null(strstr(r.stop_reason, "full.csv: write failed: File too large"));
			assert_int_equal(popc_log_reader_unfinished(&r), 0);
			with_stop++;
		} else {
			assert_int_equal(popc_log_reader_unfinished(&r), POPC_LOG_NO_STOP);
			without_stop++;
		}
		popc_log_reader_close(&r);
	}
	assert_true(with_stop > 0 && without_stop > 0);
	/* no room at all: the header is refused, before any row */
	popc_scene s;
	popc_scene_defaults(&s);
	popc_log_writer w;
	popc_error err;
	assert_int_equal(popc_log_open(&w, "/dev/full", POPC_LOG_COL_ALWAYS, &err), 0);
	assert_int_equal(popc_log_write_header(&w, "sim", &s, NULL, &err), POPC_ERR_IO);
	assert_string_equal(err.msg, "/dev/full: write failed: No space left on device");
	assert_int_equal(popc_log_close(&w, &err), POPC_ERR_IO);
}

/* An unfinished popc log (a run cut short) reads as its whole rows, and the
 * reader says how it ended; a foreign log has no stop line to miss. */
static void test_reader_unfinished(void **state)
{
	(void)state;
	const struct {
		const char *text;
		long long rows, last_row_line, cut_line;
		int unfinished;
	} cases[] = {
		{"# format = 1\nt,x\n0,1\n0.001,2\n# stop = completed\n", 2, 4, 0, 0},
		{"# format = 1\nt,x\n0,1\n0.001,2\n", 2, 4, 0, POPC_LOG_NO_STOP},
		/* every cell there, but no newline: cut (the 3 may be 3.25 cut) */
		{"# format = 1\nt,x\n0,1\n0.001,2\n0.002,3", 2, 4, 5, POPC_LOG_CUT_LINE},
		{"# format = 1\nt,x\n0,1\n0.001,2\n0.0", 2, 4, 5, POPC_LOG_CUT_LINE},
		/* a stop line cut short is no stop line */
		{"# format = 1\nt,x\n0,1\n# stop = comp", 1, 3, 4, POPC_LOG_CUT_LINE},
		{"t,x\n0,1\n0.001,2\n", 2, 3, 0, 0},
		{"t,x\n0,1\n0.001,2", 2, 3, 0, 0},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_file("unfinished.csv", cases[i].text);
		popc_log_reader r;
		popc_error err;
		assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
		double v[POPC_LOG_MAX_COLUMNS];
		int got;
		while ((got = popc_log_reader_next(&r, v, &err)) == 1)
			;
		if (got != 0)
			fail_msg("case %zu: %s", i, err.msg);
		assert_int_equal(r.rows, cases[i].rows);
		assert_int_equal(r.last_row_line, cases[i].last_row_line);
		assert_int_equal(r.cut_line, cases[i].cut_line);
		assert_int_equal(popc_log_reader_unfinished(&r), cases[i].unfinished);
		popc_log_reader_close(&r);
	}
}

/* A popc log's header that the scene refuses: the file, the key's own line
 * and the key as the header spells it (it said "LOG: header: --set run.rate
 * = ..." without a line); a foreign log's repeated comment keys are text. */
static void test_reader_header_errors(void **state)
{
	(void)state;
	const struct {
		const char *text, *message;
	} cases[] = {
		{"# format = 1\n# source = sim\n# [run]\n# duration = 5\n# rate = 1e7\nt,x\n0,1\n",
		 ":5: header: run.rate = 1e7: out of range; allowed [1, 1e+06] Hz"},
		{"# format = 1\n# source = sim\n# [run]\n# rate = inf\nt,x\n0,1\n",
		 ":4: header: run.rate = 'inf': not a finite number"},
		{"# format = 1\n# [run]\n# rat = 10\nt,x\n0,1\n",
		 ":3: header: unknown key run.rat; [run] has: duration, rate"},
		{"# format = 1\n# [nosuch]\n# a = 1\nt,x\n0,1\n", ":3: header: unknown section [nosuch]"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_file("header.csv", cases[i].text);
		popc_log_reader r;
		popc_error err;
		assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
		popc_scene s;
		popc_scene_defaults(&s);
		assert_int_equal(popc_log_reader_scene(&r, &s, &err), POPC_ERR_INVALID);
		char want[512];
		snprintf(want, sizeof want, "%s%s", path, cases[i].message);
		if (strncmp(err.msg, want, strlen(want)) != 0)
			fail_msg("case %zu: '%s', expected '%s...'", i, err.msg, want);
		popc_log_reader_close(&r);
	}
	const char *path = write_file("foreign.csv", "# note = a\n# note = b\nt,x\n0,1\n");
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	popc_log_reader_close(&r);
}

/* Cells of a tab-separated row are what lies between its tabs: "\t\t" is an
 * empty cell, not padding (it was skipped, and every later cell read one
 * column left: f_c = 0.7 from the fifth cell, no error). A row with more
 * or fewer cells than names is refused with its line and both counts; an
 * empty cell reads only in a column nobody reads. */
static void test_reader_tab_empty_cells(void **state)
{
	(void)state;
	const popc_log_reader_options tab = {.delimiter = '\t'};
	const struct {
		const char *text;
		const popc_log_reader_options *opt;
		const char *message; /* NULL: read */
	} cases[] = {
		/* the row: 5 cells under 4 names */
		{"t\tx\tf_e\tf_c\n0\t0\t0\t0.1\n0.001\t1e-5\t\t0.1\t0.7\n", NULL,
		 ":3: 5 cells, expected 4 (more cells than columns)"},
		{"t\tx\tf_e\tf_c\n0\t0\t0\t0.1\n0.001\t1e-5\t\t0.1\t0.7\n", &tab,
		 ":3: 5 cells, expected 4 (more cells than columns)"},
		/* 4 cells, one empty: a read column's empty cell is named */
		{"t\tx\tf_e\tf_c\n0\t0\t0\t0.1\n0.001\t1e-5\t\t0.7\n", NULL,
		 ":3: column 3 (f_e): empty cell"},
		/* an empty first cell: no blank to skip before it */
		{"t\tx\n0\t1\n\t2\n", NULL, ":3: column 1 (t): empty cell"},
		/* more than 64 cells: counted, not just "more" */
		{"t\tx\n0\t1\n0.001\t2\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t"
		 "\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t\t"
		 "\t\t\t\t\t\t\t\t\t\n",
		 NULL, ":3: 66 cells, expected 2 (more cells than columns)"},
		/* blanks around a cell are still no part of it, under a tab too */
		{"t\tx\n0\t 1 \n 0.001 \t2\n", NULL, NULL},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_file("tab.tsv", cases[i].text);
		popc_error err;
		int st = read_all(path, cases[i].opt, NULL, &err);
		if (!cases[i].message) {
			if (st != 0)
				fail_msg("case %zu: %s", i, err.msg);
			continue;
		}
		if (st != POPC_ERR_INVALID || !strstr(err.msg, cases[i].message))
			fail_msg("case %zu: status %d, '%s', expected '%s'", i, st, st ? err.msg : "",
				 cases[i].message);
	}
	/* an empty cell in a column nobody reads keeps the others in place */
	const char *path = write_file("tab.tsv", "t\tnote\tx\n0\ta\t1\n0.001\t\t2\n");
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, NULL, &err), 0);
	const int cols[] = {0, 2};
	assert_int_equal(popc_log_reader_use_columns(&r, cols, 2), 0);
	double v[POPC_LOG_MAX_COLUMNS];
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_true(v[0] == 0.001 && isnan(v[1]) && v[2] == 2.0);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 0);
	popc_log_reader_close(&r);
}

/* A comment mark that is the delimiter took every row with an empty first
 * cell for a comment and dropped it, without a word: refused at open, given
 * or detected, naming both. */
static void test_reader_comment_is_delimiter(void **state)
{
	(void)state;
	const char *text = "note,t,x\na,0,1\n,0.001,2\n";
	const struct {
		popc_log_reader_options opt;
		const char *message;
	} cases[] = {
		{{.comment = ','}, ": the comment mark ',' is also the delimiter (detected from line 1)"},
		{{.comment = ';', .delimiter = ';'}, ": the comment mark ';' is also the delimiter:"},
		{{.delimiter = '#'}, ": the comment mark '#' (the default) is also the delimiter:"},
		{{.comment = '\t', .delimiter = '\t'}, ": the comment mark 'tab' is also the delimiter:"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_file("comment.csv", text);
		popc_error err;
		int st = read_all(path, &cases[i].opt, NULL, &err);
		char want[600];
		snprintf(want, sizeof want, "%s%s", path, cases[i].message);
		if (st != POPC_ERR_INVALID || strncmp(err.msg, want, strlen(want)) != 0)
			fail_msg("case %zu: status %d, '%s', expected '%s'", i, st, st ? err.msg : "",
				 want);
	}
	/* the same file with another comment mark: both rows */
	const char *path = write_file("comment.csv", text);
	popc_log_reader_options opt = {.comment = '%'};
	popc_log_reader r;
	popc_error err;
	assert_int_equal(popc_log_reader_open(&r, path, &opt, &err), 0);
	const int cols[] = {1, 2};
	assert_int_equal(popc_log_reader_use_columns(&r, cols, 2), 0);
	double v[POPC_LOG_MAX_COLUMNS];
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_int_equal(popc_log_reader_next(&r, v, &err), 1);
	assert_true(v[1] == 0.001 && v[2] == 2.0);
	popc_log_reader_close(&r);
}

/* A headerless file read without no_header whose columns are all mapped by
 * position lost its first row to the names, silently (no lookup by name
 * failed to say so): refused with the hint. A mapping by a numeric name says
 * the numbers are names (pandas' 0,1,2); no_header reads the row. */
static void test_reader_numeric_names_by_position(void **state)
{
	(void)state;
	const char *text = "-0.0065 0.25 0 0.5\n-0.0064 0.125 0 0.25\n";
	const struct {
		const char *maps[2];
		int no_header;
		long long rows; /* -1: refused */
	} cases[] = {
		{{"x=#1", "f_c=#4"}, 0, -1},
		{{"x=#1", NULL}, 0, -1},
		{{"x=#1", "f_c=0.5"}, 0, 1}, /* a name: the line is names */
		{{"x=#1", "f_c=#4"}, 1, 2},
		{{NULL, NULL}, 0, 1}, /* no mapping: each lookup by name says it */
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_file("numbers.txt", text);
		popc_log_reader_options opt = {.no_header = cases[i].no_header};
		char maps[2][32];
		popc_error err;
		for (int m = 0; m < 2 && cases[i].maps[m]; m++) {
			snprintf(maps[m], sizeof maps[m], "%s", cases[i].maps[m]);
			assert_int_equal(popc_log_reader_add_mapping(&opt, maps[m], &err), 0);
		}
		popc_log_reader r;
		int st = popc_log_reader_open(&r, path, &opt, &err);
		if (cases[i].rows < 0) {
			char want[1024];
			snprintf(want, sizeof want,
				 "%s:1: the first line that is no comment holds only numbers, and every "
				 "--column maps a position",
				 path);
			if (st != POPC_ERR_INVALID || strncmp(err.msg, want, strlen(want)) != 0 ||
			    !strstr(err.msg, "needs --no-header"))
				fail_msg("case %zu: status %d, '%s'", i, st, st ? err.msg : "");
			continue;
		}
		if (st != 0)
			fail_msg("case %zu: %s", i, err.msg);
		double v[POPC_LOG_MAX_COLUMNS];
		long long rows = 0;
		while ((st = popc_log_reader_next(&r, v, &err)) == 1)
			rows++;
		assert_int_equal(st, 0);
		assert_int_equal(rows, cases[i].rows);
		popc_log_reader_close(&r);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_column_table),
		cmocka_unit_test(test_column_names_line),
		cmocka_unit_test(test_round_trip_bitwise),
		cmocka_unit_test(test_writer_cell_cache),
		cmocka_unit_test(test_reader_errors),
		cmocka_unit_test(test_reader_one_pass_and_split),
		cmocka_unit_test(test_reader_checked_columns),
		cmocka_unit_test(test_reader_rows_across_blocks),
		cmocka_unit_test(test_reader_bom),
		cmocka_unit_test(test_reader_trailing_sections),
		cmocka_unit_test(test_foreign_log_mapping),
		cmocka_unit_test(test_writer_full_disk),
		cmocka_unit_test(test_reader_unfinished),
		cmocka_unit_test(test_reader_header_errors),
		cmocka_unit_test(test_reader_tab_empty_cells),
		cmocka_unit_test(test_reader_comment_is_delimiter),
		cmocka_unit_test(test_reader_numeric_names_by_position),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
