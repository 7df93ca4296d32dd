/* popc bench integrators|loop|log: speed against error (DESIGN section 7).
 *
 * integrators  work-precision: for each integrator and substep count, the
 *              maximum position error over the logged samples against the
 *              exact discretization, and the time per control step.
 * loop         the control loop without logging, exact against the paper's
 *              scheme (trapezoid at 100 substeps), side by side.
 * log          log writing against printf("%.17g"), log reading + energy
 *              recompute against strtod, and the reader's memory.
 *
 * Fair error comparison: with a PC in the loop, an integrator's trajectory
 * leaves the exact one as soon as one encoder count differs (the PC is a
 * switching law), and the difference is then the controller's, not the
 * integrator's. So every integrator is fed the same force sequence: the f_c(k)
 * of the exact closed-loop run of the scene, replayed open loop through the
 * simulated axis, whose exact shadow measures max |x - x_exact| at the samples.
 * The time per control step is measured closed loop (controller + plant, no
 * log, shadow off): what a user pays per tick for that integrator. */
#include <errno.h>
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench_floor.h"
#include "cli.h"
#include "popc/axis.h"
#include "popc/controller.h"
#include "popc/encoder.h"
#include "popc/log.h"
#include "popc/log_reader.h"
#include "popc/numfmt.h"
#include "popc/plant.h"
#include "popc/sweep.h"
#include "popc/run.h"

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- options shared by the sub-benchmarks ---- */

typedef struct bench_opts {
	const char *scene_path;   /* NULL: the built-in defaults (the paper's scene) */
	char **sets;
	int n_sets;
	int csv;
	const char *plot_dir;
	double min_time_s;        /* wall time each timing measurement accumulates */
	int repeats;              /* timing repeats; the fastest is reported */
	long rows;                /* log rows (bench log) */
	const char *dir;          /* scratch directory for log files */
} bench_opts;

static void usage(FILE *f)
{
	fputs("usage: popc bench integrators|loop|log [options]\n"
	      "\n"
	      "Measures popc's speed against its error (DESIGN section 7).\n"
	      "  integrators  work-precision table: per integrator and substep count, the max\n"
	      "               position error against the exact discretization (same force\n"
	      "               sequence for all: the exact run's f_c, replayed open loop) and\n"
	      "               the closed-loop time per control step; measured orders\n"
	      "  loop         control loop without logging: exact vs trapezoid at 100 substeps,\n"
	      "               and the tick's dependency chain alone (the floor any\n"
	      "               implementation of the tick meets)\n"
	      "  log          log writing vs printf(\"%.17g\"), reading + energy recompute vs\n"
	      "               strtod, reader memory for two log lengths\n"
	      "\n"
	      "  --scene FILE             scene (default: the built-in paper scene)\n"
	      "  --set section.key=value  override a scene key (repeatable)\n"
	      "  --format text|csv        output format (default text)\n"
	      "  --plot DIR               integrators: write DIR/integrators.{dat,gp,png}\n"
	      "                           (DIR and its parents are made if missing)\n"
	      "  --min-time S             wall time per timing (default 0.2 s)\n"
	      "  --repeat N               timing repeats, fastest kept (default 3)\n"
	      "  --rows N                 log: rows per log (default 200000)\n"
	      "  --dir DIR                log: scratch directory (default $TMPDIR or /tmp)\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 1 failed, 2 usage. Figures and how to read them:\n"
	      "docs/BENCHMARKS.md.\n",
	      f);
}

/* ---- a recording axis: delegates to the sim axis, keeps every f_c ---- */

typedef struct recorder {
	popc_axis *inner;
	double *f_c;
	long long n, cap;
} recorder;

static int rec_start(popc_axis *a, popc_error *err)
{
	recorder *r = a->priv;
	return r->inner->ops->start(r->inner, err);
}

static int rec_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	recorder *r = a->priv;
	return r->inner->ops->sample(r->inner, out, err);
}

static int rec_exchange(popc_axis *a, double f_c_N, popc_axis_sample *next, popc_error *err)
{
	recorder *r = a->priv;
	if (r->n == r->cap) {
		long long cap = r->cap ? 2 * r->cap : 4096;
		double *g = realloc(r->f_c, (size_t)cap * sizeof *g);
		if (!g)
			return popc_error_set(err, POPC_ERR_NOMEM, "bench: out of memory");
		r->f_c = g;
		r->cap = cap;
	}
	r->f_c[r->n++] = f_c_N;
	return r->inner->ops->exchange(r->inner, f_c_N, next, err);
}

static int rec_stop(popc_axis *a, popc_error *err)
{
	recorder *r = a->priv;
	return r->inner->ops->stop(r->inner, err);
}

static void rec_destroy(popc_axis *a)
{
	(void)a;
}

static const popc_axis_ops recorder_ops = {
	.name = "sim",
	.log_columns = POPC_LOG_COL_X_TRUE,
	.start = rec_start,
	.sample = rec_sample,
	.exchange = rec_exchange,
	.stop = rec_stop,
	.report = NULL,
	.destroy = rec_destroy,
};

/* The exact closed-loop run of the scene; returns its f_c sequence. */
static int reference_forces(const popc_scene *s0, recorder *rec, popc_error *err)
{
	popc_scene s = *s0;
	s.integrator = POPC_INTEGRATOR_EXACT;
	memset(rec, 0, sizeof *rec);
	int st = popc_sim_axis_create(&rec->inner, &s, err);
	if (st)
		return st;
	popc_axis ax = {.ops = &recorder_ops, .priv = rec};
	popc_run_summary sum;
	st = popc_run(&s, &ax, NULL, &sum, err);
	popc_axis_destroy(&rec->inner);
	return st;
}

/* Max |x - x_exact| at the samples when the integrator is fed the forces
 * open loop. Returns 0, or POPC_ERR_NUMERIC (POPC_ERR_DIVERGED) when the integrator was stopped
 * as unstable (*tick_out: where). */
static int replay_error(const popc_scene *s0, popc_integrator m, int substeps, const recorder *rec,
			double *err_m, long long *tick_out, popc_error *err)
{
	popc_scene s = *s0;
	s.integrator = m;
	s.substeps = substeps;
	popc_axis *ax;
	int st = popc_sim_axis_create(&ax, &s, err);
	if (st)
		return st;
	popc_axis_sample smp;
	st = ax->ops->start(ax, err);
	if (!st)
		st = ax->ops->sample(ax, &smp, err);
	long long k = 0;
	for (; !st && k < rec->n; k++)
		st = ax->ops->exchange(ax, rec->f_c[k], &smp, err);
	*err_m = popc_sim_axis_max_error(ax);
	*tick_out = k;
	popc_error e2;
	ax->ops->stop(ax, &e2);
	popc_axis_destroy(&ax);
	return st;
}

/* Closed-loop time per control step (ns), no log, shadow off: the fastest of
 * `repeats` measurements, each repeating the run until min_time_s passed. */
static int loop_ns_per_tick(const popc_scene *s0, popc_integrator m, int substeps,
			    const bench_opts *o, double *ns, popc_error *err)
{
	popc_scene s = *s0;
	s.integrator = m;
	s.substeps = substeps;
	double best = INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		double wall = 0.0;
		long long ticks = 0;
		do {
			popc_axis *ax;
			int st = popc_sim_axis_create(&ax, &s, err);
			if (st)
				return st;
			popc_sim_axis_set_shadow(ax, 0);
			popc_run_summary sum;
			st = popc_run(&s, ax, NULL, &sum, err);
			popc_axis_destroy(&ax);
			if (st && sum.ticks < 2)
				return st;
			wall += sum.wall_time_s;
			ticks += sum.ticks;
		} while (wall < o->min_time_s);
		double v = 1e9 * wall / (double)ticks;
		if (v < best)
			best = v;
	}
	*ns = best;
	return 0;
}

/* ---- bench integrators ---- */

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
		return NAN;
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

static int bench_integrators(const popc_scene *s, const bench_opts *o)
{
	popc_error err;
	recorder rec;
	int st = reference_forces(s, &rec, &err);
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
	st = loop_ns_per_tick(s, POPC_INTEGRATOR_EXACT, 1, o, &exact_ns, &err);
	if (st) {
		free(rec.f_c);
		return popc_cli_fail("bench", st, &err);
	}
	for (int m = 1; m < N_METHODS; m++) {
		for (int i = 0; i < N_SWEEP; i++) {
			wp_point *p = &pts[m][npts[m]++];
			p->substeps = sweep[i];
			popc_error e2;
			int rst = replay_error(s, methods[m], sweep[i], &rec, &p->error_m, &p->tick, &e2);
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
			p->ns = NAN;
			if (!p->unstable) {
				rst = loop_ns_per_tick(s, methods[m], sweep[i], o, &p->ns, &e2);
				if (rst && rst != POPC_ERR_NUMERIC && rst != POPC_ERR_DIVERGED) {
					free(rec.f_c);
					return popc_cli_fail("bench", rst, &e2);
				}
			}
		}
		order[m] = fit_order(pts[m], npts[m], floor_m, &used[m]);
	}
	if (o->csv) {
		puts("integrator,substeps,h_s,max_error_m,ns_per_step,status");
		printf("exact,1,%.6g,0,%.6g,reference\n", popc_scene_period_s(s), exact_ns);
		for (int m = 1; m < N_METHODS; m++)
			for (int i = 0; i < npts[m]; i++) {
				const wp_point *p = &pts[m][i];
				printf("%s,%d,%.6g,%.6g,%.6g,%s\n", popc_integrator_name(methods[m]),
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
		return 1;
	return 0;
}

/* ---- bench loop ---- */

/* Plant step alone, ns per control period (constant input). */
static double plant_ns(const popc_scene *s0, popc_integrator m, int substeps, const bench_opts *o)
{
	popc_scene s = *s0;
	s.integrator = m;
	s.substeps = substeps;
	popc_plant_config cfg;
	popc_plant_config_from_scene(&cfg, &s);
	popc_plant p;
	if (popc_plant_init(&p, &cfg, NULL) != 0)
		return NAN;
	popc_plant_input u = {0.5, 0.0, 0.0, 0.0};
	double best = INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		popc_plant_state st = {-0.01, 0.0};
		long long n = 0;
		double t0 = now_s(), dt;
		do {
			for (int i = 0; i < 10000; i++)
				popc_plant_step(&p, &st, &u);
			n += 10000;
			dt = now_s() - t0;
		} while (dt < o->min_time_s / 4);
		if (!isfinite(st.x_m)) /* keeps the loop and tells if the step diverged */
			return NAN;
		if (1e9 * dt / (double)n < best)
			best = 1e9 * dt / (double)n;
	}
	return best;
}

static int bench_loop(const popc_scene *s0, const bench_opts *o)
{
	popc_error err;
	popc_scene s = *s0;
	/* long enough that start-up is noise; the summary's ns per tick */
	if (s.duration_s < 100)
		s.duration_s = 100;
	double ex_ns, tr_ns;
	int st = loop_ns_per_tick(&s, POPC_INTEGRATOR_EXACT, 1, o, &ex_ns, &err);
	if (!st)
		st = loop_ns_per_tick(&s, POPC_INTEGRATOR_TRAPEZOID, 100, o, &tr_ns, &err);
	if (st)
		return popc_cli_fail("bench", st, &err);
	/* the commands of the real loop over the timed scene: the reference of the
	 * trapezoid's error (over the scene's own duration) and of the stripped tick */
	recorder rec;
	st = reference_forces(s0, &rec, &err);
	double tr_err = NAN;
	long long tick;
	if (!st)
		st = replay_error(s0, POPC_INTEGRATOR_TRAPEZOID, 100, &rec, &tr_err, &tick, &err);
	free(rec.f_c);
	popc_tick_floor fl;
	if (!st) {
		st = reference_forces(&s, &rec, &err);
		if (!st)
			st = popc_bench_tick_floor(&s, rec.f_c, rec.n, o->min_time_s, o->repeats, &fl,
						   &err);
		free(rec.f_c);
	}
	if (st)
		return popc_cli_fail("bench", st, &err);
	double pex = plant_ns(&s, POPC_INTEGRATOR_EXACT, 1, o);
	double ptr = plant_ns(&s, POPC_INTEGRATOR_TRAPEZOID, 100, o);
	double ticks_per_s = 1e9 / ex_ns;
	/* the best ratio any implementation of this tick could show: the chain
	 * alone against the chain whose exact step is swapped for the trapezoid's */
	double fl_ns = fl.ns_per_tick;
	double best_ratio = (fl_ns - pex + ptr) / fl_ns;
	if (o->csv) {
		puts("what,exact,trapezoid_100,ratio");
		printf("loop_ns_per_tick,%.6g,%.6g,%.4g\n", ex_ns, tr_ns, tr_ns / ex_ns);
		printf("plant_ns_per_period,%.6g,%.6g,%.4g\n", pex, ptr, ptr / pex);
		printf("chain_floor_ns_per_tick,%.6g,%.6g,%.4g\n", fl_ns, fl_ns - pex + ptr, best_ratio);
		printf("chain_commands_equal,%d,,\n", fl.bitwise_equal);
		printf("max_error_m,0,%.6g,\n", tr_err);
		printf("exact_ticks_per_s,%.6g,,\n", ticks_per_s);
		return 0;
	}
	printf("popc bench loop: %s, no log, one core, fastest of %d\n",
	       s0->source[0] ? s0->source : "built-in paper scene", o->repeats);
	printf("%-34s %14s %16s %8s\n", "", "exact", "trapezoid x100", "ratio");
	printf("%-34s %14.2f %16.2f %8.1f\n", "control loop, ns per tick", ex_ns, tr_ns,
	       tr_ns / ex_ns);
	printf("%-34s %14.2f %16.2f %8.1f\n", "plant step alone, ns per period", pex, ptr, ptr / pex);
	if (fl.bitwise_equal)
		printf("%-34s %14.2f %16.2f %8.1f\n", "tick's dependency chain alone, ns", fl_ns,
		       fl_ns - pex + ptr, best_ratio);
	printf("%-34s %14s %16.3g\n", "max position error vs exact (m)", "0 (ref)", tr_err);
	printf("exact loop: %.3g million ticks per second (target >= 20: %s)\n"
	       "control loop %.1f x faster than the paper's scheme (target >= 50: %s)\n"
	       "plant step alone %.1f x faster (the controller, not the plant, costs the rest of "
	       "the loop)\n",
	       ticks_per_s / 1e6, ticks_per_s >= 20e6 ? "met" : "NOT met", tr_ns / ex_ns,
	       tr_ns / ex_ns >= 50 ? "met" : "NOT met", ptr / pex);
	if (fl.bitwise_equal)
		printf("dependency chain: the tick stripped to its arithmetic (no metrics, guards or "
		       "calls;\n  its %lld commands equal the loop's bit for bit) costs %.1f ns; with "
		       "this arithmetic\n  the ratio cannot pass %.1f x; 50 x needs the whole tick in "
		       "<= %.2f ns\n",
		       fl.ticks_checked, fl_ns, best_ratio, tr_ns / 50.0);
	else if (fl.not_covered)
		printf("dependency chain: not measured for this scene (%s)\n", fl.not_covered);
	else
		printf("dependency chain: not measured: its command at tick %lld differs from the "
		       "loop's\n",
		       fl.first_difference);
	return 0;
}

/* ---- bench log ---- */

/* The rows of one run of the scene (its integrator, closed loop) lasting
 * n ticks. */
static popc_log_row *make_rows(const popc_scene *s0, long n, popc_error *err)
{
	popc_scene s = *s0;
	s.duration_s = (double)(n - 1) * popc_scene_period_s(&s);
	popc_log_row *rows = malloc((size_t)n * sizeof *rows);
	if (!rows) {
		popc_error_set(err, POPC_ERR_NOMEM, "bench: out of memory for %ld rows", n);
		return NULL;
	}
	popc_controller_config cc;
	popc_controller_config_from_scene(&cc, &s);
	popc_controller ctl;
	popc_controller_init(&ctl, &cc);
	popc_axis *ax;
	if (popc_sim_axis_create(&ax, &s, err) != 0) {
		free(rows);
		return NULL;
	}
	popc_axis_sample smp;
	int st = ax->ops->sample(ax, &smp, err);
	for (long i = 0; !st && i < n; i++) {
		popc_log_row *r = &rows[i];
		r->tick.t_s = (double)i * popc_scene_period_s(&s);
		popc_controller_step(&ctl, smp.count, popc_encoder_position(smp.count, s.enc_resolution_m),
				     &r->tick);
		r->x_true_m = smp.x_true_m;
		r->dt_s = r->rtt_s = 0.0;
		if (i + 1 < n)
			st = ax->ops->exchange(ax, r->tick.f_c_N, &smp, err);
	}
	popc_axis_destroy(&ax);
	if (st) {
		free(rows);
		return NULL;
	}
	return rows;
}

/* A log of the scene run for `ticks` ticks, written by popc run's own loop. */
static int run_to_log(const popc_scene *s0, long long ticks, const char *path, popc_error *err)
{
	popc_scene s = *s0;
	s.duration_s = (double)(ticks - 1) * popc_scene_period_s(&s);
	popc_axis *ax;
	int st = popc_sim_axis_create(&ax, &s, err);
	if (st)
		return st;
	popc_log_writer w;
	st = popc_log_open(&w, path, ax->ops->log_columns, err);
	if (!st)
		st = popc_log_write_header(&w, "sim", &s, NULL, err);
	if (!st) {
		popc_run_options ro = {.log = &w, .stop_flag = NULL};
		popc_run_summary sum;
		st = popc_run(&s, ax, &ro, &sum, err);
	}
	popc_error e2;
	int cst = popc_log_close(&w, &e2);
	popc_axis_destroy(&ax);
	return st ? st : cst;
}

static int write_popc(const char *path, const popc_scene *s, const popc_log_row *rows, long n,
		      popc_error *err)
{
	popc_log_writer w;
	int st = popc_log_open(&w, path, POPC_LOG_COL_X_TRUE, err);
	if (!st)
		st = popc_log_write_header(&w, "sim", s, NULL, err);
	for (long i = 0; !st && i < n; i++)
		st = popc_log_write_row(&w, &rows[i], err);
	popc_error e2;
	int cst = popc_log_close(&w, &e2);
	return st ? st : cst;
}

static int write_printf(const char *path, const popc_log_row *rows, long n)
{
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	fprintf(f, "%s\n", popc_log_column_names(POPC_LOG_COL_X_TRUE));
	for (long i = 0; i < n; i++) {
		const popc_tick *t = &rows[i].tick;
		fprintf(f, "%.17g,%.17g,%lld,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%u\n", t->t_s,
			t->x_m, t->count, rows[i].x_true_m, t->v_mps, t->f_e_N, t->f_pc_N, t->f_c_N,
			t->W_J, t->E_ref_J, t->flags);
	}
	return fclose(f);
}

static long file_bytes(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return -1;
	fseek(f, 0, SEEK_END);
	long n = ftell(f);
	fclose(f);
	return n;
}

/* The recompute loop of popc-analyze's energy verb: W and E_ref from a log's
 * x, count, v, f_e and f_c columns, with the observer that ran online. */
typedef struct recompute {
	popc_observer obs;
	double period_s;
	int ix, icount, iv, ife, ifc;
	long long rows;
} recompute;

static void recompute_row(recompute *rc, const double *v)
{
	popc_observation ob;
	popc_observer_update(&rc->obs, v[rc->ix], (long long)v[rc->icount], v[rc->iv], rc->period_s,
			     v[rc->ife], &ob);
	popc_observer_commit(&rc->obs, &ob, v[rc->ife], v[rc->ifc]);
	rc->rows++;
}

static int read_popc(const char *path, const popc_scene *s, recompute *rc, popc_error *err)
{
	popc_log_reader r;
	int st = popc_log_reader_open(&r, path, NULL, err);
	if (st)
		return st;
	popc_observer_init(&rc->obs, s->variant, s->ignore_mode);
	rc->period_s = popc_scene_period_s(s);
	rc->rows = 0;
	if (!st)
		st = popc_log_reader_require(&r, "x", &rc->ix, err);
	if (!st)
		st = popc_log_reader_require(&r, "count", &rc->icount, err);
	if (!st)
		st = popc_log_reader_require(&r, "v", &rc->iv, err);
	if (!st)
		st = popc_log_reader_require(&r, "f_e", &rc->ife, err);
	if (!st)
		st = popc_log_reader_require(&r, "f_c", &rc->ifc, err);
	double v[POPC_LOG_MAX_COLUMNS];
	while (!st && (st = popc_log_reader_next(&r, v, err)) == 1) {
		recompute_row(rc, v);
		st = 0;
	}
	popc_log_reader_close(&r);
	return st < 0 ? st : 0;
}

/* The baseline reader: fgets and strtod per cell, same recompute. */
static int read_strtod(const char *path, const popc_scene *s, recompute *rc)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	popc_observer_init(&rc->obs, s->variant, s->ignore_mode);
	rc->period_s = popc_scene_period_s(s);
	rc->rows = 0;
	/* popc's column order with x_true: t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags */
	rc->ix = 1, rc->icount = 2, rc->iv = 4, rc->ife = 5, rc->ifc = 7;
	char line[1024];
	int header = 1;
	while (fgets(line, sizeof line, f)) {
		if (line[0] == '#')
			continue;
		if (header) {
			header = 0;
			continue;
		}
		double v[16];
		char *p = line, *end;
		int n = 0;
		while (n < 16) {
			v[n++] = strtod(p, &end);
			if (*end != ',')
				break;
			p = end + 1;
		}
		recompute_row(rc, v);
	}
	fclose(f);
	return 0;
}

/* Peak resident memory (KiB) of a child process that reads the log. */
static long child_read_rss_kib(const char *path, const popc_scene *s)
{
	int fd[2];
	if (pipe(fd) != 0)
		return -1;
	fflush(NULL);
	pid_t pid = fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		close(fd[0]);
		recompute rc;
		popc_error err;
		long kib = -1;
		if (read_popc(path, s, &rc, &err) == 0) {
			struct rusage ru;
			getrusage(RUSAGE_SELF, &ru);
			kib = ru.ru_maxrss;
		}
		ssize_t w = write(fd[1], &kib, sizeof kib);
		_exit(w == (ssize_t)sizeof kib ? 0 : 1);
	}
	close(fd[1]);
	long kib = -1;
	if (read(fd[0], &kib, sizeof kib) != (ssize_t)sizeof kib)
		kib = -1;
	close(fd[0]);
	int status;
	waitpid(pid, &status, 0);
	return kib;
}

static int bench_log(const popc_scene *s, const bench_opts *o)
{
	popc_error err;
	const char *dir = o->dir ? o->dir : getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
	char p_popc[POPC_PATH_MAX], p_printf[POPC_PATH_MAX], p_big[POPC_PATH_MAX];
	snprintf(p_popc, sizeof p_popc, "%s/popc-bench-%ld-popc.csv", dir, (long)getpid());
	snprintf(p_printf, sizeof p_printf, "%s/popc-bench-%ld-printf.csv", dir, (long)getpid());
	snprintf(p_big, sizeof p_big, "%s/popc-bench-%ld-big.csv", dir, (long)getpid());
	long n = o->rows;
	popc_log_row *rows = make_rows(s, n, &err);
	if (!rows)
		return popc_cli_fail("bench", POPC_ERR_NOMEM, &err);
	double w_popc = INFINITY, w_printf = INFINITY, r_popc = INFINITY, r_strtod = INFINITY;
	int st = 0;
	recompute a, b;
	for (int r = 0; r < o->repeats && !st; r++) {
		double t0 = now_s();
		st = write_popc(p_popc, s, rows, n, &err);
		double t1 = now_s();
		if (!st && write_printf(p_printf, rows, n) != 0)
			st = popc_error_set(&err, POPC_ERR_IO, "%s: write failed", p_printf);
		double t2 = now_s();
		if (!st)
			st = read_popc(p_popc, s, &a, &err);
		double t3 = now_s();
		if (!st && read_strtod(p_popc, s, &b) != 0)
			st = popc_error_set(&err, POPC_ERR_IO, "%s: read failed", p_popc);
		double t4 = now_s();
		w_popc = fmin(w_popc, t1 - t0);
		w_printf = fmin(w_printf, t2 - t1);
		r_popc = fmin(r_popc, t3 - t2);
		r_strtod = fmin(r_strtod, t4 - t3);
	}
	long bytes_popc = file_bytes(p_popc), bytes_printf = file_bytes(p_printf);
	/* exactness: the recompute from the log equals the online W and E_ref bitwise */
	int exact = !st && a.rows == n && a.obs.W_J == rows[n - 1].tick.W_J &&
		    a.obs.E_ref_J == rows[n - 1].tick.E_ref_J;
	free(rows); /* before the children fork: their peak memory is the reader's */
	rows = NULL;
	/* memory: the same reader on a log four times longer */
	long rss_small = -1, rss_big = -1;
	if (!st)
		st = run_to_log(s, 4LL * n, p_big, &err);
	if (!st) {
		rss_small = child_read_rss_kib(p_popc, s);
		rss_big = child_read_rss_kib(p_big, s);
	}
	long bytes_big = file_bytes(p_big);
	remove(p_popc);
	remove(p_printf);
	remove(p_big);
	if (st)
		return popc_cli_fail("bench", st, &err);
	double mb = 1e-6 * (double)bytes_popc;
	if (o->csv) {
		puts("what,popc_MBps,libc_MBps,ratio");
		printf("write,%.6g,%.6g,%.4g\n", mb / w_popc, 1e-6 * (double)bytes_printf / w_printf,
		       w_printf / w_popc);
		printf("read_recompute,%.6g,%.6g,%.4g\n", mb / r_popc, mb / r_strtod,
		       r_strtod / r_popc);
		printf("reader_peak_rss_kib,%ld,%ld,\n", rss_small, rss_big);
		printf("recompute_bitwise,%d,,\n", exact);
		return exact ? 0 : 1;
	}
	printf("popc bench log: %ld rows of the scene's run (%.1f MB as popc writes them), one "
	       "core, fastest of %d, files in %s\n",
	       n, mb, o->repeats, dir);
	printf("%-44s %10s %10s %7s\n", "", "popc", "C library", "ratio");
	printf("%-44s %10.1f %10.1f %7.2f   (targets: >= 300 MB/s, >= 3 x)\n",
	       "write MB/s (vs printf %.17g)", mb / w_popc, 1e-6 * (double)bytes_printf / w_printf,
	       w_printf / w_popc);
	printf("%-44s %10.1f %10.1f %7.2f   (targets: >= 500 MB/s, >= 2 x)\n",
	       "read + W/E_ref recompute MB/s (vs strtod)", mb / r_popc, mb / r_strtod,
	       r_strtod / r_popc);
	printf("write: %.1f ns per row popc, %.1f ns per row printf\n", 1e9 * w_popc / (double)n,
	       1e9 * w_printf / (double)n);
	printf("reader peak memory: %ld KiB for %.1f MB, %ld KiB for %.1f MB (whole process)\n",
	       rss_small, mb, rss_big, 1e-6 * (double)bytes_big);
	printf("recomputed W and E_ref equal the online values bitwise: %s\n", exact ? "yes" : "NO");
	return exact ? 0 : 1;
}

/* ---- entry ---- */

enum { OPT_SCENE = 256, OPT_SET, OPT_FORMAT, OPT_PLOT, OPT_MIN_TIME, OPT_REPEAT, OPT_ROWS, OPT_DIR };

int popc_cmd_bench(int argc, char **argv)
{
	static const struct option opts[] = {
		{"scene", required_argument, NULL, OPT_SCENE},
		{"set", required_argument, NULL, OPT_SET},
		{"format", required_argument, NULL, OPT_FORMAT},
		{"plot", required_argument, NULL, OPT_PLOT},
		{"min-time", required_argument, NULL, OPT_MIN_TIME},
		{"repeat", required_argument, NULL, OPT_REPEAT},
		{"rows", required_argument, NULL, OPT_ROWS},
		{"dir", required_argument, NULL, OPT_DIR},
		{"help", no_argument, NULL, 'h'},
		{NULL, 0, NULL, 0},
	};
	bench_opts o = {.min_time_s = 0.2, .repeats = 3, .rows = 200000};
	int c;
	long lv;
	char *end;
	optind = 1;
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case OPT_SCENE: o.scene_path = optarg; break;
		case OPT_SET:
			if (popc_cli_push(&o.sets, &o.n_sets, optarg) != 0) {
				fprintf(stderr, "popc bench: out of memory\n");
				free(o.sets);
				return 1;
			}
			break;
		case OPT_FORMAT:
			if (strcmp(optarg, "csv") == 0)
				o.csv = 1;
			else if (strcmp(optarg, "text") != 0) {
				fprintf(stderr, "popc bench: --format %s: expected text or csv\n", optarg);
				free(o.sets);
				return 2;
			}
			break;
		case OPT_PLOT: o.plot_dir = optarg; break;
		case OPT_MIN_TIME:
			errno = 0;
			o.min_time_s = strtod(optarg, &end);
			if (end == optarg || *end || errno || !(o.min_time_s >= 0 && o.min_time_s <= 60)) {
				fprintf(stderr, "popc bench: --min-time %s: expected seconds in [0, 60]\n",
					optarg);
				free(o.sets);
				return 2;
			}
			break;
		case OPT_REPEAT:
			if (popc_cli_parse_long(optarg, 1, 100, &lv) != 0) {
				fprintf(stderr, "popc bench: --repeat %s: expected an integer in [1, 100]\n",
					optarg);
				free(o.sets);
				return 2;
			}
			o.repeats = (int)lv;
			break;
		case OPT_ROWS:
			if (popc_cli_parse_long(optarg, 1000, 100000000L, &lv) != 0) {
				fprintf(stderr, "popc bench: --rows %s: expected an integer in [1000, 1e8]\n",
					optarg);
				free(o.sets);
				return 2;
			}
			o.rows = lv;
			break;
		case OPT_DIR: o.dir = optarg; break;
		case 'h': usage(stdout); free(o.sets); return 0;
		default: usage(stderr); free(o.sets); return 2;
		}
	}
	if (optind + 1 != argc) {
		fprintf(stderr, "popc bench: %s\n",
			optind >= argc ? "missing what to measure (integrators, loop or log)"
				       : "one thing to measure at a time");
		usage(stderr);
		free(o.sets);
		return 2;
	}
	const char *what = argv[optind];
	if (strcmp(what, "integrators") != 0 && strcmp(what, "loop") != 0 && strcmp(what, "log") != 0) {
		fprintf(stderr, "popc bench: unknown benchmark '%s' (integrators, loop or log)\n", what);
		free(o.sets);
		return 2;
	}
	popc_scene s;
	popc_error err;
	int st = popc_cli_load_scene(&s, o.scene_path, o.sets, o.n_sets, &err);
	free(o.sets);
	if (st)
		return popc_cli_fail("bench", st, &err);
	if (strcmp(s.axis, "sim") != 0) {
		fprintf(stderr, "popc bench: the benchmarks run the simulated axis (axis = %s)\n", s.axis);
		return 2;
	}
	/* the figure's directory is made (or refused) before half a minute of
	 * measuring, as report -o and sweep -o make theirs */
	if (o.plot_dir && (st = popc_sweep_mkdir_p(o.plot_dir, &err)) != 0)
		return popc_cli_fail("bench", st, &err);
	if (strcmp(what, "integrators") == 0)
		return bench_integrators(&s, &o);
	if (strcmp(what, "loop") == 0)
		return bench_loop(&s, &o);
	return bench_log(&s, &o);
}
