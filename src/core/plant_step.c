/* Stepping the lumped plant (plant.h): one control period or a part of it,
 * by the exact step or a fixed-step integrator; a plant with friction goes
 * through plant_friction.c. (Apart from plant.c, which sets the plant up and
 * computes the step matrices, so that plant_friction.c can use those without
 * a call cycle.) */
#include "popc/core/plant.h"

#include <math.h>

#include "plant_substep.h"

static void fixed_step(const popc_plant_config *cfg, const popc_plant_step_coeffs *c,
		       popc_plant_state *st, const popc_plant_input *u)
{
	const int n = cfg->substeps;
	const double hs = c->h_s / n, m = cfg->mass_kg, k = cfg->stiffness_Npm,
		     b = cfg->damping_Nspm, w = cfg->omega_radps;
	double x = st->x_m, v = st->v_mps;
	switch (cfg->method) {
	case POPC_INTEGRATOR_TRAPEZOID: {
		double u_prev = popc_plant_input_at(u, w, 0.0);
		for (int i = 0; i < n; i++) {
			double u_next = popc_plant_input_at(u, w, (i + 1) * hs);
			double xs = c->trap[0][0] * x + c->trap[0][1] * v + c->trap_in[0] * (u_prev + u_next);
			double vs = c->trap[1][0] * x + c->trap[1][1] * v + c->trap_in[1] * (u_prev + u_next);
			x = xs;
			v = vs;
			u_prev = u_next;
		}
		break;
	}
	case POPC_INTEGRATOR_RK4:
		for (int i = 0; i < n; i++)
			popc_plant_rk4_substep(cfg, u, i * hs, hs, 0.0, &x, &v);
		break;
	case POPC_INTEGRATOR_SEMI_IMPLICIT_EULER:
		for (int i = 0; i < n; i++) {
			v += hs * (popc_plant_input_at(u, w, i * hs) - b * v - k * x) / m;
			x += hs * v;
		}
		break;
	case POPC_INTEGRATOR_EULER:
		for (int i = 0; i < n; i++) {
			double a = (popc_plant_input_at(u, w, i * hs) - b * v - k * x) / m;
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
	if (p->friction) {
		/* the full period's matrices are finite (popc_plant_init); a
		 * segment's are finite for an h below T (the same exponential,
		 * shorter) */
		(void)popc_plant_friction_step(p, st, u, p->full.h_s);
		return;
	}
	if (p->cfg.method == POPC_INTEGRATOR_EXACT)
		popc_plant_step_exact(&p->full, st, u);
	else
		fixed_step(&p->cfg, &p->full, st, u);
}

int popc_plant_step_h(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
		      double h_s)
{
	if (p->friction)
		return popc_plant_friction_step(p, st, u, h_s);
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
