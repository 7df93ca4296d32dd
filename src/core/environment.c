#include "popc/environment.h"

void popc_environment_from_scene(popc_environment *e, const popc_scene *s)
{
	e->kind = s->env_kind;
	e->stiffness_Npm = s->env_stiffness_Npm;
	e->damping_Nspm = s->env_damping_Nspm;
	e->position_m = s->env_position_m;
}
