/* sweep_reference: the runs of a sweep and nothing else, the reference of
 * docs/BENCHMARKS.md section 6 ("the sweep's own cost").
 *
 *   sweep_reference SCENE [--set section.key=value]... --vary section.key=LIST...
 *
 * Makes every run of the product of the --vary lists in this one process, one
 * after the other, as a `popc sweep -j 1 --no-log` worker makes it: the run's
 * scene (the base scene with its values set, validated), the simulated axis,
 * the chatter detector on every tick, popc_run with a stop flag (never set
 * here; popc run and a sweep's runs check it every tick, 3 instructions a
 * tick). Nothing else: no checking of
 * every run before the first, no worker process, no summary text, no row, no
 * files. So the CPU of `popc sweep` minus the CPU of this program on the same
 * runs is what the sweep adds to its runs (its own cost), process start-up and
 * dynamic loading cancelling (both are linked alike).
 *
 * Prints the number of runs and of ticks, and the sum of the runs' pc_energy,
 * so that the runs are seen to be the sweep's (its summary.csv has the same). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/axes/axis.h"
#include "popc/core/controller.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"
#include "popc/sweep/sweep_chatter.h"
#include "popc/sweep/sweep_plan.h"

static volatile sig_atomic_t stop_flag;

static void feed_chatter(void *user, const popc_tick *tick)
{
	popc_chatter_add(user, tick);
}

static int usage(void)
{
	fputs("usage: sweep_reference SCENE [--set section.key=value]... --vary section.key=LIST...\n",
	      stderr);
	return 2;
}

int main(int argc, char **argv)
{
	if (argc < 4)
		return usage();
	popc_scene base;
	popc_error err;
	popc_scene_defaults(&base);
	if (popc_scene_load(&base, argv[1], &err) != 0) {
		fprintf(stderr, "sweep_reference: %s\n", err.msg);
		return 2;
	}
	popc_sweep_axis *axes = calloc((size_t)argc, sizeof *axes);
	int n_axes = 0;
	if (!axes)
		return 1;
	for (int k = 2; k + 1 < argc; k += 2) {
		int st;
		if (strcmp(argv[k], "--set") == 0)
			st = popc_scene_set_assignment(&base, argv[k + 1], &err);
		else if (strcmp(argv[k], "--vary") == 0)
			st = popc_sweep_axis_parse(argv[k + 1], &axes[n_axes++], &err);
		else
			return usage();
		if (st) {
			fprintf(stderr, "sweep_reference: %s\n", err.msg);
			return 2;
		}
	}
	popc_sweep_plan plan;
	/* no check of every run: the runs are checked as they are made */
	if (popc_sweep_plan_init(&plan, &base, axes, n_axes, 0, &err) != 0) {
		fprintf(stderr, "sweep_reference: %s\n", err.msg);
		return 2;
	}
	long long ticks = 0;
	double pc_energy_J = 0.0;
	for (long long i = 0; i < plan.n_runs; i++) {
		popc_scene s;
		popc_axis *axis = NULL;
		popc_controller_config ccfg;
		popc_chatter det;
		popc_chatter_result chat;
		popc_run_summary sum;
		int st = popc_sweep_run_scene(&plan, i, &s, &err);
		if (!st)
			st = popc_axis_create(&axis, &s, NULL, &err);
		if (!st) {
			popc_controller_config_from_scene(&ccfg, &s);
			st = popc_sweep_chatter_init(&det, &s, &ccfg, &err);
		}
		if (!st) {
			popc_run_options ro = {.stop_flag = &stop_flag, .on_tick = feed_chatter,
					       .tick_user = &det};
			st = popc_run(&s, axis, &ro, &sum, &err);
			popc_chatter_finish(&det, &chat);
			ticks += sum.ticks;
			pc_energy_J += sum.metrics.pc_energy_J;
		}
		popc_axis_destroy(&axis);
		if (st) {
			fprintf(stderr, "sweep_reference: run %lld: %s\n", i, err.msg);
			return 1;
		}
	}
	printf("%lld runs, %lld ticks, sum of pc_energy %.17g J\n", plan.n_runs, ticks, pc_energy_J);
	popc_sweep_plan_free(&plan);
	return 0;
}
