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

/* The chain's body, specialized by its callers below: the variant's
 * branches (Table I's halves, the threshold, the PC at all) and the check
 * against the real loop's commands are constants there, so the timed loop
 * carries no test of them and no variable they would keep alive. A generic
 * body kept a dozen of its doubles on the stack (register pressure), each a
 * store and a reload on the tick's dependency chain: 23-31 ns where the
 * arithmetic alone takes about 14 (issue 23). The plant state and the sums
 * are locals whose address is never taken (a split period steps a copy),
 * so they stay in registers. */
static inline __attribute__((always_inline)) long long
chain_body(fused_scene *f, const double *ref, double *x_end, const int pc, const int thr_zero,
	   const int ignore, const int hold)
{
	const double T = f->period_s, delta = f->delta_m, bound = f->pc_bound_N, x0 = f->x0_m;
	const double k_x0 = f->k_x0_N, tol = f->tol_s;
	const popc_plant_step_coeffs *c = &f->plant.full;
	const int literal = f->ignore_mode == POPC_IGNORE_LITERAL;
	const long long n = f->n_ticks;
	popc_intent_segment g = {0};
	double y = 0.0, yv = 0.0; /* the plant's state, y = x - x0 */
	double x_prev = 0.0, f_e_prev = 0.0, f_c_prev = 0.0, f_pc_prev = 0.0;
	double prev_fc = 0.0, prev_dx = 0.0;
	long long count_prev = 0, prev_dcount = 0;
	double W_sum = 0.0, W_comp = 0.0, E_sum = 0.0, E_comp = 0.0;
	long long k;
	for (k = 0; k + 1 < n; k++) {
		/* sample: the encoder's count and the measured position */
		long long count = (long long)floor((x0 + y) / delta);
		double xm = popc_encoder_position(count, delta);
		double f_e, f_c, f_pc = 0.0;
		if (__builtin_expect(k == 0, 0)) {
			/* tick 0: v = 0, W(0) = E_ref(0) = 0, no PC */
			f_e = popc_environment_force(&f->env, xm, 0.0);
			f_c = f_e;
		} else {
			double v = (xm - x_prev) / T;
			f_e = popc_environment_force(&f->env, xm, v);
			double dx = xm - x_prev;
			long long dcount = count - count_prev;
			double E = popc_compensated_add(&E_sum, &E_comp, (f_e + f_e_prev) * dx / 2.0);
			double W;
			if (ignore && dcount != 0 && dcount == -prev_dcount && (dcount == 1 || dcount == -1))
				W = popc_compensated_add(&W_sum, &W_comp, -(prev_fc * prev_dx));
			else
				W = popc_compensated_add(&W_sum, &W_comp, f_c_prev * dx);
			double thr = thr_zero ? 0.0 : E;
			if (hold && dcount == 0)
				f_pc = f_pc_prev;
			else if (pc && W < thr && dx != 0.0)
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
		if (popc_intent_period_input(&f->intent, &g, t, t_end, tol, &u)) {
			u.u0_N = (u.u0_N - k_x0) - f_c;
			popc_plant_state st = {y, yv};
			popc_plant_step_exact(c, &st, &u);
			y = st.x_m;
			yv = st.v_mps;
		} else {
			popc_plant_state st = {y, yv};
			if (split_period(f, &st, t, t_end, f_c) != 0)
				return -1;
			y = st.x_m;
			yv = st.v_mps;
		}
	}
	*x_end = x0 + y;
	return k;
}

/* The f_c sequence of the stripped tick, checked: compares each command
 * with ref[k] bit for bit and returns the first tick that differs (or the
 * number of commands when all agree). -1: a split step failed (its matrices
 * are not finite). */
static long long check_chain(fused_scene *f, const double *ref, double *x_end)
{
	const popc_variant v = f->variant;
	return chain_body(f, ref, x_end, v != POPC_VARIANT_NONE, v == POPC_VARIANT_PO_PC,
			  v == POPC_VARIANT_IGNORE || v == POPC_VARIANT_IMPROVED,
			  v == POPC_VARIANT_HOLD || v == POPC_VARIANT_IMPROVED);
}

/* The timed chain, one specialization per variant (no check); cloned like
 * the sim axis' exchange: the same floor instruction in both. Returns the
 * number of commands, or -1 as check_chain. */
#define TIMED_CHAIN(name, pc, thr_zero, ignore, hold)                                              	POPC_FLOOR_CLONES static long long name(fused_scene *f, double *x_end)                      	{                                                                                           		return chain_body(f, NULL, x_end, pc, thr_zero, ignore, hold);                      	}
TIMED_CHAIN(chain_none, 0, 0, 0, 0)
TIMED_CHAIN(chain_po_pc, 1, 1, 0, 0)
TIMED_CHAIN(chain_ref_energy, 1, 0, 0, 0)
TIMED_CHAIN(chain_ignore, 1, 0, 1, 0)
TIMED_CHAIN(chain_hold, 1, 0, 0, 1)
TIMED_CHAIN(chain_improved, 1, 0, 1, 1)
#undef TIMED_CHAIN

static long long run_chain(fused_scene *f, double *x_end)
{
	switch (f->variant) {
	case POPC_VARIANT_NONE: return chain_none(f, x_end);
	case POPC_VARIANT_PO_PC: return chain_po_pc(f, x_end);
	case POPC_VARIANT_IGNORE: return chain_ignore(f, x_end);
	case POPC_VARIANT_HOLD: return chain_hold(f, x_end);
	case POPC_VARIANT_IMPROVED: return chain_improved(f, x_end);
	default: return chain_ref_energy(f, x_end); /* ref-energy (applies() admits no other) */
	}
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
	long long agree = check_chain(&f, f_c_ref, &x_end);
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
	/* the timed chain is the checked one specialized: it ends where the
	 * checked one ended, bit for bit, or no figure */
	double x_timed;
	if (run_chain(&f, &x_timed) != agree || memcmp(&x_timed, &x_end, sizeof x_end) != 0) {
		out->bitwise_equal = 0;
		out->first_difference = agree;
		goto done;
	}
	double best = (double)INFINITY;
	for (int r = 0; r < repeats; r++) {
		double wall = 0.0, sink = 0.0;
		long long ticks = 0;
		do {
			double t0 = popc_thread_cpu_s();
			ticks += run_chain(&f, &x_end) + 1;
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
