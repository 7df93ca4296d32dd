/* popc bench: the recording axis and the timed closed-loop run that the
 * benchmarks share (bench.h). */
#include "bench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "popc/run/run.h"

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

static const popc_axis_ops bench_recorder_ops_ = {
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
int bench_reference_forces(const popc_scene *s0, recorder *rec, popc_error *err)
{
	popc_scene s = *s0;
	s.integrator = POPC_INTEGRATOR_EXACT;
	memset(rec, 0, sizeof *rec);
	int st = popc_sim_axis_create(&rec->inner, &s, err);
	if (st)
		return st;
	popc_axis ax = {.ops = &bench_recorder_ops_, .priv = rec};
	popc_run_summary sum;
	st = popc_run(&s, &ax, NULL, &sum, err);
	popc_axis_destroy(&rec->inner);
	return st;
}

/* Max |x - x_exact| at the samples when the integrator is fed the forces
 * open loop. Returns 0, or POPC_ERR_NUMERIC (POPC_ERR_DIVERGED) when the integrator was stopped
 * as unstable (*tick_out: where). */
int bench_replay_error(const popc_scene *s0, popc_integrator m, int substeps, const recorder *rec,
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
	*err_m = ax->ops->integrator_error_m(ax);
	*tick_out = k;
	popc_error e2;
	ax->ops->stop(ax, &e2);
	popc_axis_destroy(&ax);
	return st;
}

/* Closed-loop CPU time per control step (ns), no log, shadow off, the summary
 * unread as under popc run -q: the fastest of `repeats` measurements, each
 * repeating the run until min_time_s passed. */
int bench_loop_ns_per_tick(const popc_scene *s0, popc_integrator m, int substeps,
			    const bench_opts *o, double *ns, popc_error *err)
{
	popc_scene s = *s0;
	s.integrator = m;
	s.substeps = substeps;
	double best = (double)INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		double wall = 0.0;
		long long ticks = 0;
		do {
			popc_axis *ax;
			int st = popc_sim_axis_create(&ax, &s, err);
			if (st)
				return st;
			ax->ops->set_shadow(ax, 0);
			popc_run_summary sum;
			/* as popc run -q: nobody reads the summary (run.h) */
			popc_run_options ro = {.summary_unread = 1};
			double c0 = popc_thread_cpu_s();
			st = popc_run(&s, ax, &ro, &sum, err);
			wall += popc_thread_cpu_s() - c0;
			popc_axis_destroy(&ax);
			if (st && sum.ticks < 2)
				return st;
			ticks += sum.ticks;
		} while (wall < o->min_time_s);
		double v = 1e9 * wall / (double)ticks;
		if (v < best)
			best = v;
	}
	*ns = best;
	return 0;
}
