/* PO/PC variants (controller.h; seed eq. 3 and Table I; README, "Controller variants"). */
#include "popc/core/controller.h"
#include "popc/core/compensated.h"
#include "popc/core/port.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

const char *const popc_variant_names[] = {"none",
					  "po-pc",
					  "ref-energy",
					  "filtered-velocity",
					  "ignore",
					  "hold",
					  "improved",
					  "pc-off-reversals",
					  "energy-bounding",
					  "windowed-po",
					  NULL};
const char *const popc_ignore_mode_names[] = {"literal", "undo", NULL};

const char *popc_variant_name(popc_variant v)
{
	return (unsigned)v < POPC_VARIANT_COUNT ? popc_variant_names[v] : "?";
}

int popc_variant_from_name(const char *name, popc_variant *out)
{
	for (int i = 0; popc_variant_names[i]; i++)
		if (strcmp(popc_variant_names[i], name) == 0) {
			*out = (popc_variant)i;
			return 0;
		}
	return POPC_ERR_INVALID;
}

void popc_observer_init(popc_observer *o, popc_variant variant, popc_ignore_mode mode)
{
	memset(o, 0, sizeof *o);
	o->variant = variant;
	o->ignore_mode = mode;
}

static int uses_ignore(popc_variant v)
{
	return v == POPC_VARIANT_IGNORE || v == POPC_VARIANT_IMPROVED;
}

/* The observer step; static so that popc_controller_step gets it inlined
 * (the library is built position-independent, where a call to an exported
 * function is never inlined), public through popc_observer_update below. */
static inline void observer_update(popc_observer *o, double x_m, long long count, double v_mps,
				   double period_s, double f_e_N, popc_observation *obs)
{
	obs->flags = 0;
	if (!o->started) {
		/* tick 0: no displacement yet, W(0) = E_ref(0) = 0 */
		o->started = 1;
		o->x_prev_m = x_m;
		o->count_prev = count;
		o->f_e_prev_N = f_e_N;
		o->f_c_prev_N = 0.0;
		obs->dx_m = 0.0;
		obs->dcount = 0;
		return;
	}
	double dx = x_m - o->x_prev_m;
	long long dcount = count - o->count_prev;
	obs->dcount = dcount;
	/* reference energy of the ideal spring: trapezoid of f_e over dx */
	o->E_ref_J = popc_compensated_add(&o->E_ref_sum_J, &o->E_ref_comp_J,
				     (f_e_N + o->f_e_prev_N) * dx / 2.0);
	if (o->variant == POPC_VARIANT_FILTERED_VELOCITY) {
		/* seed eq. 2 with the estimated velocity: dW = f_c(k-1) v(k) T */
		double dxv = v_mps * period_s;
		obs->dx_m = dxv;
		o->W_J = popc_port_observe(&o->W_sum_J, &o->W_comp_J, o->f_c_prev_N, dxv);
	} else if (uses_ignore(o->variant) && dcount != 0 && dcount == -o->prev_dcount &&
		   (dcount == 1 || dcount == -1)) {
		/* Table I: one-count reversal: W(k) = W(k-1) - Prev_fc Prev_dx */
		obs->dx_m = dx;
		o->W_J = popc_compensated_add(&o->W_sum_J, &o->W_comp_J, -(o->prev_fc_N * o->prev_dx_m));
		obs->flags |= POPC_FLAG_IGNORE;
	} else {
		/* seed eq. 3: W(k) = W(k-1) + f_c(k-1) dx(k), the port's effort
		 * (held force) times its flow increment (port.h) */
		obs->dx_m = dx;
		o->W_J = popc_port_observe(&o->W_sum_J, &o->W_comp_J, o->f_c_prev_N, dx);
	}
	o->x_prev_m = x_m;
	o->count_prev = count;
	o->f_e_prev_N = f_e_N;
}

void popc_observer_update(popc_observer *o, double x_m, long long count, double v_mps,
			  double period_s, double f_e_N, popc_observation *obs)
{
	observer_update(o, x_m, count, v_mps, period_s, f_e_N, obs);
}

static inline void observer_commit(popc_observer *o, const popc_observation *obs, double f_e_N,
				   double f_c_N)
{
	if (uses_ignore(o->variant) && obs->dcount != 0) {
		/* Table I: Prev_dx = dx(k); Prev_fc = f_c(k) before the PC is added
		 * (literal: f_e(k)), or f_c(k-1) (undo the previous increment). */
		o->prev_fc_N = o->ignore_mode == POPC_IGNORE_LITERAL ? f_e_N : o->f_c_prev_N;
		o->prev_dx_m = obs->dx_m;
		o->prev_dcount = obs->dcount;
	}
	o->f_c_prev_N = f_c_N;
}

void popc_observer_commit(popc_observer *o, const popc_observation *obs, double f_e_N,
			  double f_c_N)
{
	observer_commit(o, obs, f_e_N, f_c_N);
}

int popc_observer_same_rule(const popc_observer *a, const popc_observer *b)
{
	const int fa = a->variant == POPC_VARIANT_FILTERED_VELOCITY;
	const int fb = b->variant == POPC_VARIANT_FILTERED_VELOCITY;
	if (fa != fb || uses_ignore(a->variant) != uses_ignore(b->variant))
		return 0;
	return !uses_ignore(a->variant) || a->ignore_mode == b->ignore_mode;
}

/* The rings' lengths: a variant that does not use a ring gets none. */
static size_t reversal_ring_len(const popc_controller_config *cfg)
{
	return cfg->variant == POPC_VARIANT_PC_OFF_REVERSALS ? (size_t)cfg->reversal_count : 0;
}

static size_t po_ring_len(const popc_controller_config *cfg)
{
	return cfg->variant == POPC_VARIANT_WINDOWED_PO ? (size_t)cfg->po_window_ticks : 0;
}

int popc_controller_create(const popc_controller_config *cfg, popc_controller **out,
			   popc_error *err)
{
	*out = NULL;
	popc_controller_config c_cfg = *cfg;
	/* a ring has at least one slot whatever the caller filled in (the
	 * scene's ranges start at 1) */
	if (c_cfg.reversal_count < 1)
		c_cfg.reversal_count = 1;
	if (c_cfg.po_window_ticks < 1)
		c_cfg.po_window_ticks = 1;
	const size_t n_rev = reversal_ring_len(&c_cfg), n_po = po_ring_len(&c_cfg);
	/* the struct, then the reversal ring, then the PO ring: long long and
	 * double after a struct that holds both keep their alignment; the
	 * lengths are ints, so the sum cannot wrap a 64-bit size_t, and a
	 * 32-bit one is checked */
	const size_t rev_bytes = n_rev * sizeof(long long);
	if (n_po > (SIZE_MAX - sizeof(popc_controller) - rev_bytes) / sizeof(double))
		return popc_error_set(err, POPC_ERR_NOMEM,
				      "controller: a window of %d ticks does not fit in memory",
				      c_cfg.po_window_ticks);
	const size_t bytes = sizeof(popc_controller) + rev_bytes + n_po * sizeof(double);
	popc_controller *c = malloc(bytes);
	if (!c)
		return popc_error_set(err, POPC_ERR_NOMEM,
				      "controller: out of memory (%zu bytes for po_window_ticks = %d, "
				      "reversal_count = %d)",
				      bytes, c_cfg.po_window_ticks, c_cfg.reversal_count);
	memset(c, 0, bytes);
	c->cfg = c_cfg;
	c->reversal_tick = n_rev ? (long long *)(void *)(c + 1) : NULL;
	c->po_inc_J = n_po ? (double *)(void *)((char *)(c + 1) + rev_bytes) : NULL;
	popc_observer_init(&c->obs, cfg->variant, cfg->ignore_mode);
	popc_foaw_init(&c->foaw, cfg->foaw_window, cfg->foaw_noise_m, cfg->resolution_m,
		       cfg->period_s);
	*out = c;
	return 0;
}

void popc_controller_free(popc_controller *c)
{
	free(c);
}

/* f_pc = (E_ref - W) / dx when the PO is below its threshold; never divides by
 * a zero displacement: the series PC, the port's correction (port.h) in
 * impedance causality. */
static double pc_force(double W, double threshold, double dx)
{
	return popc_port_pc(W, threshold, dx);
}

/* pc-off-reversals (seed Sec. VI: "turn off the PC when the velocity sign
 * change is repeated"): a reversal is a tick whose count moved against the
 * last count that moved. Returns whether at least reversal_count reversals
 * fall in the ticks (k - reversal_window, k], k = c->tick. */
static int reversals_repeated(popc_controller *c, long long dcount)
{
	const int n = c->cfg.reversal_count;
	if (dcount != 0) {
		int dir = dcount > 0 ? 1 : -1;
		if (c->last_dir != 0 && dir != c->last_dir) {
			c->reversal_tick[c->reversal_next] = c->tick;
			c->reversal_next = (c->reversal_next + 1) % n;
			if (c->n_reversals < n)
				c->n_reversals++;
		}
		c->last_dir = dir;
	}
	if (c->n_reversals < n)
		return 0;
	/* the oldest of the last n reversals is the next slot of the ring */
	return c->reversal_tick[c->reversal_next] > c->tick - c->cfg.reversal_window_ticks;
}

/* energy-bounding (after Kim and Ryu 2004): a force step df held by the
 * zero-order hold over a displacement dx generates at most |df| |dx| / 2
 * more energy than the continuous element (rectangle against trapezoid),
 * while the physical damping b dissipates at least b dx^2 / T over the period
 * (Cauchy-Schwarz: the integral of v^2 is >= dx^2 / T). A force that moves
 * with the displacement at a stiffness of at most K_b = 2 b / T keeps the
 * first below the second; so f_c follows the displacement at K_b,
 *   f_c(k) = f_c(k-1) + K_b dx(k),
 * and never beyond the environment: saturated to [0, f_e(k)] (or
 * [f_e(k), 0] when f_e < 0). The saturation only lowers |f_c|: where the
 * environment is softer than K_b, f_c = f_e; where it is stiffer, the device
 * feels K_b, the stiffness actually rendered (rendered_stiffness in the run
 * summary). Returns f_c(k) - f_e(k) (the PC force). */
static double energy_bounded_pc(const popc_controller *c, double f_e, double dx, unsigned *flags)
{
	const double k_b = (1.0 - c->cfg.eb_margin) * 2.0 * c->cfg.damping_Nspm / c->cfg.period_s;
	double f = c->obs.f_c_prev_N + k_b * dx;
	const double lo = f_e < 0.0 ? f_e : 0.0, hi = f_e > 0.0 ? f_e : 0.0;
	if (f > hi)
		f = hi;
	else if (f < lo)
		f = lo;
	if (f != f_e)
		*flags |= POPC_FLAG_BOUND;
	return f - f_e;
}

/* windowed-po: D(k) = sum over the last po_window ticks of the increments of
 * W - E_ref (seed eq. 3 and the trapezoid reference); when D(k) < 0, the
 * measured speed |dx| / T is at least the floor and a count moved, the PC
 * dissipates -D(k) over the next step as a damper, f_pc = -D(k) / dx(k), its
 * damping |f_pc| / |v| at most po_damping_max. Energy older than the window
 * is forgotten, so a long passive history no longer hides a new active
 * phase, and an old deficit no longer drives the PC for ever. */
static double windowed_pc(popc_controller *c, double inc_J, double dx, unsigned *flags)
{
	const int n = c->cfg.po_window_ticks;
	double old = 0.0;
	if (c->po_n == n)
		old = c->po_inc_J[c->po_next];
	else
		c->po_n++;
	c->po_inc_J[c->po_next] = inc_J;
	c->po_next = (c->po_next + 1) % n;
	popc_compensated_add(&c->po_sum_J, &c->po_comp_J, inc_J);
	const double D = popc_compensated_add(&c->po_sum_J, &c->po_comp_J, -old);
	const double speed = fabs(dx) / c->cfg.period_s;
	if (!(D < 0.0) || dx == 0.0 || speed < c->cfg.po_velocity_floor_mps)
		return 0.0;
	double f_pc = -D / dx;
	const double f_max = c->cfg.po_damping_max_Nspm * speed;
	if (fabs(f_pc) > f_max) {
		f_pc = f_pc > 0.0 ? f_max : -f_max;
		*flags |= POPC_FLAG_BOUND;
	}
	return f_pc;
}

void popc_controller_step(popc_controller *c, long long count, double x_m, popc_tick *out)
{
	const popc_controller_config *cfg = &c->cfg;
	double v;
	if (cfg->variant == POPC_VARIANT_FILTERED_VELOCITY)
		v = popc_foaw_update(&c->foaw, count, x_m);
	else
		v = c->started ? (x_m - c->obs.x_prev_m) / cfg->period_s : 0.0;
	c->started = 1;

	double f_e = popc_environment_force(&cfg->env, x_m, v);
	/* windowed-po's increment of W - E_ref, from the observer's state before
	 * its update: f_c(k-1) dx(k) - (f_e(k) + f_e(k-1)) dx(k) / 2 */
	double po_inc_J = 0.0;
	if (cfg->variant == POPC_VARIANT_WINDOWED_PO && c->obs.started) {
		double dx = x_m - c->obs.x_prev_m;
		po_inc_J = c->obs.f_c_prev_N * dx - (f_e + c->obs.f_e_prev_N) * dx / 2.0;
	}
	popc_observation ob;
	observer_update(&c->obs, x_m, count, v, cfg->period_s, f_e, &ob);
	const double W = c->obs.W_J, E_ref = c->obs.E_ref_J;
	unsigned flags = ob.flags;

	double f_pc = 0.0;
	switch (cfg->variant) {
	case POPC_VARIANT_NONE:
		break;
	case POPC_VARIANT_PO_PC:
		f_pc = pc_force(W, 0.0, ob.dx_m);
		break;
	case POPC_VARIANT_REF_ENERGY:
	case POPC_VARIANT_FILTERED_VELOCITY:
	case POPC_VARIANT_IGNORE:
		f_pc = pc_force(W, E_ref, ob.dx_m);
		break;
	case POPC_VARIANT_HOLD:
	case POPC_VARIANT_IMPROVED:
		if (ob.dcount == 0) {
			/* Table I, |dx(k)| < delta: f_pc(k) = f_pc(k-1) */
			f_pc = c->f_pc_prev_N;
			if (f_pc != 0.0)
				flags |= POPC_FLAG_HOLD;
		} else {
			f_pc = pc_force(W, E_ref, ob.dx_m);
		}
		break;
	case POPC_VARIANT_PC_OFF_REVERSALS:
		f_pc = pc_force(W, E_ref, ob.dx_m);
		if (reversals_repeated(c, ob.dcount)) {
			if (f_pc != 0.0)
				flags |= POPC_FLAG_PC_OFF;
			f_pc = 0.0;
		}
		break;
	case POPC_VARIANT_ENERGY_BOUNDING:
		f_pc = energy_bounded_pc(c, f_e, ob.dx_m, &flags);
		break;
	case POPC_VARIANT_WINDOWED_PO:
		f_pc = windowed_pc(c, po_inc_J, ob.dx_m, &flags);
		break;
	default:
		break;
	}
	if (isnan(f_pc)) { /* +-inf is left to the bound below: its sign is meaningful */
		f_pc = 0.0;
		flags |= POPC_FLAG_GUARD;
	}
	/* energy-bounding's f_pc is what takes f_c back within the energy bound:
	 * clamping it would undo the bound, so pc_bound does not apply to it */
	if (cfg->variant == POPC_VARIANT_ENERGY_BOUNDING) {
		/* no clamp */
	} else if (f_pc > cfg->pc_bound_N) {
		f_pc = cfg->pc_bound_N;
		flags |= POPC_FLAG_CLAMP;
	} else if (f_pc < -cfg->pc_bound_N) {
		f_pc = -cfg->pc_bound_N;
		flags |= POPC_FLAG_CLAMP;
	}
	if (f_pc != 0.0)
		flags |= POPC_FLAG_ACTIVE;
	double f_c = f_e + f_pc;
	if (!isfinite(f_c)) { /* only if f_e itself overflowed: command nothing */
		f_c = 0.0;
		flags |= POPC_FLAG_GUARD;
	}
	/* The axis clamps what it sends; clamping here keeps the log and the PO
	 * (W(k+1) uses f_c(k)) on the force the device really received. */
	if (cfg->force_limit_N > 0.0 && fabs(f_c) > cfg->force_limit_N) {
		f_c = f_c > 0.0 ? cfg->force_limit_N : -cfg->force_limit_N;
		flags |= POPC_FLAG_LIMIT;
	}
	observer_commit(&c->obs, &ob, f_e, f_c);
	c->f_pc_prev_N = f_pc;
	c->tick++;

	out->x_m = x_m;
	out->count = count;
	out->v_mps = v;
	out->f_e_N = f_e;
	out->f_pc_N = f_pc;
	out->f_c_N = f_c;
	out->W_J = W;
	out->E_ref_J = E_ref;
	out->flags = flags;
}
