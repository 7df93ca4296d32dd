/* The admittance controller: force sensor, VE, observer and parallel PC
 * (admittance.h; docs/ADMITTANCE.md). */
#include "popc/core/admittance.h"

#include <math.h>
#include <string.h>

#include "popc/core/port.h"
#include "popc/core/random.h"

const char *const popc_admittance_variant_names[] = {"none", "parallel-pc", "parallel-ignore",
						     "parallel-hold", "parallel-improved", NULL};

const char *popc_admittance_variant_name(popc_admittance_variant v)
{
	return (unsigned)v < POPC_ADMITTANCE_VARIANT_COUNT ? popc_admittance_variant_names[v] : "?";
}

/* a standard normal deviate, Box-Muller's polar-free form: two per pair of
 * uniforms, the second kept for the next call */
static double normal(popc_force_sensor *s)
{
	if (s->has_spare) {
		s->has_spare = 0;
		return s->spare;
	}
	const double two_pi = 6.283185307179586476925286766559;
	double r = sqrt(-2.0 * log(popc_uniform_open0(&s->state)));
	double th = two_pi * popc_uniform_open0(&s->state);
	s->spare = r * sin(th);
	s->has_spare = 1;
	return r * cos(th);
}

void popc_force_sensor_init(popc_force_sensor *s, double resolution_N, double noise_N,
			    uint64_t seed)
{
	memset(s, 0, sizeof *s);
	s->resolution_N = resolution_N;
	s->noise_N = noise_N;
	s->state = seed;
}

long long popc_force_sensor_read(popc_force_sensor *s, double f_N)
{
	double f = f_N;
	if (s->noise_N > 0.0)
		f += s->noise_N * normal(s);
	/* the nearest count, ties to even (the default rounding mode); a count
	 * is exact in a double up to 2^53, and 2^52 keeps f = n r exact too */
	double q = nearbyint(f / s->resolution_N);
	const double lim = 4503599627370496.0; /* 2^52 */
	if (!(q < lim))
		q = q != q ? 0.0 : lim; /* NaN (never from a finite force): 0 */
	if (q < -lim)
		q = -lim;
	return (long long)q;
}

void popc_admittance_observer_init(popc_admittance_observer *o, popc_admittance_variant v)
{
	memset(o, 0, sizeof *o);
	o->variant = v;
}

static int uses_ignore(popc_admittance_variant v)
{
	return v == POPC_ADMITTANCE_IGNORE || v == POPC_ADMITTANCE_IMPROVED;
}

static inline void observer_update(popc_admittance_observer *o, long long n, double f_N,
				   double v_ve_mps, double period_s,
				   popc_admittance_observation *ob)
{
	ob->flags = 0;
	ob->dn = 0;
	/* the effort whose energy is counted: f(k), or, at a one-count reversal
	 * of the force count (dn(k) = -dn_prev = +-1, the dual of Table I's
	 * position reversal), f(k-1): the energy T (f(k) - f(k-1)) v_VE(k) =
	 * T dn r v_VE(k) that the one-count change alone produces is ignored
	 * (docs/ADMITTANCE.md, "The duals of Table I") */
	double effort = f_N;
	if (o->started) {
		ob->dn = n - o->n_prev;
		if (uses_ignore(o->variant) && (ob->dn == 1 || ob->dn == -1) && ob->dn == -o->dn_prev) {
			effort = o->f_prev_N;
			ob->flags |= POPC_ADM_FLAG_IGNORE;
		}
		if (ob->dn != 0)
			o->dn_prev = ob->dn;
	}
	o->started = 1;
	o->n_prev = n;
	o->f_prev_N = f_N;
	/* W-(k) = W(k-1) + f(k) v_VE(k) T: effort x flow increment (port.h) */
	ob->W_minus_J = popc_port_observe(&o->W_sum_J, &o->W_comp_J, effort, v_ve_mps * period_s);
	o->W_J = ob->W_minus_J;
}

void popc_admittance_observer_update(popc_admittance_observer *o, long long n, double f_N,
				     double v_ve_mps, double period_s,
				     popc_admittance_observation *ob)
{
	observer_update(o, n, f_N, v_ve_mps, period_s, ob);
}

static inline void observer_commit(popc_admittance_observer *o, double f_N, double v_pc_mps,
				   double period_s)
{
	if (v_pc_mps != 0.0)
		o->W_J = popc_port_observe(&o->W_sum_J, &o->W_comp_J, f_N, v_pc_mps * period_s);
}

void popc_admittance_observer_commit(popc_admittance_observer *o, double f_N, double v_pc_mps,
				     double period_s)
{
	observer_commit(o, f_N, v_pc_mps, period_s);
}

void popc_admittance_init(popc_admittance_controller *c, const popc_admittance_config *cfg,
			  double x0_m)
{
	memset(c, 0, sizeof *c);
	c->cfg = *cfg;
	c->x_v_m = x0_m;
	popc_admittance_observer_init(&c->obs, cfg->variant);
}

void popc_admittance_step(popc_admittance_controller *c, long long n, popc_admittance_tick *out)
{
	const popc_admittance_config *cfg = &c->cfg;
	const double T = cfg->period_s;
	const double f = (double)n * cfg->force_resolution_N;
	unsigned flags = 0;

	/* 1. the VE: m_v a + b_v v + f_env(x_v, v) = f, semi-implicit Euler
	 * (the environment at the VE's state before the step) */
	const double f_env = popc_environment_force(&cfg->env, c->x_v_m, c->v_v_mps);
	double v_ve;
	if (cfg->virtual_mass_kg > 0.0)
		v_ve = c->v_v_mps +
		       T * (f - cfg->virtual_damping_Nspm * c->v_v_mps - f_env) / cfg->virtual_mass_kg;
	else /* a damper (the scene refuses m_v = 0 without damping) */
		v_ve = (f - f_env) / cfg->virtual_damping_Nspm;
	if (!isfinite(v_ve)) {
		v_ve = 0.0;
		flags |= POPC_ADM_FLAG_GUARD;
	}
	c->v_v_mps = v_ve;
	c->x_v_m += T * v_ve;

	/* 2. the observer */
	popc_admittance_observation ob;
	observer_update(&c->obs, n, f, v_ve, T, &ob);
	flags |= ob.flags;

	/* 3. the parallel PC: v_pc = beta f = -W- / (T f) (port.h); held
	 * while the count does not change (hold, improved) */
	double v_pc = 0.0;
	switch (cfg->variant) {
	case POPC_ADMITTANCE_NONE:
		break;
	case POPC_ADMITTANCE_HOLD:
	case POPC_ADMITTANCE_IMPROVED:
		if (c->obs.started && ob.dn == 0 && c->v_pc_prev_mps != 0.0) {
			v_pc = c->v_pc_prev_mps;
			flags |= POPC_ADM_FLAG_HOLD;
			break;
		}
		v_pc = popc_port_pc(ob.W_minus_J, 0.0, f * T);
		break;
	case POPC_ADMITTANCE_PARALLEL:
	case POPC_ADMITTANCE_IGNORE:
	default:
		v_pc = popc_port_pc(ob.W_minus_J, 0.0, f * T);
		break;
	}
	if (isnan(v_pc)) {
		v_pc = 0.0;
		flags |= POPC_ADM_FLAG_GUARD;
	}
	const double bound = cfg->pc_velocity_bound_mps;
	if (v_pc > bound) {
		v_pc = bound;
		flags |= POPC_ADM_FLAG_CLAMP;
	} else if (v_pc < -bound) {
		v_pc = -bound;
		flags |= POPC_ADM_FLAG_CLAMP;
	}
	if (v_pc != 0.0)
		flags |= POPC_ADM_FLAG_ACTIVE;

	/* 4. the command and W(k) */
	double v_c = v_ve + v_pc;
	if (!isfinite(v_c)) {
		v_c = 0.0;
		flags |= POPC_ADM_FLAG_GUARD;
	}
	observer_commit(&c->obs, f, v_pc, T);
	c->v_pc_prev_mps = v_pc;

	out->n = n;
	out->f_N = f;
	out->x_ve_m = c->x_v_m;
	out->v_ve_mps = v_ve;
	out->f_env_N = f_env;
	out->v_pc_mps = v_pc;
	out->v_c_mps = v_c;
	out->W_J = c->obs.W_J;
	out->flags = flags;
}

double popc_admittance_count_velocity_mps(double resolution_N, double stiffness_Npm,
					  double virtual_mass_kg, double virtual_damping_Nspm,
					  double period_s)
{
	double v = 0.0;
	if (stiffness_Npm > 0.0)
		v = resolution_N / (stiffness_Npm * period_s);
	else if (virtual_mass_kg > 0.0)
		v = resolution_N * period_s / virtual_mass_kg;
	else if (virtual_damping_Nspm > 0.0)
		v = resolution_N / virtual_damping_Nspm;
	return isfinite(v) && v > 0.0 ? v : 0.0;
}
