/* What plant_step.c and plant_friction.c share (private to src/core): the
 * operator's input at a time in the step, and one RK4 substep of the fixed-
 * step integrator. */
#ifndef POPC_PLANT_SUBSTEP_H
#define POPC_PLANT_SUBSTEP_H

#include <math.h>

#include "popc/core/plant.h"

/* u(tau) = u0 + u1 tau (+ us sin(w tau) + uc cos(w tau) with a sine). */
static inline double popc_plant_input_at(const popc_plant_input *u, double w, double tau)
{
	double val = u->u0_N + u->u1_Nps * tau;
	if (w != 0.0)
		val += u->us_N * sin(w * tau) + u->uc_N * cos(w * tau);
	return val;
}

/* One classical RK4 substep of hs from t of M x'' = u(t) + f_N - B x' - K x.
 * f_N (friction's constant force over the substep) is added only when it is
 * not 0, so that the linear plant's substep keeps its operations and bits. */
static inline void popc_plant_rk4_substep(const popc_plant_config *cfg, const popc_plant_input *u,
					  double t, double hs, double f_N, double *xp, double *vp)
{
	const double m = cfg->mass_kg, k = cfg->stiffness_Npm, b = cfg->damping_Nspm,
		     w = cfg->omega_radps;
	double u0 = popc_plant_input_at(u, w, t), um = popc_plant_input_at(u, w, t + hs / 2),
	       u1 = popc_plant_input_at(u, w, t + hs);
	if (f_N != 0.0) {
		u0 += f_N;
		um += f_N;
		u1 += f_N;
	}
	double x = *xp, v = *vp;
	double k1x = v, k1v = (u0 - b * v - k * x) / m;
	double x2 = x + hs / 2 * k1x, v2 = v + hs / 2 * k1v;
	double k2x = v2, k2v = (um - b * v2 - k * x2) / m;
	double x3 = x + hs / 2 * k2x, v3 = v + hs / 2 * k2v;
	double k3x = v3, k3v = (um - b * v3 - k * x3) / m;
	double x4 = x + hs * k3x, v4 = v + hs * k3v;
	double k4x = v4, k4v = (u1 - b * v4 - k * x4) / m;
	*xp = x + hs / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
	*vp = v + hs / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

#endif
