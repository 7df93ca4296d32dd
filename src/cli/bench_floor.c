/* The control tick stripped to its arithmetic, for `popc bench loop`.
 *
 * Issue 5 asks the closed loop with the exact integrator to be 50 times faster
 * than the same loop with the paper's trapezoid at 100 substeps. Whatever the
 * implementation, a tick cannot cost less than the arithmetic that feeds the
 * next command from the last one: the encoder's floor(x / delta), the
 * displacement, the two compensated energy sums, the PC division, the clamp
 * and the plant step form one dependency chain per tick. This file runs that
 * chain and nothing else -- no metrics, no log row, no guards (NaN, count
 * overflow, divergence), no axis vtable -- so that `popc bench loop` can state
 * what the loop costs at least on this machine, and so the best ratio any
 * implementation could show.
 *
 * It is not a second controller: it applies to the scenes the paper's loop
 * covers (exact integrator; every variant but filtered-velocity, Table I's
 * ignore and hold with either Prev_fc reading; affine operator intents with
 * a breakpoint inside a period split as the sim axis splits it; no axis force
 * limit) and its
 * command sequence is checked bitwise against the real loop's before it is
 * timed (the operations are those of popc_controller_step and the sim axis'
 * exact hot path, in the same order). */
#include "bench_floor.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "popc/axes/sim_axis.h"
#include "popc/core/compensated.h"
#include "popc/core/encoder.h"
#include "popc/core/environment.h"
#include "popc/core/intent.h"
#include "popc/core/plant.h"
#include "popc/scene/from_scene.h"

typedef struct fused_scene {
	popc_plant plant;
	popc_intent intent;
	popc_environment env;
	popc_variant variant;
	popc_ignore_mode ignore_mode;
	double period_s, delta_m, pc_bound_N, tol_s, x0_m;
	double k_x0_N;         /* K x0: the plant steps y = x - x0, as the sim axis */
	long long n_ticks;
} fused_scene;

/* Where the sim axis starts the plant: its first sample's true position. */
static int initial_position(const popc_scene *s, double *x0_m, popc_error *err)
{
	popc_axis *ax;
	int st = popc_sim_axis_create(&ax, s, err);
	if (st)
		return st;
	popc_axis_sample smp;
	st = ax->ops->sample(ax, &smp, err);
	*x0_m = smp.x_true_m;
	popc_axis_destroy(&ax);
	return st;
}

/* Whether the chain covers the scene; *why names what it does not cover. */
static int applies(const popc_scene *s, const char **why)
{
	if (s->integrator != POPC_INTEGRATOR_EXACT)
		*why = "only the exact integrator";
	else if (s->variant == POPC_VARIANT_FILTERED_VELOCITY)
		*why = "every variant but filtered-velocity (its FOAW estimator is a loop of its own)";
	else if (s->variant > POPC_VARIANT_IMPROVED)
		*why = "only the variants of the paper (none to improved), not its successors";
	else if (s->delay_ticks != 0)
		*why = "only run.delay_ticks = 0";
	else if (s->dev_coulomb_N != 0.0 || s->dev_stiction_N != 0.0)
		*why = "only a device without friction";
	else if (s->intent == POPC_INTENT_SINE)
		*why = "only affine operator intents (ramp, force, table)";
	else
		return 1;
	return 0;
}

/* The f_c sequence of the stripped tick. ref != NULL: compares each command
 * with ref[k] bit for bit and returns the first tick that differs (or the
 * number of commands when all agree); ref == NULL: returns the number of
 * commands. -1: a split step failed (its matrices are not finite). */
/* A period with a breakpoint of the intent inside: exact sub-steps up to
 * each breakpoint, the same operations as the sim axis' advance() (once per
 * breakpoint, so no part of the timed chain's cost). */
static int split_period(fused_scene *f, popc_plant_state *st, double t, double t_end,
			double f_c)
{
	for (;;) {
		popc_plant_input u;
		double next;
		popc_intent_input(&f->intent, t, &u, &next); /* next > t (intent.h) */
		u.u0_N = (u.u0_N - f->k_x0_N) - f_c;
		if (next < t_end - f->tol_s && next > t) {
			if (popc_plant_step_h(&f->plant, st, &u, next - t) != 0)
				return -1;
			t = next;
			continue;
		}
		return popc_plant_step_h(&f->plant, st, &u, t_end - t);
	}
}

/* cloned like the sim axis' exchange: the same floor instruction in both */
POPC_FLOOR_CLONES
static long long run_chain(fused_scene *f, const double *ref, double *x_end)
{
	const double T = f->period_s, delta = f->delta_m, bound = f->pc_bound_N;
	const popc_plant_step_coeffs *c = &f->plant.full;
	const popc_variant var = f->variant;
	/* Table I's two halves: ignore the energy of one-count reversals, hold
	 * f_pc while no count moves */
	const int ignore = var == POPC_VARIANT_IGNORE || var == POPC_VARIANT_IMPROVED;
	const int hold = var == POPC_VARIANT_HOLD || var == POPC_VARIANT_IMPROVED;
	const int literal = f->ignore_mode == POPC_IGNORE_LITERAL;
	popc_intent_segment g = {0};
	popc_plant_state st = {0.0, 0.0}; /* y = x - x0 */
	double x_prev = 0.0, f_e_prev = 0.0, f_c_prev = 0.0, f_pc_prev = 0.0;
	double prev_fc = 0.0, prev_dx = 0.0;
	long long count_prev = 0, prev_dcount = 0;
	double W = 0.0, W_sum = 0.0, W_comp = 0.0, E = 0.0, E_sum = 0.0, E_comp = 0.0;
	long long k;
	for (k = 0; k + 1 < f->n_ticks; k++) {
		/* sample: the encoder's count and the measured position */
		long long count = (long long)floor((f->x0_m + st.x_m) / delta);
		double xm = popc_encoder_position(count, delta);
		double f_e, f_c, f_pc = 0.0;
		if (k == 0) {
			/* tick 0: v = 0, W(0) = E_ref(0) = 0, no PC */
			f_e = popc_environment_force(&f->env, xm, 0.0);
			f_c = f_e;
		} else {
			double v = (xm - x_prev) / T;
			f_e = popc_environment_force(&f->env, xm, v);
			double dx = xm - x_prev;
			long long dcount = count - count_prev;
			E = popc_compensated_add(&E_sum, &E_comp, (f_e + f_e_prev) * dx / 2.0);
			if (ignore && dcount != 0 && dcount == -prev_dcount && (dcount == 1 || dcount == -1))
				W = popc_compensated_add(&W_sum, &W_comp, -(prev_fc * prev_dx));
			else
				W = popc_compensated_add(&W_sum, &W_comp, f_c_prev * dx);
			double thr = var == POPC_VARIANT_PO_PC ? 0.0 : E;
			if (hold && dcount == 0)
				f_pc = f_pc_prev;
			else if (var != POPC_VARIANT_NONE && W < thr && dx != 0.0)
				f_pc = (thr - W) / dx;
			if (f_pc > bound)
				f_pc = bound;
			else if (f_pc < -bound)
				f_pc = -bound;
			f_c = f_e + f_pc;
			if (ignore && dcount != 0) {
				prev_fc = literal ? f_e : f_c_prev;
				prev_dx = dx;
				prev_dcount = dcount;
			}
		}
		x_prev = xm;
		count_prev = count;
		f_e_prev = f_e;
		f_c_prev = f_c;
		f_pc_prev = f_pc;
		if (ref && memcmp(&ref[k], &f_c, sizeof f_c) != 0)
			break;
		/* the plant over the period, f_c held, from the intent's segment */
		double t = (double)k * T, t_end = (double)(k + 1) * T;
		popc_plant_input u;
		if (popc_intent_period_input(&f->intent, &g, t, t_end, f->tol_s, &u)) {
			u.u0_N = (u.u0_N - f->k_x0_N) - f_c;
			popc_plant_step_exact(c, &st, &u);
		} else if (split_period(f, &st, t, t_end, f_c) != 0) {
			return -1;
		}
	}
	*x_end = f->x0_m + st.x_m;
	return k;
}

int popc_bench_tick_floor(const popc_scene *s, const double *f_c_ref, long long n_ref,
			  double min_time_s, int repeats, popc_tick_floor *out, popc_error *err)
{
	memset(out, 0, sizeof *out);
	out->ns_per_tick = (double)NAN;
	if (!applies(s, &out->not_covered))
		return 0;
	fused_scene f;
	memset(&f, 0, sizeof f);
	popc_plant_config cfg;
	popc_plant_config_from_scene(&cfg, s);
	int st = popc_plant_init(&f.plant, &cfg, err);
	if (st) {
		popc_plant_name_keys(s, err); /* the plant's parameters as the scene's keys */
		return st;
	}
	if ((st = popc_intent_from_scene(&f.intent, s, err)) != 0)
		return st;
	popc_environment_from_scene(&f.env, s);
	f.variant = s->variant;
	f.ignore_mode = s->ignore_mode;
	f.period_s = popc_scene_period_s(s);
	f.delta_m = s->enc_resolution_m;
	f.pc_bound_N = s->pc_bound_N;
	f.tol_s = POPC_INTENT_TICK_TOL_PERIODS * f.period_s;
	f.n_ticks = popc_scene_ticks(s) + 1;
	if ((st = initial_position(s, &f.x0_m, err)) != 0)
		goto done;
	f.k_x0_N = cfg.stiffness_Npm * f.x0_m;
	double x_end;
	/* same commands as the real loop, bit for bit, or no figure */
	long long agree = run_chain(&f, f_c_ref, &x_end);
	if (agree < 0) {
		out->not_covered = "a step split at a breakpoint has no finite matrices";
		goto done;
	}
	out->ticks_checked = agree;
	out->bitwise_equal = agree == n_ref && n_ref == f.n_ticks - 1;
	if (!out->bitwise_equal) {
		out->first_difference = agree;
		goto done;
	}
	double best = (double)INFINITY;
	for (int r = 0; r < repeats; r++) {
		double wall = 0.0, sink = 0.0;
		long long ticks = 0;
		do {
			double t0 = popc_thread_cpu_s();
			ticks += run_chain(&f, NULL, &x_end) + 1;
			wall += popc_thread_cpu_s() - t0;
			sink += x_end;
		} while (wall < min_time_s);
		if (isfinite(sink) && 1e9 * wall / (double)ticks < best)
			best = 1e9 * wall / (double)ticks;
	}
	out->ns_per_tick = best;
done:
	popc_intent_free(&f.intent);
	return st;
}
