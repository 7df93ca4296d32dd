/* The control loop through libpopc's public API (popc_lib_sim_tick: the
 * port's step and the device's exchange in one call, the two that
 * examples/device_loop.c makes without its log), timed
 * as `popc bench loop` times popc_run's loop (src/cli/bench_common.c): the
 * scene run to 100 s at least, repeated until 0.2 s of this thread's CPU
 * time, the fastest of 3 such timings, ns per tick. docs/BENCHMARKS.md
 * section 11 runs both alternately.
 *
 *     lib_loop [SCENE [section.key=value ...]]     prints ns per tick */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "popc/popc.h"

static double thread_cpu_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
	popc_lib_error err;
	popc_lib_scene *s;
	int st = popc_lib_scene_create(&s, &err);
	/* a bare scene name is looked up as popc run looks it up */
	if (!st)
		st = popc_lib_scene_set_data_path(s, getenv("POPC_DATA_PATH"), &err);
	if (!st && argc > 1)
		st = popc_lib_scene_load(s, argv[1], &err);
	for (int i = 2; !st && i < argc; i++) {
		char key[128];
		const char *eq = strchr(argv[i], '=');
		if (!eq || (size_t)(eq - argv[i]) >= sizeof key) {
			fprintf(stderr, "lib_loop: '%s': expected section.key=value\n", argv[i]);
			return 2;
		}
		memcpy(key, argv[i], (size_t)(eq - argv[i]));
		key[eq - argv[i]] = '\0';
		st = popc_lib_scene_set(s, key, eq + 1, &err);
	}
	/* the bench's scene: at least 100 s, the exact integrator */
	if (!st && popc_lib_scene_tick_count(s) - 1 < (long long)(100.0 / popc_lib_scene_period_s(s)))
		st = popc_lib_scene_set(s, "run.duration", "100", &err);
	if (!st)
		st = popc_lib_scene_set(s, "integrator.method", "exact", &err);
	if (st) {
		fprintf(stderr, "lib_loop: %s\n", err.msg);
		return 2;
	}
	const long long n = popc_lib_scene_tick_count(s);
	double best = 1e300, sink = 0.0;
	for (int r = 0; r < 3; r++) {
		double cpu = 0.0;
		long long ticks = 0;
		do {
			popc_lib_port *port;
			popc_lib_sim *sim;
			popc_lib_sample smp;
			if (popc_lib_port_create_impedance(s, 0.0, &port, &err) ||
			    popc_lib_sim_create_options(s, POPC_LIB_SIM_NO_PORT_ENERGY, &sim, &smp,
							&err)) {
				fprintf(stderr, "lib_loop: %s\n", err.msg);
				return 1;
			}
			double c0 = thread_cpu_s();
			long long k = 0;
			popc_lib_tick t;
			/* the port's step and the device's exchange in one call
			 * (API 1.3); the last tick's command goes nowhere */
			for (; k + 1 < n; k++) {
				if (popc_lib_sim_tick(port, sim, &smp, &t, &err))
					break;
				sink += t.f_c_N;
			}
			if (k + 1 == n) {
				popc_lib_port_step(port, smp.count, &t);
				sink += t.f_c_N;
				k++;
			}
			cpu += thread_cpu_s() - c0;
			ticks += k;
			popc_lib_sim_free(sim);
			popc_lib_port_free(port);
		} while (cpu < 0.2);
		if (1e9 * cpu / (double)ticks < best)
			best = 1e9 * cpu / (double)ticks;
	}
	printf("%.6g\n", best);
	popc_lib_scene_free(s);
	return sink == sink ? 0 : 1; /* keeps the loop's commands */
}
