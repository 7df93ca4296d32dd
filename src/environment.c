#include "popc/environment.h"

void popc_environment_from_scene(popc_environment *e, const popc_scene *s)
{
	e->kind = s->env_kind;
	e->stiffness_Npm = s->env_stiffness_Npm;
	e->damping_Nspm = s->env_damping_Nspm;
	e->position_m = s->env_position_m;
}

int popc_environment_in_contact(const popc_environment *e, double x_m)
{
	return e->kind == POPC_ENV_SPRING || x_m >= e->position_m;
}

double popc_environment_force(const popc_environment *e, double x_m, double v_mps)
{
	double pen = x_m - e->position_m;
	if (e->kind == POPC_ENV_WALL) {
		if (!(pen >= 0.0))
			return 0.0;
		double f = e->stiffness_Npm * pen;
		if (e->damping_Nspm != 0.0)
			f += e->damping_Nspm * v_mps;
		return f > 0.0 ? f : 0.0; /* a wall pushes, never pulls */
	}
	double f = e->stiffness_Npm * pen;
	if (e->damping_Nspm != 0.0)
		f += e->damping_Nspm * v_mps;
	return f;
}
