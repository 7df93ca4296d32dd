/* popc bench (cmd_bench.c): what the three benchmarks share. */
#ifndef POPC_CLI_BENCH_H
#define POPC_CLI_BENCH_H

#include <stdio.h>

#include "popc/axes/sim_axis.h"
#include "popc/util/clock.h" /* popc_now_s: every timing */
#include "popc/util/error.h"
#include "popc/scene/scene.h"

typedef struct bench_opts {
	const char *scene_path;   /* NULL: the built-in defaults (the paper's scene) */
	char **sets;
	int n_sets;
	int csv;                  /* --format csv or json: the CSV rows go to out */
	FILE *out;                /* stdout; for json a buffer that cmd_bench.c turns into JSON Lines */
	const char *plot_dir;
	double min_time_s;        /* wall time each timing measurement accumulates */
	int repeats;              /* timing repeats; the fastest is reported */
	long rows;                /* log rows (bench log) */
	const char *dir;          /* scratch directory for log files */
} bench_opts;

/* A recording axis: delegates to the sim axis, keeps every f_c it is sent. */
typedef struct recorder {
	popc_axis *inner;
	double *f_c;
	long long n, cap;
} recorder;

/* The exact closed-loop run of the scene; rec->f_c holds its commands
 * (freed by the caller). */
int bench_reference_forces(const popc_scene *s0, recorder *rec, popc_error *err);

/* Max |x - x_exact| at the samples when the integrator is fed the recorded
 * forces open loop. Returns 0, or POPC_ERR_NUMERIC (POPC_ERR_DIVERGED) when
 * the integrator was stopped as unstable (*tick_out: where). */
int bench_replay_error(const popc_scene *s0, popc_integrator m, int substeps, const recorder *rec,
		       double *err_m, long long *tick_out, popc_error *err);

/* Closed-loop time per control step (ns), no log, shadow off, the summary
 * unread (popc run -q): the fastest of
 * o->repeats measurements, each repeating the run until o->min_time_s passed. */
int bench_loop_ns_per_tick(const popc_scene *s0, popc_integrator m, int substeps,
			   const bench_opts *o, double *ns, popc_error *err);

/* The CPU time (user + system) of `popc run` as a whole process: this
 * program run on o->scene_path with o->sets and run.duration = duration_s,
 * -q (bench_process.c). Needs o->scene_path. */
int bench_process_cpu_s(const bench_opts *o, double duration_s, double *cpu_s, popc_error *err);

/* The benchmarks: exit codes. */
int bench_integrators(const popc_scene *s, const bench_opts *o);
int bench_loop(const popc_scene *s0, const bench_opts *o);
int bench_log(const popc_scene *s, const bench_opts *o);

#endif
