/* The admittance-type device as a lumped plant (admittance_plant.h). */
#include "popc/core/admittance_plant.h"

#include <string.h>

#include "plant_substep.h"

const char *const popc_servo_kind_names[] = {"position", "velocity", NULL};

int popc_admittance_plant_init(popc_admittance_plant *p, const popc_admittance_plant_config *cfg,
			       popc_error *err)
{
	memset(p, 0, sizeof *p);
	p->cfg = *cfg;
	const double kp = cfg->servo == POPC_SERVO_POSITION ? cfg->servo_stiffness_Npm : 0.0;
	popc_plant_config pc = {
		.mass_kg = cfg->hand_mass_kg + cfg->dev_mass_kg,
		.damping_Nspm = cfg->hand_damping_Nspm + cfg->dev_damping_Nspm + cfg->servo_damping_Nspm,
		.stiffness_Npm = cfg->hand_stiffness_Npm + cfg->dev_stiffness_Npm + kp,
		.omega_radps = cfg->omega_radps,
		.method = cfg->method,
		.substeps = cfg->substeps,
		.period_s = cfg->period_s,
	};
	p->k_total_Npm = pc.stiffness_Npm;
	return popc_plant_init(&p->plant, &pc, err);
}

void popc_admittance_plant_input(const popc_admittance_plant *p, const popc_plant_input *hand,
				 double x_cmd_m, double v_cmd_mps, double tau0_s,
				 popc_plant_input *u)
{
	const popc_admittance_plant_config *c = &p->cfg;
	const double kp = c->servo == POPC_SERVO_POSITION ? c->servo_stiffness_Npm : 0.0;
	/* x_c(tau0 + s) = x_cmd + v_c (tau0 + s); in y the springs' pull at the
	 * origin, K x_origin, moves to the input */
	const double x_c = x_cmd_m + v_cmd_mps * tau0_s;
	*u = *hand;
	u->u0_N = (hand->u0_N - p->k_total_Npm * c->x_origin_m) + kp * x_c +
		  c->servo_damping_Nspm * v_cmd_mps;
	u->u1_Nps = hand->u1_Nps + kp * v_cmd_mps;
}

double popc_admittance_plant_sensed_N(const popc_admittance_plant *p, const popc_plant_state *st,
				      const popc_plant_input *hand, const popc_plant_input *u,
				      double tau_s)
{
	const popc_admittance_plant_config *c = &p->cfg;
	const popc_plant_config *pc = &p->plant.cfg;
	const double w = pc->omega_radps;
	/* the body's acceleration from its equation (in y), then the hand's
	 * share: f_s = u_hand - K_HO x - B_HO x' - M_HO x'' */
	const double a = (popc_plant_input_at(u, w, tau_s) - pc->damping_Nspm * st->v_mps -
			  pc->stiffness_Npm * st->x_m) /
			 pc->mass_kg;
	const double x = c->x_origin_m + st->x_m;
	return popc_plant_input_at(hand, w, tau_s) - c->hand_stiffness_Npm * x -
	       c->hand_damping_Nspm * st->v_mps - c->hand_mass_kg * a;
}
