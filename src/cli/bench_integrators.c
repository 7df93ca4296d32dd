/* popc bench integrators: the work-precision table and figure (bench.h).
 *
 * Fair error comparison: with a PC in the loop, an integrator's trajectory
 * leaves the exact one as soon as one encoder count differs (the PC is a
 * switching law), and the difference is then the controller's, not the
 * integrator's. So every integrator is fed the same force sequence: the f_c(k)
 * of the exact closed-loop run of the scene, replayed open loop through the
 * simulated axis, whose exact shadow measures max |x - x_exact| at the samples.
 * The time per control step is measured closed loop (controller + plant, no
 * log, shadow off): what a user pays per tick for that integrator. */
#include "bench.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "popc/core/plant.h"

#define N_METHODS 5
static const popc_integrator methods[N_METHODS] = {
	POPC_INTEGRATOR_EXACT, POPC_INTEGRATOR_TRAPEZOID, POPC_INTEGRATOR_RK4,
	POPC_INTEGRATOR_SEMI_IMPLICIT_EULER, POPC_INTEGRATOR_EULER,
};
/* Substep sweep: powers of two (a clean log-log slope) plus the paper's 100. */
static const int sweep[] = {1, 2, 4, 8, 16, 32, 64, 100, 128, 256, 512, 1024};
#define N_SWEEP ((int)(sizeof sweep / sizeof sweep[0]))

typedef struct wp_point {
	int substeps;
	double error_m, ns;
	int unstable;              /* stopped by the sim axis' stability guards */
	long long tick;
	char why[24];              /* which guard */
} wp_point;

/* Least-squares slope of -log(error) against log(substeps) over the points
 * above the rounding floor: the measured order of convergence. */
static double fit_order(const wp_point *p, int n, double floor_m, int *used)
{
	double sx = 0, sy = 0, sxx = 0, sxy = 0;
	int k = 0;
	for (int i = 0; i < n; i++) {
		if (p[i].unstable || !(p[i].error_m > floor_m) || !isfinite(p[i].error_m))
			continue;
		double x = log((double)p[i].substeps), y = -log(p[i].error_m);
		sx += x;
		sy += y;
		sxx += x * x;
		sxy += x * y;
		k++;
	}
	*used = k;
	if (k < 2)
		return (double)NAN;
	return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

static int write_plot(const char *dir, const wp_point pts[N_METHODS][N_SWEEP], const int *npts,
		      const double *order, double exact_ns, double floor_m)
{
	char path[POPC_PATH_MAX + 32];
	snprintf(path, sizeof path, "%s/integrators.dat", dir);
	FILE *f = fopen(path, "w");
	if (!f) {
		fprintf(stderr, "popc bench: %s: %s\n", path, strerror(errno));
		return -1;
	}
	fprintf(f, "# popc bench integrators: ns_per_step max_error_m substeps; one block per "
		   "integrator\n");
	for (int m = 1; m < N_METHODS; m++) {
		fprintf(f, "# %s\n", popc_integrator_name(methods[m]));
		for (int i = 0; i < npts[m]; i++)
			if (!pts[m][i].unstable && pts[m][i].error_m > 0)
				fprintf(f, "%.6g %.6g %d\n", pts[m][i].ns, pts[m][i].error_m,
					pts[m][i].substeps);
		fputs("\n\n", f);
	}
	fclose(f);
	snprintf(path, sizeof path, "%s/integrators.gp", dir);
	f = fopen(path, "w");
	if (!f) {
		fprintf(stderr, "popc bench: %s: %s\n", path, strerror(errno));
		return -1;
	}
	fprintf(f, "# popc bench integrators --plot: work-precision diagram (gnuplot %s)\n"
		   "set terminal pngcairo size 900,640 noenhanced\n"
		   "set output 'integrators.png'\n"
		   "set logscale xy\n"
		   "set format y '1e%%L'\n"
		   "set xlabel 'time per control step (ns), closed loop, no log'\n"
		   "set ylabel 'max |x - x_exact| at the samples (m)'\n"
		   "set title 'work-precision, same force sequence for every integrator'\n"
		   "set grid\n"
		   "set key top right\n"
		   "set arrow from %.6g, graph 0 to %.6g, graph 1 nohead dt 2 lc rgb 'black'\n"
		   "set label 'exact (the reference, error 0)' at %.6g, graph 0.05 rotate by 90 "
		   "offset -1,0\n",
		"5", exact_ns, exact_ns, exact_ns);
	fprintf(f, "set label 'rounding floor %.2g m' at graph 0.6, first %.6g offset 0,0.6\n"
		   "set arrow from graph 0, first %.6g to graph 1, first %.6g nohead dt 3 lc rgb "
		   "'gray'\n",
		floor_m, floor_m, floor_m, floor_m);
	/* the measured order beside each curve, at its last point above the floor */
	for (int m = 1; m < N_METHODS; m++) {
		int last = -1;
		for (int i = 0; i < npts[m]; i++)
			if (!pts[m][i].unstable && pts[m][i].error_m > floor_m)
				last = i;
		/* alternate above and below the point: euler and semi-implicit euler
		 * end close together */
		if (last >= 0 && isfinite(order[m]))
			fprintf(f, "set label 'p = %.2f' at %.6g, %.6g offset 1,%d tc ls %d\n", order[m],
				pts[m][last].ns, pts[m][last].error_m, m % 2 ? 1 : -1, m);
	}
	fputs("plot ", f);
	for (int m = 1; m < N_METHODS; m++)
		fprintf(f, "%s'integrators.dat' index %d using 1:2 with linespoints ls %d title '%s'",
			m > 1 ? ", \\\n     " : "", m - 1, m, popc_integrator_name(methods[m]));
	fputs("\n", f);
	fclose(f);
	/* gnuplot runs in DIR (the script names its files relatively); no shell,
	 * so a directory name needs no quoting */
	int status = -1;
	pid_t pid = fork();
	if (pid == 0) {
		if (chdir(dir) == 0)
			execlp("gnuplot", "gnuplot", "integrators.gp", (char *)NULL);
		_exit(127);
	}
	if (pid > 0)
		while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
			;
	if (pid < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
		fprintf(stderr, "popc bench: gnuplot failed on %s/integrators.gp\n", dir);
		return -1;
	}
	return 0;
}

int bench_integrators(const popc_scene *s, const bench_opts *o)
{
	popc_error err;
	recorder rec;
	int st = bench_reference_forces(s, &rec, &err);
	if (st) {
		free(rec.f_c);
		return popc_cli_fail("bench", st, &err);
	}
	/* rounding floor: a few hundred ulps of the largest position */
	double x_scale = fmax(fabs(s->op_x0_m), fabs(s->op_x_end_m));
	double floor_m = 256.0 * DBL_EPSILON * fmax(x_scale, 1e-3);

	static wp_point pts[N_METHODS][N_SWEEP];
	int npts[N_METHODS] = {0};
	double order[N_METHODS];
	int used[N_METHODS] = {0};
	double exact_ns = 0.0;
	st = bench_loop_ns_per_tick(s, POPC_INTEGRATOR_EXACT, 1, o, &exact_ns, &err);
	if (st) {
		free(rec.f_c);
		return popc_cli_fail("bench", st, &err);
	}
	for (int m = 1; m < N_METHODS; m++) {
		for (int i = 0; i < N_SWEEP; i++) {
			wp_point *p = &pts[m][npts[m]++];
			p->substeps = sweep[i];
			popc_error e2;
			int rst = bench_replay_error(s, methods[m], sweep[i], &rec, &p->error_m, &p->tick, &e2);
			p->unstable = rst == POPC_ERR_NUMERIC || rst == POPC_ERR_DIVERGED;
			snprintf(p->why, sizeof p->why, "%s",
				 strstr(e2.msg, "made up") ? "made-up energy"
				 : strstr(e2.msg, "free motion would grow") ? "growth bound"
				 : strstr(e2.msg, "position error") ? "error bound"
									 : "diverged");
			if (rst && !p->unstable) {
				free(rec.f_c);
				return popc_cli_fail("bench", rst, &e2);
			}
			p->ns = (double)NAN;
			if (!p->unstable) {
				rst = bench_loop_ns_per_tick(s, methods[m], sweep[i], o, &p->ns, &e2);
				if (rst && rst != POPC_ERR_NUMERIC && rst != POPC_ERR_DIVERGED) {
					free(rec.f_c);
					return popc_cli_fail("bench", rst, &e2);
				}
			}
		}
		order[m] = fit_order(pts[m], npts[m], floor_m, &used[m]);
	}
	if (o->csv) {
		fprintf(o->out, "%s\n", "integrator,substeps,h_s,max_error_m,ns_per_step,status");
		fprintf(o->out, "exact,1,%.6g,0,%.6g,reference\n", popc_scene_period_s(s), exact_ns);
		for (int m = 1; m < N_METHODS; m++)
			for (int i = 0; i < npts[m]; i++) {
				const wp_point *p = &pts[m][i];
				fprintf(o->out, "%s,%d,%.6g,%.6g,%.6g,%s\n", popc_integrator_name(methods[m]),
				       p->substeps, popc_scene_period_s(s) / p->substeps, p->error_m, p->ns,
				       p->unstable ? "stopped" : "ok");
			}
	} else {
		printf("popc bench integrators: %s, %lld control steps at %g Hz, variant %s\n",
		       s->source[0] ? s->source : "built-in paper scene", rec.n + 1, s->rate_Hz,
		       popc_variant_name(s->variant));
		printf("error: max |x - x_exact| at the samples, every integrator fed the exact "
		       "run's f_c open loop\n");
		printf("time: closed loop (controller + plant), no log, fastest of %d x %.2g s\n\n",
		       o->repeats, o->min_time_s);
		printf("%-20s %9s %12s %14s\n", "integrator", "substeps", "error (m)", "ns per step");
		printf("%-20s %9s %12s %14.1f\n", "exact", "-", "0 (ref)", exact_ns);
		for (int m = 1; m < N_METHODS; m++) {
			for (int i = 0; i < npts[m]; i++) {
				const wp_point *p = &pts[m][i];
				if (p->unstable)
					printf("%-20s %9d %12s %14s  (at tick %lld: %s)\n",
					       popc_integrator_name(methods[m]), p->substeps, "stopped", "-",
					       p->tick, p->why);
				else
					printf("%-20s %9d %12.3g %14.1f\n", popc_integrator_name(methods[m]),
					       p->substeps, p->error_m, p->ns);
			}
			if (isfinite(order[m]))
				printf("  %s: measured order %.2f (least squares over %d points above the "
				       "rounding floor %.2g m)\n",
				       popc_integrator_name(methods[m]), order[m], used[m], floor_m);
			else
				printf("  %s: order not measurable (fewer than 2 points above the rounding "
				       "floor %.2g m)\n",
				       popc_integrator_name(methods[m]), floor_m);
		}
	}
	free(rec.f_c);
	if (o->plot_dir && write_plot(o->plot_dir, (const wp_point(*)[N_SWEEP])pts, npts, order,
				      exact_ns, floor_m) != 0)
		return POPC_EXIT_RUN_FAILED;
	return 0;
}
