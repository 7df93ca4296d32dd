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

#include "popc/scene.h"

static char tmpdir[256];

static int setup(void **state)
{
	(void)state;
	snprintf(tmpdir, sizeof tmpdir, "/tmp/popc-test-scene-XXXXXX");
	return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown(void **state)
{
	(void)state;
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	return system(cmd) == 0 ? 0 : -1;
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
						   "ignore_mode = undo\n[integrator]\nmethod = rk4\n"
						   "substeps = 7\n[operator]\nintent = sine\n");
	popc_scene s;
	popc_error err;
	popc_scene_defaults(&s);
	assert_int_equal(popc_scene_load(&s, path, &err), 0);
	assert_true(s.duration_s == 2.5 && s.rate_Hz == 2000.0);
	assert_int_equal(s.variant, POPC_VARIANT_IMPROVED);
	assert_int_equal(s.ignore_mode, POPC_IGNORE_UNDO);
	assert_int_equal(s.integrator, POPC_INTEGRATOR_RK4);
	assert_int_equal(s.substeps, 7);
	assert_int_equal(s.intent, POPC_INTENT_SINE);
	assert_int_equal(popc_scene_set_assignment(&s, "environment.stiffness=1e6", &err), 0);
	assert_true(s.env_stiffness_Npm == 1e6);
	assert_int_equal(popc_scene_set_assignment(&s, "controller.variant=hold", &err), 0);
	assert_int_equal(s.variant, POPC_VARIANT_HOLD);
	assert_int_equal(popc_scene_validate(&s, &err), 0);
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
		{"[run]\nduration = 5\n[nonsense]\nx = 1\n", {":4:", "unknown section [nonsense]", NULL}},
		{"[run]\nduraton = 5\n", {":2:", "unknown key run.duraton", "duration"}},
		{"[run]\nduration = 5s\n", {":2:", "run.duration", "not a finite number"}},
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
		{"operator.x_end=-0.01", NULL},
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

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_defaults_are_the_paper_scene),
		cmocka_unit_test(test_good_scene_and_overrides),
		cmocka_unit_test(test_bad_scenes),
		cmocka_unit_test(test_bad_overrides),
		cmocka_unit_test(test_cross_key_validation),
		cmocka_unit_test(test_dump_round_trip),
	};
	return cmocka_run_group_tests(tests, setup, teardown);
}
