/* Scene parser: good and bad inputs, --set, the resolved dump round trip. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "popc/scene/scene.h"

#include "test_tmpdir.h"

static int setup(void **state)
{
	(void)state;
	return test_tmpdir_make("scene");
}

static int teardown(void **state)
{
	(void)state;
	return test_tmpdir_remove();
}

static const char *write_scene(const char *name, const char *text)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/%s", tmpdir, name);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(text, f);
	fclose(f);
	return path;
}

static void test_defaults_are_the_paper_scene(void **state)
{
	(void)state;
	popc_scene s;
	popc_error err;
	assert_int_equal(popc_scene_defaults_check(&err), 0); /* every default in its range */
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_validate(&s, &err), 0);
	assert_true(s.op_mass_kg == 0.1 && s.op_damping_Nspm == 0.5 && s.op_stiffness_Npm == 50.0);
	assert_true(s.dev_mass_kg == 0.2 && s.dev_damping_Nspm == 0.0 && s.dev_stiffness_Npm == 0.0);
	assert_true(s.env_stiffness_Npm == 1000.0 && s.rate_Hz == 1000.0 && s.enc_resolution_m == 1e-5);
	assert_int_equal(popc_scene_ticks(&s), 5000);
	/* the shipped paper.ini says the same as the defaults */
	char path[1024];
	snprintf(path, sizeof path, "%s/data/scenes/paper.ini", getenv("POPC_SOURCE_ROOT"));
	popc_scene p;
	popc_scene_defaults(&p);
	assert_int_equal(popc_scene_load(&p, path, &err), 0);
	memset(p.source, 0, sizeof p.source);
	assert_memory_equal(&p, &s, sizeof s);
}

static void test_good_scene_and_overrides(void **state)
{
	(void)state;
	const char *path = write_scene("good.ini", "; comment\n# another\n[run]\nduration = 2.5 ; s\n"
						   "rate=2000\n[controller]\nvariant = improved\n"
						   "ignore_mode = literal\n[integrator]\nmethod = rk4\n"
						   "substeps = 7\n[operator]\nintent = sine\n");
	popc_scene s;
	popc_error err;
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, path, &err), 0);
	assert_true(s.duration_s == 2.5 && s.rate_Hz == 2000.0);
	assert_int_equal(s.variant, POPC_VARIANT_IMPROVED);
	assert_int_equal(s.ignore_mode, POPC_IGNORE_LITERAL); /* not the default (undo) */
	assert_int_equal(s.integrator, POPC_INTEGRATOR_RK4);
	assert_int_equal(s.substeps, 7);
	assert_int_equal(s.intent, POPC_INTENT_SINE);
	assert_int_equal(popc_scene_set_assignment(&s, "environment.stiffness=1e6", &err), 0);
	assert_true(s.env_stiffness_Npm == 1e6);
	assert_int_equal(popc_scene_set_assignment(&s, "controller.variant=hold", &err), 0);
	assert_int_equal(s.variant, POPC_VARIANT_HOLD);
	assert_int_equal(popc_scene_validate(&s, &err), 0);
	/* a CR before each LF, and one ending the file, are line ends */
	path = write_scene("crlf.ini", "[run]\r\nrate = 500\r\nduration = 2\r");
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, path, &err), 0);
	assert_true(s.duration_s == 2.0 && s.rate_Hz == 500.0);
}

/* Every bad input is an error naming the file and line (or --set), the key
 * and, for values, the allowed range. */
static void test_bad_scenes(void **state)
{
	(void)state;
	const struct {
		const char *text;
		const char *must_contain[3];
	} cases[] = {
		/* inih reports sections through their first key: the key's line is named */
		/* an unknown section is named at its own line, with keys or without
		 * (an empty one was accepted: libinih reports keys only) */
		{"[run]\nduration = 5\n[nonsense]\nx = 1\n", {":3:", "unknown section [nonsense]; sections are run, operator", NULL}},
		{"[run]\nduration = 5\n[nonsense]\n", {":3:", "unknown section [nonsense]; sections are run, operator", NULL}},
		{"[nosuch]\n[run]\nduration = 5\n", {":1:", "unknown section [nosuch]", NULL}},
		{"[run]\nduration = 5\n[contoller]\n[controller]\nvariant = none\n", {":3:", "unknown section [contoller]", NULL}},
		/* CR-only line ends read as one line: "[run]" and the rest dropped,
		 * so the scene was the defaults */
		{"[run]\rduration = 2\r[operator]\rmass = 7\r", {":1:", "a carriage return (CR) inside the line", "CR-only"}},
		{"[run]\nduration = 2\rrate = 500\n", {":2:", "a carriage return (CR) inside the line", NULL}},
		{"[run]\nduraton = 5\n", {":2:", "unknown key run.duraton", "duration"}},
		/* a unit after the number: named, with the key's unit (issue 27) */
		{"[run]\nduration = 5s\n", {":2:", "run.duration", "units are not accepted ('s' after the number): give the number alone, in s"}},
		{"[environment]\nstiffness = 1000N/m\n", {":2:", "'1000N/m'", "units are not accepted ('N/m' after the number): give the number alone, in N/m"}},
		{"[environment]\nstiffness = 2 kN/m\n", {":2:", "environment.stiffness", "('kN/m' after the number)"}},
		{"[encoder]\nresolution = 1e-5m\n", {":2:", "encoder.resolution", "('m' after the number): give the number alone, in m"}},
		{"[run]\nduration = 5e\n", {":2:", "run.duration", "not a finite number"}},
		{"[run]\nduration = nan\n", {":2:", "run.duration", "(0, 1e+07] s"}},
		{"[run]\nduration = inf\n", {":2:", "run.duration", "not a finite number"}},
		{"[run]\nduration = 0x10\n", {":2:", "run.duration", NULL}},
		{"[run]\nduration =\n", {":2:", "run.duration", NULL}},
		{"[run]\nduration = 0\n", {":2:", "out of range", "(0, 1e+07] s"}},
		{"[operator]\nmass = -0.1\n", {":2:", "operator.mass", "[0, 1000] kg"}},
		{"[run]\nrate = 1e300\n", {":2:", "run.rate", "[1, 1e+06] Hz"}},
		{"[run]\nrate = 1000\nrate = 2000\n", {":3:", "run.rate given twice", NULL}},
		{"[controller]\nvariant = best\n", {":2:", "controller.variant", "improved"}},
		{"[integrator]\nsubsteps = 2.5\n", {":2:", "integrator.substeps", "whole number"}},
		{"[integrator]\nsubsteps = 0\n", {":2:", "integrator.substeps", "[1, 1e+06]"}},
		{"[run]\nthis line has no equals sign\n", {":2:", "malformed line", NULL}},
		{"duration = 5\n", {":1:", "unknown section []", NULL}},
		{"[encoder]\nresolution = 0\n", {":2:", "encoder.resolution", "(0, 1] m"}},
		{"[run]\ndelay_ticks = 1001\n", {":2:", "run.delay_ticks", "[0, 1000] periods"}},
		{"[run]\ndelay_ticks = -1\n", {":2:", "run.delay_ticks", "[0, 1000]"}},
		{"[controller]\nreversal_count = 0\n", {":2:", "controller.reversal_count", "[1, 64]"}},
		{"[controller]\nreversal_window = 0\n", {":2:", "controller.reversal_window", "[1, 1e+07] ticks"}},
		{"[controller]\npo_window = 4097\n", {":2:", "controller.po_window", "[1, 4096] ticks"}},
		{"[controller]\npo_velocity_floor = -1\n", {":2:", "controller.po_velocity_floor", "[0, 1000] m/s"}},
		{"[controller]\npo_damping_max = -1\n", {":2:", "controller.po_damping_max", "[0, 1e+09] N s/m"}},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		const char *path = write_scene("bad.ini", cases[i].text);
		popc_scene s;
		popc_error err = {{0}};
		popc_scene_defaults(&s);
		int st = popc_scene_load(&s, path, &err);
		if (st != POPC_ERR_INVALID)
			fail_msg("case %zu: status %d, expected an error: %s", i, st, cases[i].text);
		if (strncmp(err.msg, path, strlen(path)) != 0)
			fail_msg("case %zu: message does not start with the file: %s", i, err.msg);
		for (int j = 0; j < 3 && cases[i].must_contain[j]; j++)
			if (!strstr(err.msg, cases[i].must_contain[j]))
				fail_msg("case %zu: '%s' lacks '%s'", i, err.msg, cases[i].must_contain[j]);
	}
	popc_scene s;
	popc_error err;
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, "/nonexistent/x.ini", &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "/nonexistent/x.ini"));
}

/* libinih reads at most 199 characters of a line (INI_MAX_LINE 200 in Debian's
 * build) and parses the rest as a line of its own: the tail of a long comment
 * set a key, and every later message named the wrong line. A longer line is
 * refused with its real number; a line of exactly 199 characters is read. */
static void test_long_lines(void **state)
{
	(void)state;
	char x197[198], x200[201], text[1024];
	memset(x197, 'x', 197);
	x197[197] = '\0';
	memset(x200, 'x', 200);
	x200[200] = '\0';
	const char *expect = "line longer than 199 characters (libinih's limit)";
	struct {
		int line;
	} bad[4];
	char texts[4][1024];
	/* a comment whose tail is a key */
	snprintf(texts[0], sizeof texts[0], "[run]\n; %srate = 2000\n", x197);
	bad[0].line = 2;
	/* a long trailing comment after a good value */
	snprintf(texts[1], sizeof texts[1], "[run]\nrate = 2000\nduration = 5 ; %s\n", x200);
	bad[1].line = 3;
	/* a long table path: refused, not cut */
	snprintf(texts[2], sizeof texts[2], "[operator]\ntable = /tmp/%s%s.csv\n", x200, x200);
	bad[2].line = 2;
	/* 200 characters on the last line, no newline */
	snprintf(texts[3], sizeof texts[3], "[run]\nrate = 2000\n\n;%.199s", x200);
	bad[3].line = 4;
	for (int i = 0; i < 4; i++) {
		const char *path = write_scene("long.ini", texts[i]);
		popc_scene s;
		popc_error err = {{0}};
		popc_scene_defaults(&s);
		int st = popc_scene_load(&s, path, &err);
		char where[600];
		snprintf(where, sizeof where, "%s:%d: %s", path, bad[i].line, expect);
		if (st != POPC_ERR_INVALID || strcmp(err.msg, where) != 0)
			fail_msg("case %d: status %d, '%s'; expected '%s'", i, st, err.msg, where);
		assert_true(s.rate_Hz == 1000.0 || i == 1 || i == 3);
	}
	/* exactly 199 characters, with and without a newline after them */
	snprintf(text, sizeof text, "[run]\n;%.198s\nrate = 2000\nduration = 2 ;%.185s\n", x200, x200);
	popc_scene s;
	popc_error err = {{0}};
	popc_scene_defaults(&s);
	if (popc_scene_load(&s, write_scene("fits.ini", text), &err) != 0)
		fail_msg("%s", err.msg);
	assert_true(s.rate_Hz == 2000.0 && s.duration_s == 2.0);
	snprintf(text, sizeof text, "[run]\nrate = 3000\n;%.198s", x200);
	popc_scene_defaults(&s);
	if (popc_scene_load(&s, write_scene("fits.ini", text), &err) != 0)
		fail_msg("%s", err.msg);
	assert_true(s.rate_Hz == 3000.0);
	/* an error before a long line is named first */
	snprintf(text, sizeof text, "[run]\nrate 2000\n;%s\n", x200);
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, write_scene("both.ini", text), &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, ":2: malformed line"));
	/* a directory is not an empty scene */
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, tmpdir, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "cannot read scene"));
}

/* Numbers: subnormals are finite numbers (then the range decides); text that
 * rounds to 0 or to infinity is refused, saying which; blanks around a --set
 * value count as in a file (inih trims them there). */
static void test_number_text(void **state)
{
	(void)state;
	const struct {
		const char *assignment;
		double value;         /* when ok */
		const char *message;  /* NULL: accepted */
	} cases[] = {
		{"run.duration=5e-324", 5e-324, NULL},
		{"run.duration=2.5e-320", 2.5e-320, NULL},
		{"environment.position=-4.9e-324", -4.9e-324, NULL},
		{"run.duration=1e-400", 0, "below the smallest double"},
		{"run.duration=0.000000000000000000001e-310", 0, "below the smallest double"},
		{"environment.position=-1e-400", 0, "below the smallest double"},
		{"run.duration=1e400", 0, "above the largest double"},
		{"run.duration=0e-999", 0, "out of range"}, /* a true zero */
		{"environment.position=0e-999", 0.0, NULL},
		{"run.duration= 5", 5, NULL},
		{"run.duration=5 ", 5, NULL},
		{"run.duration=\t5\t ", 5, NULL},
		{"run.duration= ", 0, "not a finite number"},
		{"run.duration=5 5", 0, "not a finite number"},
		{"run.duration=inf", 0, "not a finite number"},
		{"run.duration=0x10", 0, "not a finite number"},
		{"run.duration=5 5", 0, "not a finite number"},
		{"environment.stiffness=1000N/m", 0, "units are not accepted ('N/m' after the number): give the number alone, in N/m"},
		{"controller.variant= hold ", POPC_VARIANT_HOLD, NULL},
		{" run . duration =7", 7, NULL},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_scene s;
		popc_error err = {{0}};
		popc_scene_defaults(&s);
		int st = popc_scene_set_assignment(&s, cases[i].assignment, &err);
		if (cases[i].message) {
			if (st != POPC_ERR_INVALID || !strstr(err.msg, cases[i].message))
				fail_msg("'%s': status %d '%s'; expected '%s'", cases[i].assignment, st,
					 err.msg, cases[i].message);
			continue;
		}
		if (st != 0)
			fail_msg("'%s': %s", cases[i].assignment, err.msg);
		double got = strstr(cases[i].assignment, "variant") ? (double)s.variant
			   : strstr(cases[i].assignment, "position") ? s.env_position_m
								      : s.duration_s;
		if (memcmp(&got, &cases[i].value, sizeof got) != 0)
			fail_msg("'%s': %.17g, expected %.17g", cases[i].assignment, got, cases[i].value);
	}
	/* the same rules in a file */
	popc_scene s;
	popc_error err = {{0}};
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, write_scene("sub.ini", "[run]\nduration = 5e-324 \n"),
					 &err), 0);
	assert_true(s.duration_s == 5e-324);
	assert_int_equal(popc_scene_load(&s, write_scene("uf.ini", "[operator]\nx0 = 1e-400\n"), &err),
			 POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, ":2: operator.x0 = '1e-400': below the smallest double"));
}

static void test_bad_overrides(void **state)
{
	(void)state;
	const struct {
		const char *assignment, *must_contain;
	} cases[] = {
		{"run.duration", "expected section.key=value"},
		{"duration=5", "expected section.key=value"},
		{"run.=5", "expected section.key=value"},
		{"run.duration=-1", "(0, 1e+07] s"},
		{"run.speed=1", "unknown key run.speed"},
		{"wall.stiffness=1", "unknown section [wall]"},
		{"controller.pc_bound=1e7", "(0, 1e+06] N"},
		{"controller.pc_bound=NaN", "not a finite number"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_scene s;
		popc_error err = {{0}};
		popc_scene_defaults(&s);
		assert_int_equal(popc_scene_set_assignment(&s, cases[i].assignment, &err), POPC_ERR_INVALID);
		if (!strstr(err.msg, cases[i].must_contain))
			fail_msg("'%s': '%s' lacks '%s'", cases[i].assignment, err.msg, cases[i].must_contain);
	}
}

static void test_cross_key_validation(void **state)
{
	(void)state;
	const char *sets[][2] = {
		{"operator.mass=0", "device.mass=0"},
		{"operator.x_end=-0.0065", NULL}, /* ends where it starts (x0) */
		{"operator.intent=table", NULL},
		{"operator.intent=sine", "operator.frequency=300"},
	};
	for (size_t i = 0; i < sizeof sets / sizeof sets[0]; i++) {
		popc_scene s;
		popc_error err;
		popc_scene_defaults(&s);
		for (int j = 0; j < 2 && sets[i][j]; j++)
			assert_int_equal(popc_scene_set_assignment(&s, sets[i][j], &err), 0);
		assert_int_equal(popc_scene_validate(&s, &err), POPC_ERR_INVALID);
	}
}

/* The resolved dump reads back to the same scene, bit for bit. */
static void test_dump_round_trip(void **state)
{
	(void)state;
	popc_scene s, r;
	popc_error err;
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_set_assignment(&s, "operator.speed=0.1234567890123456789", &err), 0);
	assert_int_equal(popc_scene_set_assignment(&s, "encoder.resolution=3.3e-7", &err), 0);
	assert_int_equal(popc_scene_set_assignment(&s, "environment.kind=spring", &err), 0);
	char path[512];
	snprintf(path, sizeof path, "%s/dump.ini", tmpdir);
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	popc_scene_write(&s, f, "");
	fclose(f);
	popc_scene_defaults(&r);
	assert_int_equal(popc_scene_load(&r, path, &err), 0);
	memset(r.source, 0, sizeof r.source);
	memset(s.source, 0, sizeof s.source);
	assert_memory_equal(&r, &s, sizeof s);
}

/* One rule for paths: relative to where they are written. A --set path is
 * relative to the working directory and made absolute (a scene file's are
 * relative to its directory: tests/cli); an absolute one is kept as given;
 * connect is a URI, not a path. */
static void test_set_paths_absolute(void **state)
{
	(void)state;
	char cwd[1024], want[1100];
	assert_non_null(getcwd(cwd, sizeof cwd));
	popc_scene s;
	popc_scene_defaults(&s);
	popc_error err;
	assert_int_equal(popc_scene_set_assignment(&s, "operator.table= rel/x.csv ", &err), 0);
	snprintf(want, sizeof want, "%s%srel/x.csv", cwd, cwd[1] ? "/" : "");
	assert_string_equal(s.op_table, want);
	assert_int_equal(popc_scene_set(&s, "axis", "map", "/abs/m.ini", &err), 0);
	assert_string_equal(s.axis_map, "/abs/m.ini");
	assert_int_equal(popc_scene_set(&s, "axis", "connect", "tcp:127.0.0.1:1502", &err), 0);
	assert_string_equal(s.axis_connect, "tcp:127.0.0.1:1502");
	assert_int_equal(popc_scene_key_is_path("operator", "table"), 1);
	assert_int_equal(popc_scene_key_is_path("axis", "map"), 1);
	assert_int_equal(popc_scene_key_is_path("axis", "connect"), 0);
	assert_int_equal(popc_scene_key_is_path("run", "duration"), 0);
	assert_int_equal(popc_scene_key_is_path("run", "nosuch"), 0);
	/* a path that fits alone but not once absolute is refused, not kept
	 * relative (it would name another file from another directory); the
	 * limit is a line of a scene file, "table = PATH" in libinih's 199
	 * characters, since the resolved scene is written as one and read back
	 * (popc scene show, a sweep's runs/<id>/scene.ini) */
	const size_t line_max = 199, prefix = strlen("table = ");
	char longrel[1024];
	memset(longrel, 'a', sizeof longrel - 1);
	longrel[line_max - prefix + 1] = '\0';
	assert_int_equal(popc_scene_set(&s, "operator", "table", longrel, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "too long for a line of a scene file"));
	if (strlen(cwd) + 1 + 1 < line_max - prefix) {
		size_t fits = line_max - prefix - strlen(cwd) - 1; /* cwd '/' longrel */
		longrel[fits] = '\0';
		assert_int_equal(popc_scene_set(&s, "operator", "table", longrel, &err), 0);
		assert_int_equal(strlen(s.op_table), line_max - prefix);
		longrel[fits] = 'a';
		longrel[fits + 1] = '\0';
		assert_int_equal(popc_scene_set(&s, "operator", "table", longrel, &err),
				 POPC_ERR_INVALID);
		assert_non_null(strstr(err.msg, "operator.table"));
		assert_non_null(strstr(err.msg, "the path from the working directory"));
		assert_non_null(strstr(err.msg, "too long for a line of a scene file"));
	}
	/* libinih reads "; x" after a blank as a comment: such a path would come
	 * back cut from a written scene */
	assert_int_equal(popc_scene_set(&s, "operator", "table", "/a ;b.csv", &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "comment"));
	assert_int_equal(popc_scene_set(&s, "operator", "table", "/a;b.csv", &err), 0);
}

/* A key found once and set by its index (a sweep's varied keys) gives the
 * scene, the status and the message popc_scene_set gives. */
static void test_set_index_is_set(void **state)
{
	(void)state;
	const struct {
		const char *section, *key, *value;
	} cases[] = {
		{"operator", "speed", "0.05"},     {"operator", "speed", " 0.07 "},
		{"operator", "speed", "-1"},       {"operator", "speed", "fast"},
		{"controller", "variant", "hold"}, {"controller", "variant", "sideways"},
		{"run", "duration", "1e999"},      {"environment", "stiffness", "2.5e4"},
		{"encoder", "resolution", "0"},    {"run", "rate", "1000.5"},
	};
	for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
		popc_scene a, b;
		popc_scene_defaults(&a);
		popc_scene_defaults(&b);
		popc_error ea, eb;
		memset(&ea, 0, sizeof ea);
		memset(&eb, 0, sizeof eb);
		int k = popc_scene_key_index(cases[c].section, cases[c].key);
		assert_true(k >= 0);
		int sa = popc_scene_set(&a, cases[c].section, cases[c].key, cases[c].value, &ea);
		int sb = popc_scene_set_index(&b, k, cases[c].value, &eb);
		assert_int_equal(sa, sb);
		if (sa)
			assert_string_equal(ea.msg, eb.msg);
		assert_memory_equal(&a, &b, sizeof a);
	}
	/* names trimmed as popc_scene_set trims them */
	assert_int_equal(popc_scene_key_index(" operator ", " speed "),
			 popc_scene_key_index("operator", "speed"));
	assert_int_equal(popc_scene_key_index("operator", "sped"), -1);
	assert_int_equal(popc_scene_key_index("plant", "speed"), -1);
	popc_scene s;
	popc_error e;
	popc_scene_defaults(&s);
	assert_int_not_equal(popc_scene_set_index(&s, -1, "1", &e), 0);
	assert_int_not_equal(popc_scene_set_index(&s, 100000, "1", &e), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_defaults_are_the_paper_scene),
		cmocka_unit_test(test_good_scene_and_overrides),
		cmocka_unit_test(test_bad_scenes),
		cmocka_unit_test(test_long_lines),
		cmocka_unit_test(test_number_text),
		cmocka_unit_test(test_bad_overrides),
		cmocka_unit_test(test_cross_key_validation),
		cmocka_unit_test(test_dump_round_trip),
		cmocka_unit_test(test_set_paths_absolute),
		cmocka_unit_test(test_set_index_is_set),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
