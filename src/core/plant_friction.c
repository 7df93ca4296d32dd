/* Device friction on the lumped plant (plant.h): Coulomb friction and
 * stiction,
 *
 *     M x'' = u(t) - B x' - K x - F_c sign(x')         while x' != 0,
 *     x' = 0, x constant            while x' = 0 and |u(t) - K x| <= F_s,
 *
 * F_s = max(stiction, coulomb) >= F_c. At rest the body breaks away when the
 * net applied force g = u - K x (B x' = 0) leaves [-F_s, F_s], sliding in the
 * direction of g; a sliding body that reaches x' = 0 sticks if |g| <= F_s
 * there, else slides back (Karnopp's stick band, without its velocity band:
 * the exact method finds v = 0 itself).
 *
 * Exact method. Between velocity zero crossings the friction force is the
 * constant -F_c s (s = sign of the motion), an input like u0, so each slide
 * is the linear plant stepped exactly (expm, plant.c). The period is cut at
 * the first v = 0:
 *   - detection: v is stepped over friction_subs sub-intervals of the period
 *     (each turning at most 1/2 rad at sqrt(K/M) or the sine's w), and a sign
 *     change of v at a sub-interval's end, or a non-positive minimum of s v on
 *     the cubic Hermite interpolant of (v, a) at its two ends, brackets a zero.
 *     This is the approximate part: two zeros closer than the interpolant can
 *     see within one sub-interval (a graze of v = 0 with |v| below the cubic's
 *     error, O(a''' h^4)) can be missed; the body then slides on through it;
 *   - location: safeguarded Newton (v' = a is known in closed form) on the
 *     exact solution v(t) = [Phi(t) x0 + Gam(t) u]_v, with bisection when
 *     Newton leaves the bracket or does not halve it, until the bracket is two
 *     adjacent doubles of the time since the sub-interval's start (or v = 0
 *     exactly). The state is taken at the bracket's far end (s v <= 0) and v
 *     set to 0: the time is exact to one ulp of the sub-interval time, and the
 *     velocity discarded is |a| ulp(t) (1e-19 m/s for a = 1 m/s^2, t = 1 ms).
 * Sticking is exact (x constant, v = 0); the break-away time is the closed
 * form of a linear input, moved to the first double where |g| > F_s, or for a
 * sine input bisected to adjacent doubles on sub-intervals of 1/2 rad (an
 * excursion of g past F_s shorter than one sub-interval can be missed).
 *
 * Fixed-step integrators: per substep, a body at rest (v == 0) whose net
 * force at the substep's start is within F_s stays put; otherwise the
 * integrator takes its substep with the constant friction force -F_c s
 * (s = sign(v), or sign(g) when breaking away), and a substep that ends with
 * s v < 0 (it passed v = 0) ends at rest, v = 0: the next substep decides
 * stick or slip. Their error against the exact method is measured by the
 * simulated axis' shadow as without friction. */
#include <math.h>

#include "popc/core/plant.h"

#include "plant_substep.h"

/* A body keeps hitting v = 0 at its stick/slip boundary (F_s = F_c and an
 * applied force that barely moves it) with each event advancing time by
 * about one ulp: after this many events in one step it stays at rest for
 * the rest of that step (sticking is where such a body is within rounding). */
#define FRICTION_EVENTS_MAX 1000

/* Root finding: at most this many iterations (bisection alone needs about 60
 * per sub-interval to reach adjacent doubles, plus the exponent range when
 * the root is near 0) */
#define ROOT_ITERATIONS_MAX 2200

double popc_plant_stick_N(const popc_plant_config *cfg)
{
	return fmax(cfg->stiction_N, cfg->coulomb_N);
}

/* u(tau0 + t) as an input of t, plus the constant force f_N */
static void shift_input(const popc_plant_input *u, double w, double tau0, double f_N,
			popc_plant_input *out)
{
	out->u0_N = (u->u0_N + u->u1_Nps * tau0) + f_N;
	out->u1_Nps = u->u1_Nps;
	if (w != 0.0 && tau0 != 0.0) {
		double c = cos(w * tau0), s = sin(w * tau0);
		/* us sin(w (tau0 + t)) + uc cos(w (tau0 + t)) */
		out->us_N = u->us_N * c - u->uc_N * s;
		out->uc_N = u->us_N * s + u->uc_N * c;
	} else {
		out->us_N = u->us_N;
		out->uc_N = u->uc_N;
	}
}

static double accel(const popc_plant_config *c, const popc_plant_input *u, double t,
		    const popc_plant_state *st)
{
	return (popc_plant_input_at(u, c->omega_radps, t) - c->damping_Nspm * st->v_mps -
		c->stiffness_Npm * st->x_m) /
	       c->mass_kg;
}

/* The exact state t after st0 under the input useg (friction included). */
static int exact_at(const popc_plant *p, const popc_plant_state *st0, const popc_plant_input *useg,
		    double t, popc_plant_state *out)
{
	*out = *st0;
	if (t == 0.0)
		return 0;
	popc_plant_step_coeffs c;
	const popc_plant_step_coeffs *cp = &c;
	if (t == p->full.h_s)
		cp = &p->full;
	else if (t == p->sub.h_s)
		cp = &p->sub;
	else {
		int status = popc_plant_coeffs(&p->cfg, t, &c);
		if (status)
			return status;
	}
	popc_plant_step_exact(cp, out, useg);
	return 0;
}

/* The smallest theta in (0, 1) where s p(theta) <= 0 for the cubic Hermite
 * interpolant p of v0, v1 with slopes m0, m1 (per unit theta), given
 * s v0 > 0, s v1 > 0; -1 when its minimum over [0, 1] is positive. */
static double hermite_dip(double s, double v0, double m0, double v1, double m1)
{
	double c1 = s * m0, c2 = s * (-3.0 * v0 - 2.0 * m0 + 3.0 * v1 - m1),
	       c3 = s * (2.0 * v0 + m0 - 2.0 * v1 + m1), c0 = s * v0;
	/* critical points: c1 + 2 c2 th + 3 c3 th^2 = 0 */
	double th[2];
	int n = 0;
	if (c3 == 0.0) {
		if (c2 != 0.0)
			th[n++] = -c1 / (2.0 * c2);
	} else {
		double disc = c2 * c2 - 3.0 * c3 * c1;
		if (disc >= 0.0) {
			double q = -(c2 + copysign(sqrt(disc), c2)); /* no cancellation */
			if (q != 0.0) {
				th[n++] = q / (3.0 * c3);
				th[n++] = c1 / q;
			}
		}
	}
	double best = -1.0;
	for (int i = 0; i < n; i++)
		if (th[i] > 0.0 && th[i] < 1.0 && ((c3 * th[i] + c2) * th[i] + c1) * th[i] + c0 <= 0.0)
			if (best < 0.0 || th[i] < best)
				best = th[i];
	return best;
}

/* Locates v = 0 in (lo, hi] after st0 (s v(lo) > 0, s v(hi) <= 0, state at hi
 * given): safeguarded Newton, bisection as the fallback, to adjacent doubles.
 * Leaves in *at the state at the final hi and in *t_hi that time. */
static int locate_zero(const popc_plant *p, const popc_plant_state *st0,
		       const popc_plant_input *useg, double s, double lo, double hi,
		       popc_plant_state *at, double *t_hi)
{
	popc_plant_state cur = *at;
	double t_last = hi, width_before = 2.0 * (hi - lo);
	for (int it = 0; it < ROOT_ITERATIONS_MAX; it++) {
		double mid = lo + 0.5 * (hi - lo);
		if (!(mid > lo && mid < hi) || cur.v_mps == 0.0)
			break; /* adjacent doubles, or the zero itself */
		double a = accel(&p->cfg, useg, t_last, &cur);
		double cand = t_last - cur.v_mps / a;
		/* Newton's step unless it leaves the bracket or the last two
		 * steps did not halve it */
		if (!(cand > lo && cand < hi) || hi - lo > 0.5 * width_before)
			cand = mid;
		width_before = hi - lo;
		popc_plant_state trial;
		int status = exact_at(p, st0, useg, cand, &trial);
		if (status)
			return status;
		if (s * trial.v_mps > 0.0) {
			lo = cand;
			/* Newton continues from the latest point on either side */
			cur = trial;
		} else {
			hi = cand;
			*at = trial;
			cur = trial;
		}
		t_last = cand;
	}
	*t_hi = hi;
	return 0;
}

/* The slide from st (moving in direction s, or at rest breaking away in it)
 * over [0, len] of the input useg (friction included): to the end, or to the
 * first v = 0 (*stopped = 1, v set to 0, *t_out its time). */
static int slide(const popc_plant *p, popc_plant_state *st, const popc_plant_input *useg, double s,
		 double len, int *stopped, double *t_out)
{
	const popc_plant_config *c = &p->cfg;
	int n = len == p->full.h_s ? p->friction_subs : 1;
	if (n == 1 && len != p->full.h_s && p->friction_subs > 1)
		n = (int)ceil(p->friction_subs * (len / p->full.h_s));
	if (n < 1)
		n = 1;
	/* sub-intervals of hsub (p->sub's matrices for a whole period), the last
	 * one ending exactly at len */
	double hsub = len / n;
	popc_plant_state a = *st;
	double t0 = 0.0;
	*stopped = 0;
	for (int j = 0; j < n; j++) {
		double h = j + 1 == n ? len - t0 : hsub;
		popc_plant_input uj;
		shift_input(useg, c->omega_radps, t0, 0.0, &uj);
		popc_plant_state b;
		int status = exact_at(p, &a, &uj, h, &b);
		if (status)
			return status;
		double lo = 0.0, hi = -1.0;
		popc_plant_state at_hi = b;
		if (s * b.v_mps <= 0.0) {
			hi = h;
		} else if (s * a.v_mps > 0.0) {
			double th = hermite_dip(s, a.v_mps, h * accel(c, &uj, 0.0, &a), b.v_mps,
						h * accel(c, &uj, h, &b));
			if (th > 0.0) {
				popc_plant_state m;
				if ((status = exact_at(p, &a, &uj, th * h, &m)) != 0)
					return status;
				if (s * m.v_mps <= 0.0) {
					hi = th * h;
					at_hi = m;
				}
			}
		}
		if (hi >= 0.0) {
			/* a body breaking away (v = 0 at lo = 0) moves off in s at once
			 * (|g| > F_s >= F_c): v has the sign s just after lo */
			double t_hi;
			if ((status = locate_zero(p, &a, &uj, s, lo, hi, &at_hi, &t_hi)) != 0)
				return status;
			*st = at_hi;
			st->v_mps = 0.0;
			*stopped = 1;
			*t_out = t0 + t_hi;
			return 0;
		}
		a = b;
		t0 += h;
	}
	*st = a;
	return 0;
}

/* At rest at tau: the first time in (tau, h] where |u(t) - K x| > F_s, or a
 * value > h when none. */
static double break_away(const popc_plant_config *c, const popc_plant_input *u, double x,
			 double tau, double h, double f_s, int subs)
{
	double kx = c->stiffness_Npm * x, w = c->omega_radps;
#define OUTSIDE(t) (fabs(popc_plant_input_at(u, w, (t)) - kx) > f_s)
	if (w == 0.0) {
		if (u->u1_Nps == 0.0)
			return 2.0 * h + 1.0;
		double edge = u->u1_Nps > 0.0 ? f_s : -f_s;
		double t = (edge + kx - u->u0_N) / u->u1_Nps;
		if (t > h)
			return t;
		if (!(t > tau))
			t = tau;
		if (OUTSIDE(t)) {
			/* the closed form rounds: back to the first double past the
			 * edge (within 64 doubles: a force flat to rounding over more
			 * is at the edge anyway) */
			for (int i = 0; i < 64; i++) {
				double prev = nextafter(t, -HUGE_VAL);
				if (!(prev > tau) || !OUTSIDE(prev))
					break;
				t = prev;
			}
			return t;
		}
		/* g is monotone: past the edge from some time in (t, h] or never */
		if (!OUTSIDE(h))
			return 2.0 * h + 1.0;
		double lo = t, hi = h;
		for (int it = 0; it < ROOT_ITERATIONS_MAX; it++) {
			double mid = lo + 0.5 * (hi - lo);
			if (!(mid > lo && mid < hi))
				break;
			if (OUTSIDE(mid))
				hi = mid;
			else
				lo = mid;
		}
		return hi;
	}
	int n = subs < 1 ? 1 : subs;
	double step = (h - tau) / n, lo = tau;
	for (int j = 1; j <= n; j++) {
		double hi = j == n ? h : tau + j * step;
		if (OUTSIDE(hi)) {
			for (int it = 0; it < ROOT_ITERATIONS_MAX; it++) {
				double mid = lo + 0.5 * (hi - lo);
				if (!(mid > lo && mid < hi))
					break;
				if (OUTSIDE(mid))
					hi = mid;
				else
					lo = mid;
			}
			return hi;
		}
		lo = hi;
	}
	return 2.0 * h + 1.0;
#undef OUTSIDE
}

static double sign_of(double v)
{
	return v > 0.0 ? 1.0 : -1.0;
}

static int exact_friction_step(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
			       double h)
{
	const popc_plant_config *c = &p->cfg;
	double f_c = c->coulomb_N, f_s = popc_plant_stick_N(c), w = c->omega_radps;
	popc_plant_state cur = *st;
	double tau = 0.0;
	for (int events = 0; tau < h; events++) {
		double s;
		if (cur.v_mps == 0.0) {
			double g = popc_plant_input_at(u, w, tau) - c->stiffness_Npm * cur.x_m;
			if (!(fabs(g) > f_s)) {
				if (events >= FRICTION_EVENTS_MAX)
					break; /* at rest for the rest of the step */
				double tb = break_away(c, u, cur.x_m, tau, h, f_s, p->friction_subs);
				if (!(tb < h))
					break; /* stuck to the end of the step */
				tau = tb;
				g = popc_plant_input_at(u, w, tau) - c->stiffness_Npm * cur.x_m;
			}
			s = sign_of(g);
		} else {
			s = sign_of(cur.v_mps);
		}
		if (events >= FRICTION_EVENTS_MAX) {
			/* slide to the end without looking for v = 0 */
			popc_plant_input useg;
			shift_input(u, w, tau, -s * f_c, &useg);
			popc_plant_state end;
			int status = exact_at(p, &cur, &useg, h - tau, &end);
			if (status)
				return status;
			cur = end;
			break;
		}
		popc_plant_input useg;
		shift_input(u, w, tau, -s * f_c, &useg);
		int stopped = 0;
		double t_stop = 0.0;
		popc_plant_state next = cur;
		int status = slide(p, &next, &useg, s, h - tau, &stopped, &t_stop);
		if (status)
			return status;
		cur = next;
		if (!stopped)
			break;
		double t_new = tau + t_stop;
		tau = t_new < h ? t_new : h;
	}
	*st = cur;
	return 0;
}

/* One substep of hs of the fixed-step method with the input u from t and
 * the constant extra force f_N (plant.c's fixed_step, one substep). */
static void fixed_substep(const popc_plant_config *cfg, const popc_plant_step_coeffs *c,
			  const popc_plant_input *u, double t, double hs, double f_N, double *xp,
			  double *vp)
{
	const double m = cfg->mass_kg, k = cfg->stiffness_Npm, b = cfg->damping_Nspm,
		     w = cfg->omega_radps;
	double x = *xp, v = *vp;
	switch (cfg->method) {
	case POPC_INTEGRATOR_TRAPEZOID: {
		double us = popc_plant_input_at(u, w, t) + popc_plant_input_at(u, w, t + hs) + 2.0 * f_N;
		double xs = c->trap[0][0] * x + c->trap[0][1] * v + c->trap_in[0] * us;
		double vs = c->trap[1][0] * x + c->trap[1][1] * v + c->trap_in[1] * us;
		x = xs;
		v = vs;
		break;
	}
	case POPC_INTEGRATOR_RK4:
		popc_plant_rk4_substep(cfg, u, t, hs, f_N, &x, &v);
		break;
	case POPC_INTEGRATOR_SEMI_IMPLICIT_EULER:
		v += hs * (popc_plant_input_at(u, w, t) + f_N - b * v - k * x) / m;
		x += hs * v;
		break;
	case POPC_INTEGRATOR_EULER: {
		double a = (popc_plant_input_at(u, w, t) + f_N - b * v - k * x) / m;
		x += hs * v;
		v += hs * a;
		break;
	}
	default:
		break;
	}
	*xp = x;
	*vp = v;
}

static int fixed_friction_step(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
			       double h)
{
	const popc_plant_config *cfg = &p->cfg;
	popc_plant_step_coeffs c;
	const popc_plant_step_coeffs *cp = &p->full;
	if (h != p->full.h_s) {
		int status = popc_plant_coeffs(cfg, h, &c);
		if (status)
			return status;
		cp = &c;
	}
	const int n = cfg->substeps;
	const double hs = h / n, f_c = cfg->coulomb_N, f_s = popc_plant_stick_N(cfg);
	double x = st->x_m, v = st->v_mps;
	for (int i = 0; i < n; i++) {
		double t = i * hs, s;
		if (v == 0.0) {
			double g = popc_plant_input_at(u, cfg->omega_radps, t) - cfg->stiffness_Npm * x;
			if (!(fabs(g) > f_s))
				continue; /* stuck through this substep */
			s = sign_of(g);
		} else {
			s = sign_of(v);
		}
		fixed_substep(cfg, cp, u, t, hs, -s * f_c, &x, &v);
		if (s * v < 0.0)
			v = 0.0; /* passed v = 0 within the substep: at rest at its end */
	}
	st->x_m = x;
	st->v_mps = v;
	return 0;
}

int popc_plant_friction_step(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
			     double h_s)
{
	if (p->cfg.method == POPC_INTEGRATOR_EXACT)
		return exact_friction_step(p, st, u, h_s);
	return fixed_friction_step(p, st, u, h_s);
}
