/* popc bench loop: the control loop without logging, exact against the
 * paper's scheme (trapezoid at 100 substeps), side by side, and the tick's
 * dependency chain alone (bench_floor.c) (bench.h). */
#include "bench.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_floor.h"
#include "cli.h"
#include "popc/core/plant.h"
#include "popc/run/run.h"
#include "popc/scene/from_scene.h"

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
		return (double)NAN;
	popc_plant_input u = {0.5, 0.0, 0.0, 0.0};
	double best = (double)INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		popc_plant_state st = {-0.01, 0.0};
		long long n = 0;
		double t0 = popc_thread_cpu_s(), dt;
		do {
			for (int i = 0; i < 10000; i++)
				popc_plant_step(&p, &st, &u);
			n += 10000;
			dt = popc_thread_cpu_s() - t0;
		} while (dt < o->min_time_s / 4);
		if (!isfinite(st.x_m)) /* keeps the loop and tells if the step diverged */
			return (double)NAN;
		if (1e9 * dt / (double)n < best)
			best = 1e9 * dt / (double)n;
	}
	return best;
}

/* One closed-loop run of s through the axis factory (either causality), no
 * log: this thread's CPU time and the ticks run. */
static int causality_run(const popc_scene *s, double *cpu_s, long long *ticks, popc_error *err)
{
	popc_axis *ax;
	int st = popc_axis_create(&ax, s, NULL, err);
	if (st)
		return st;
	if (ax->ops->set_shadow)
		ax->ops->set_shadow(ax, 0);
	popc_run_summary sum;
	double c0 = popc_thread_cpu_s();
	st = popc_run(s, ax, NULL, &sum, err);
	*cpu_s += popc_thread_cpu_s() - c0;
	*ticks += sum.ticks;
	popc_axis_destroy(&ax);
	return st && sum.ticks < 2 ? st : 0;
}

/* An admittance scene: its loop side by side with the same scene in
 * impedance causality (the same plant keys, controller.variant's PC on the
 * wall of [environment]), the two alternated within each repeat so that a
 * change of the machine's load reaches both; the fastest of each. */
static int bench_loop_admittance(const popc_scene *s0, const bench_opts *o)
{
	popc_error err;
	popc_scene adm = *s0, imp = *s0;
	if (adm.duration_s < 100)
		adm.duration_s = imp.duration_s = 100;
	imp.causality = POPC_CAUSALITY_IMPEDANCE;
	double best_adm = (double)INFINITY, best_imp = (double)INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		double ca = 0.0, ci = 0.0;
		long long ta = 0, ti = 0;
		int st = 0;
		do {
			st = causality_run(&adm, &ca, &ta, &err);
			if (!st)
				st = causality_run(&imp, &ci, &ti, &err);
		} while (!st && (ca < o->min_time_s || ci < o->min_time_s));
		if (st)
			return popc_cli_fail("bench", st, &err);
		best_adm = fmin(best_adm, 1e9 * ca / (double)ta);
		best_imp = fmin(best_imp, 1e9 * ci / (double)ti);
	}
	if (o->csv) {
		fprintf(o->out, "%s\n", "what,admittance,impedance,ratio");
		fprintf(o->out, "loop_ns_per_tick,%.6g,%.6g,%.4g\n", best_adm, best_imp, best_adm / best_imp);
		return 0;
	}
	printf("popc bench loop: %s, admittance against the same scene in impedance causality,\n"
	       "no log, one core, this thread's CPU time, alternated, fastest of %d\n",
	       s0->source[0] ? s0->source : "scene", o->repeats);
	printf("%-34s %14s %16s %8s\n", "", "admittance", "impedance", "ratio");
	printf("%-34s %14.2f %16.2f %8.2f\n", "control loop, ns per tick", best_adm, best_imp,
	       best_adm / best_imp);
	return 0;
}

/* Two scenes' loops alternated within each repeat (bench_loop_admittance's
 * way), the fastest ns per tick of each. */
static int pair_ns(const popc_scene *a, const popc_scene *b, const bench_opts *o, double *ns_a,
		   double *ns_b, popc_error *err)
{
	*ns_a = *ns_b = (double)INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		double ca = 0.0, cb = 0.0;
		long long ta = 0, tb = 0;
		int st = 0;
		do {
			st = causality_run(a, &ca, &ta, err);
			if (!st)
				st = causality_run(b, &cb, &tb, err);
		} while (!st && (ca < o->min_time_s || cb < o->min_time_s));
		if (st)
			return st;
		*ns_a = fmin(*ns_a, 1e9 * ca / (double)ta);
		*ns_b = fmin(*ns_b, 1e9 * cb / (double)tb);
	}
	return 0;
}

/* A teleoperation scene (docs/TELEOPERATION.md): its tick (both ports, both
 * channels, the PCs) against the one-port tick of the same scene with
 * teleop.architecture = off, and its tick with 350 ticks of delay each way
 * (700 ms at 1 kHz) against no delay: a delay must cost nothing per tick. */
static int bench_loop_teleop(const popc_scene *s0, const bench_opts *o)
{
	popc_error err;
	popc_scene tele = *s0, one = *s0, d0 = *s0, d700 = *s0;
	if (tele.duration_s < 100)
		tele.duration_s = one.duration_s = d0.duration_s = d700.duration_s = 100;
	one.tele_arch = POPC_TELEOP_OFF;
	d0.fwd.delay_ticks = d0.bwd.delay_ticks = 0;
	d700.fwd.delay_ticks = d700.bwd.delay_ticks = 350;
	double nt, no, n0, n7;
	int st = pair_ns(&tele, &one, o, &nt, &no, &err);
	if (!st)
		st = pair_ns(&d700, &d0, o, &n7, &n0, &err);
	if (st)
		return popc_cli_fail("bench", st, &err);
	if (o->csv) {
		fprintf(o->out, "%s\n", "what,teleop,other,ratio");
		fprintf(o->out, "loop_ns_per_tick_vs_one_port,%.6g,%.6g,%.4g\n", nt, no, nt / no);
		fprintf(o->out, "loop_ns_per_tick_700ms_vs_0ms,%.6g,%.6g,%.4g\n", n7, n0, n7 / n0);
		return 0;
	}
	printf("popc bench loop: %s, teleoperation, no log, one core, this thread's CPU time,\n"
	       "alternated in pairs, fastest of %d\n",
	       s0->source[0] ? s0->source : "scene", o->repeats);
	printf("%-44s %10s %10s %8s\n", "control loop, ns per tick", "teleop", "other", "ratio");
	printf("%-44s %10.2f %10.2f %8.2f\n", "against one port (teleop.architecture = off)", nt, no,
	       nt / no);
	printf("%-44s %10.2f %10.2f %8.2f\n", "700 ms round trip against 0 ms", n7, n0, n7 / n0);
	return 0;
}

/* popc run as a whole process beside the loop's figure (issue 23): the
 * process's CPU per tick, its start-up (a run of one period: loading, the
 * scene, the matrices) and the loop figure over the process's. */
typedef struct loop_process {
	int measured;             /* 0: no scene file to run (the built-in scene) */
	long long ticks;
	double ns_per_tick;       /* whole process, CPU time over its ticks */
	double startup_ms;        /* CPU of the same process over one period */
	double net_ns_per_tick;   /* without the start-up */
	double loop_over_process; /* the loop figure over ns_per_tick */
} loop_process;

/* The exact loop's ns per tick (this thread's CPU time, bench_loop_ns_per_tick)
 * and, with a scene file, `popc run SCENE -q` of the same duration as a
 * process: the two alternated within each repeat, so that a change of the
 * machine's load reaches both, the fastest of each. */
static int loop_beside_process(const popc_scene *s, const bench_opts *o, double *loop_ns,
			       loop_process *pr, popc_error *err)
{
	memset(pr, 0, sizeof *pr);
	if (!o->scene_path)
		return bench_loop_ns_per_tick(s, POPC_INTEGRATOR_EXACT, 1, o, loop_ns, err);
	bench_opts one = *o;
	one.repeats = 1;
	double best_loop = (double)INFINITY, best_proc = (double)INFINITY, best_start = (double)INFINITY;
	for (int r = 0; r < o->repeats; r++) {
		double ns, cpu, start;
		int st = bench_loop_ns_per_tick(s, POPC_INTEGRATOR_EXACT, 1, &one, &ns, err);
		if (!st)
			st = bench_process_cpu_s(o, s->duration_s, &cpu, err);
		if (!st)
			st = bench_process_cpu_s(o, popc_scene_period_s(s), &start, err);
		if (st)
			return st;
		best_loop = fmin(best_loop, ns);
		best_proc = fmin(best_proc, cpu);
		best_start = fmin(best_start, start);
	}
	*loop_ns = best_loop;
	pr->measured = 1;
	pr->ticks = popc_scene_ticks(s) + 1;
	pr->ns_per_tick = 1e9 * best_proc / (double)pr->ticks;
	pr->startup_ms = 1e3 * best_start;
	pr->net_ns_per_tick = 1e9 * (best_proc - best_start) / (double)pr->ticks;
	pr->loop_over_process = best_loop / pr->ns_per_tick;
	return 0;
}

/* Prints how the loop figure compares with the process (loop_process). */
static void print_process(const loop_process *pr, double loop_ns)
{
	if (!pr->measured) {
		printf("popc run as a process: not measured (the built-in scene; give --scene FILE)\n");
		return;
	}
	printf("popc run -q as a process: %.2f ns per tick over %lld ticks (CPU, start-up %.3g ms "
	       "included; %.2f ns without it);\n  the loop figure is %.2f x that: ",
	       pr->ns_per_tick, pr->ticks, pr->startup_ms, pr->net_ns_per_tick,
	       pr->loop_over_process);
	double start_share = pr->startup_ms * 1e6 / (pr->ns_per_tick * (double)pr->ticks);
	if (fabs(pr->loop_over_process - 1.0) <= 0.10)
		printf("they agree within 10 %%\n");
	else if (start_share > 0.05)
		printf("they differ by more than 10 %%: the start-up is %.0f %% of the process's CPU "
		       "(set a longer run.duration)\n",
		       100.0 * start_share);
	else
		printf("they differ by more than 10 %% (%.2f against %.2f ns): the loop is timed on its "
		       "thread alone, the fastest of repeated runs; a process whose start-up is small "
		       "differs from it only by the machine's load between the two (rerun on an idle "
		       "machine)\n",
		       loop_ns, pr->ns_per_tick);
}

int bench_loop(const popc_scene *s0, const bench_opts *o)
{
	if (s0->causality == POPC_CAUSALITY_ADMITTANCE)
		return bench_loop_admittance(s0, o);
	if (s0->tele_arch != POPC_TELEOP_OFF)
		return bench_loop_teleop(s0, o);
	popc_error err;
	popc_scene s = *s0;
	/* long enough that start-up is noise; the summary's ns per tick */
	if (s.duration_s < 100)
		s.duration_s = 100;
	double ex_ns, tr_ns;
	loop_process pr;
	int st = loop_beside_process(&s, o, &ex_ns, &pr, &err);
	if (!st)
		st = bench_loop_ns_per_tick(&s, POPC_INTEGRATOR_TRAPEZOID, 100, o, &tr_ns, &err);
	if (st)
		return popc_cli_fail("bench", st, &err);
	/* the commands of the real loop over the timed scene: the reference of the
	 * trapezoid's error (over the scene's own duration) and of the stripped tick */
	recorder rec;
	st = bench_reference_forces(s0, &rec, &err);
	double tr_err = (double)NAN;
	long long tick;
	if (!st)
		st = bench_replay_error(s0, POPC_INTEGRATOR_TRAPEZOID, 100, &rec, &tr_err, &tick, &err);
	free(rec.f_c);
	popc_tick_floor fl;
	if (!st) {
		st = bench_reference_forces(&s, &rec, &err);
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
		fprintf(o->out, "%s\n", "what,exact,trapezoid_100,ratio");
		fprintf(o->out, "loop_ns_per_tick,%.6g,%.6g,%.4g\n", ex_ns, tr_ns, tr_ns / ex_ns);
		fprintf(o->out, "plant_ns_per_period,%.6g,%.6g,%.4g\n", pex, ptr, ptr / pex);
		fprintf(o->out, "chain_floor_ns_per_tick,%.6g,%.6g,%.4g\n", fl_ns, fl_ns - pex + ptr, best_ratio);
		fprintf(o->out, "chain_commands_equal,%d,,\n", fl.bitwise_equal);
		/* the whole loop against the flat loop of the same tick */
		fprintf(o->out, "loop_over_chain,%.4g,,\n", fl.bitwise_equal ? ex_ns / fl_ns : (double)NAN);
		fprintf(o->out, "max_error_m,0,%.6g,\n", tr_err);
		fprintf(o->out, "exact_ticks_per_s,%.6g,,\n", ticks_per_s);
		if (pr.measured) {
			/* popc run SCENE -q as a process: its CPU per tick, its start-up,
			 * the loop figure over the process's */
			fprintf(o->out, "process_ns_per_tick,%.6g,,\n", pr.ns_per_tick);
			fprintf(o->out, "process_startup_ms,%.6g,,\n", pr.startup_ms);
			fprintf(o->out, "loop_over_process,%.4g,,\n", pr.loop_over_process);
		}
		return 0;
	}
	printf("popc bench loop: %s, no log, one core, this thread's CPU time, fastest of %d\n",
	       s0->source[0] ? s0->source : "built-in paper scene", o->repeats);
	printf("%-34s %14s %16s %8s\n", "", "exact", "trapezoid x100", "ratio");
	printf("%-34s %14.2f %16.2f %8.1f\n", "control loop, ns per tick", ex_ns, tr_ns,
	       tr_ns / ex_ns);
	printf("%-34s %14.2f %16.2f %8.1f\n", "plant step alone, ns per period", pex, ptr, ptr / pex);
	if (fl.bitwise_equal)
		printf("%-34s %14.2f %16.2f %8.1f\n", "tick's dependency chain alone, ns", fl_ns,
		       fl_ns - pex + ptr, best_ratio);
	printf("%-34s %14s %16.3g\n", "max position error vs exact (m)", "0 (ref)", tr_err);
	print_process(&pr, ex_ns);
	/* measured figures and their references (the paper's scheme, the plant
	 * alone, the stripped tick), not project targets */
	printf("exact loop: %.3g million ticks per second\n"
	       "control loop %.1f x faster than the paper's scheme (trapezoid, 100 substeps)\n"
	       "plant step alone %.1f x faster (the controller, not the plant, costs the rest of "
	       "the loop)\n",
	       ticks_per_s / 1e6, tr_ns / ex_ns, ptr / pex);
	if (fl.bitwise_equal)
		printf("dependency chain: the tick stripped to its arithmetic (no metrics, guards or "
		       "calls;\n  its %lld commands equal the loop's bit for bit) costs %.1f ns; with "
		       "this arithmetic\n  the ratio cannot pass %.1f x; the whole loop costs %.2f x the "
		       "chain\n",
		       fl.ticks_checked, fl_ns, best_ratio, ex_ns / fl_ns);
	else if (fl.not_covered)
		printf("dependency chain: not measured for this scene (%s)\n", fl.not_covered);
	else
		printf("dependency chain: not measured: its command at tick %lld differs from the "
		       "loop's\n",
		       fl.first_difference);
	return 0;
}
