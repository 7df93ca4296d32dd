/* The lumped plant M x'' = u(t) - B x' - K x and its integrators (plant.h). */
#include "popc/core/plant.h"

#include <math.h>
#include <string.h>

#define POPC_TWO_PI 6.283185307179586476925286766559

const char *const popc_integrator_names[] = {"exact", "trapezoid", "rk4", "semi-implicit-euler",
					     "euler", NULL};

const char *popc_integrator_name(popc_integrator m)
{
	return (unsigned)m < POPC_INTEGRATOR_COUNT ? popc_integrator_names[m] : "?";
}

int popc_integrator_from_name(const char *name, popc_integrator *out)
{
	for (int i = 0; popc_integrator_names[i]; i++)
		if (strcmp(popc_integrator_names[i], name) == 0) {
			*out = (popc_integrator)i;
			return 0;
		}
	return POPC_ERR_INVALID;
}

/* Exact step: the augmented system [x v y1 y2 p q] with y1' = y2 (affine input
 * u0 + u1 tau) and the rotation p' = w q, q' = -w p (p(0) = uc, q(0) = us gives
 * p = uc cos(w tau) + us sin(w tau)); u = y1 + p drives v. expm(A_aug h) holds
 * Phi in its top-left block and the input columns beside it. The sine states
 * exist only when the scene has a sine (model only what the scene needs). */
static int exact_coeffs(const popc_plant_config *cfg, double h, popc_plant_step_coeffs *c)
{
	int n = cfg->omega_radps != 0.0 ? 6 : 4;
	double a[36] = {0}, e[36];
	double m = cfg->mass_kg;
	a[0 * n + 1] = 1.0;
	a[1 * n + 0] = -cfg->stiffness_Npm / m;
	a[1 * n + 1] = -cfg->damping_Nspm / m;
	a[1 * n + 2] = 1.0 / m;
	a[2 * n + 3] = 1.0;
	if (n == 6) {
		a[1 * n + 4] = 1.0 / m;
		a[4 * n + 5] = cfg->omega_radps;
		a[5 * n + 4] = -cfg->omega_radps;
	}
	for (int i = 0; i < n * n; i++)
		a[i] *= h;
	int st = popc_expm(n, a, e);
	if (st)
		return st;
	for (int i = 0; i < 2; i++) {
		c->phi[i][0] = e[i * n + 0];
		c->phi[i][1] = e[i * n + 1];
		c->gam[i][0] = e[i * n + 2];
		c->gam[i][1] = e[i * n + 3];
		c->gam[i][2] = n == 6 ? e[i * n + 4] : 0.0;
		c->gam[i][3] = n == 6 ? e[i * n + 5] : 0.0;
	}
	return 0;
}

/* Trapezoidal rule for the linear system z' = A z + b u, one substep of length
 * hs: (I - hs A/2) z+ = (I + hs A/2) z + hs/2 b (u(t) + u(t + hs)). */
static void trapezoid_coeffs(const popc_plant_config *cfg, double hs, popc_plant_step_coeffs *c)
{
	double m = cfg->mass_kg, k = cfg->stiffness_Npm / m, b = cfg->damping_Nspm / m;
	/* L = I - hs/2 A = [1, -hs/2; hs/2 k, 1 + hs/2 b], R = I + hs/2 A */
	double l00 = 1.0, l01 = -hs / 2, l10 = hs / 2 * k, l11 = 1.0 + hs / 2 * b;
	double det = l00 * l11 - l01 * l10;
	double i00 = l11 / det, i01 = -l01 / det, i10 = -l10 / det, i11 = l00 / det;
	double r00 = 1.0, r01 = hs / 2, r10 = -hs / 2 * k, r11 = 1.0 - hs / 2 * b;
	c->trap[0][0] = i00 * r00 + i01 * r10;
	c->trap[0][1] = i00 * r01 + i01 * r11;
	c->trap[1][0] = i10 * r00 + i11 * r10;
	c->trap[1][1] = i10 * r01 + i11 * r11;
	c->trap_in[0] = i01 * (hs / 2 / m);
	c->trap_in[1] = i11 * (hs / 2 / m);
}

int popc_plant_coeffs(const popc_plant_config *cfg, double h_s, popc_plant_step_coeffs *c)
{
	memset(c, 0, sizeof *c);
	c->h_s = h_s;
	int st = 0;
	if (cfg->method == POPC_INTEGRATOR_EXACT)
		st = exact_coeffs(cfg, h_s, c);
	else if (cfg->method == POPC_INTEGRATOR_TRAPEZOID)
		trapezoid_coeffs(cfg, h_s / cfg->substeps, c);
	if (st)
		return st;
	/* scaling and squaring can overflow for a plant far too stiff for the
	 * step: a non-finite coefficient would turn every later state into
	 * garbage (and an uninitialised-looking encoder count) */
	const double *v = &c->phi[0][0];
	for (size_t i = 0; i < 4; i++)
		if (!isfinite(v[i]))
			return POPC_ERR_NUMERIC;
	v = &c->gam[0][0];
	for (size_t i = 0; i < 8; i++)
		if (!isfinite(v[i]))
			return POPC_ERR_NUMERIC;
	v = &c->trap[0][0];
	for (size_t i = 0; i < 4; i++)
		if (!isfinite(v[i]))
			return POPC_ERR_NUMERIC;
	if (!isfinite(c->trap_in[0]) || !isfinite(c->trap_in[1]))
		return POPC_ERR_NUMERIC;
	return 0;
}

int popc_plant_init(popc_plant *p, const popc_plant_config *cfg, popc_error *err)
{
	if (!(cfg->mass_kg > 0) || !isfinite(cfg->mass_kg))
		return popc_error_set(err, POPC_ERR_INVALID, "plant: mass %g kg must be > 0",
				      cfg->mass_kg);
	if (!(cfg->damping_Nspm >= 0) || !(cfg->stiffness_Npm >= 0) || !isfinite(cfg->damping_Nspm) ||
	    !isfinite(cfg->stiffness_Npm))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: damping and stiffness must be finite and >= 0");
	if (cfg->substeps < 1 || !(cfg->period_s > 0) || !isfinite(cfg->period_s))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: substeps must be >= 1 and the period > 0");
	/* Every method divides by M and the exact one scales A h; a ratio that
	 * overflows is no plant double precision can step (e.g. K = 1e9 N/m on
	 * M = 2.3e-308 kg: K/M = inf). The scene keys behind each quantity are
	 * named, since popc_plant_config_from_scene sums them. */
	double m = cfg->mass_kg, h = cfg->period_s;
	double k_m = cfg->stiffness_Npm / m, b_m = cfg->damping_Nspm / m;
	if (!isfinite(1.0 / m))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: 1/M is not finite for M = operator.mass + device.mass = "
				      "%g kg; raise operator.mass + device.mass",
				      m);
	if (!isfinite(k_m) || !isfinite(k_m * h * h))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: K/M = (operator.stiffness + device.stiffness) / (operator.mass "
				      "+ device.mass) = %g N/m / %g kg%s is not finite; raise operator.mass + "
				      "device.mass or lower operator.stiffness + device.stiffness",
				      cfg->stiffness_Npm, m, isfinite(k_m) ? " times T^2 (1 / run.rate)^2" : "");
	if (!isfinite(b_m))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: B/M = (operator.damping + device.damping) / (operator.mass + "
				      "device.mass) = %g N s/m / %g kg is not finite; raise operator.mass + "
				      "device.mass or lower operator.damping + device.damping",
				      cfg->damping_Nspm, m);
	p->cfg = *cfg;
	if (popc_plant_coeffs(cfg, cfg->period_s, &p->full) != 0)
		return popc_error_set(err, POPC_ERR_NUMERIC,
				      "plant: the %s step matrices for T = %g s are not finite (K/M = %g "
				      "1/s^2, B/M = %g 1/s): the plant (operator.* + device.* mass, damping, "
				      "stiffness) is too stiff for double precision at this run.rate",
				      popc_integrator_name(cfg->method), h, k_m, b_m);
	return 0;
}

static inline double input_at(const popc_plant_input *u, double w, double tau)
{
	double val = u->u0_N + u->u1_Nps * tau;
	if (w != 0.0)
		val += u->us_N * sin(w * tau) + u->uc_N * cos(w * tau);
	return val;
}

static void fixed_step(const popc_plant_config *cfg, const popc_plant_step_coeffs *c,
		       popc_plant_state *st, const popc_plant_input *u)
{
	const int n = cfg->substeps;
	const double hs = c->h_s / n, m = cfg->mass_kg, k = cfg->stiffness_Npm,
		     b = cfg->damping_Nspm, w = cfg->omega_radps;
	double x = st->x_m, v = st->v_mps;
	switch (cfg->method) {
	case POPC_INTEGRATOR_TRAPEZOID: {
		double u_prev = input_at(u, w, 0.0);
		for (int i = 0; i < n; i++) {
			double u_next = input_at(u, w, (i + 1) * hs);
			double xs = c->trap[0][0] * x + c->trap[0][1] * v + c->trap_in[0] * (u_prev + u_next);
			double vs = c->trap[1][0] * x + c->trap[1][1] * v + c->trap_in[1] * (u_prev + u_next);
			x = xs;
			v = vs;
			u_prev = u_next;
		}
		break;
	}
	case POPC_INTEGRATOR_RK4:
		for (int i = 0; i < n; i++) {
			double t = i * hs;
			double u0 = input_at(u, w, t), um = input_at(u, w, t + hs / 2),
			       u1 = input_at(u, w, t + hs);
			double k1x = v, k1v = (u0 - b * v - k * x) / m;
			double x2 = x + hs / 2 * k1x, v2 = v + hs / 2 * k1v;
			double k2x = v2, k2v = (um - b * v2 - k * x2) / m;
			double x3 = x + hs / 2 * k2x, v3 = v + hs / 2 * k2v;
			double k3x = v3, k3v = (um - b * v3 - k * x3) / m;
			double x4 = x + hs * k3x, v4 = v + hs * k3v;
			double k4x = v4, k4v = (u1 - b * v4 - k * x4) / m;
			x += hs / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
			v += hs / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
		}
		break;
	case POPC_INTEGRATOR_SEMI_IMPLICIT_EULER:
		for (int i = 0; i < n; i++) {
			v += hs * (input_at(u, w, i * hs) - b * v - k * x) / m;
			x += hs * v;
		}
		break;
	case POPC_INTEGRATOR_EULER:
		for (int i = 0; i < n; i++) {
			double a = (input_at(u, w, i * hs) - b * v - k * x) / m;
			x += hs * v;
			v += hs * a;
		}
		break;
	default:
		break;
	}
	st->x_m = x;
	st->v_mps = v;
}

void popc_plant_step(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u)
{
	if (p->cfg.method == POPC_INTEGRATOR_EXACT)
		popc_plant_step_exact(&p->full, st, u);
	else
		fixed_step(&p->cfg, &p->full, st, u);
}

int popc_plant_step_h(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
		      double h_s)
{
	if (h_s == p->full.h_s) {
		popc_plant_step(p, st, u);
		return 0;
	}
	popc_plant_step_coeffs c;
	int status = popc_plant_coeffs(&p->cfg, h_s, &c);
	if (status)
		return status;
	if (p->cfg.method == POPC_INTEGRATOR_EXACT)
		popc_plant_step_exact(&c, st, u);
	else
		fixed_step(&p->cfg, &c, st, u);
	return 0;
}
