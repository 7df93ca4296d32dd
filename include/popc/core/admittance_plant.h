/* The simulated admittance-type device (docs/ADMITTANCE.md, "The plant"):
 * the operator's hand (M_HO, B_HO, K_HO pulling towards x_d) holds the handle
 * of a device (M_HI, B_HI, K_HI) whose inner servo loop tracks the commanded
 * motion,
 *
 *   position servo:  F_s = K_p (x_c(t) - x) + K_v (v_c - x'),
 *   velocity servo:  F_s = K_v (v_c - x')                      (K_p = 0),
 *
 * with the velocity command v_c held over the period and the position command
 * following it, x_c(kT + tau) = x_c(k) + v_c tau (first-order hold). Hand,
 * device and servo are one rigid body,
 *
 *   (M_HO + M_HI) x'' = u_hand(t) + K_p x_c(t) + K_v v_c
 *                       - (B_HO + B_HI + K_v) x' - (K_HO + K_HI + K_p) x,
 *
 * the lumped plant of plant.h with the servo's gains added to its damping and
 * stiffness and its command to the input (u0 += K_p x_c(k) + K_v v_c,
 * u1 += K_p v_c): so the exact step (expm of the augmented system under the
 * hold) integrates it exactly, as it does the impedance plant.
 *
 * The force sensor sits between the hand and the handle; it reads the force
 * the hand exerts on the device,
 *
 *   f_s = u_hand(t) - K_HO x - B_HO x' - M_HO x'',
 *
 * taken at the end of the period (the left limit: the command of the period
 * that just ended still acts). Left out: the servo's own bandwidth limits
 * (current loop, amplifier saturation), compliance between handle and
 * sensor, sensor dynamics, friction (refused with admittance causality). */
#ifndef POPC_ADMITTANCE_PLANT_H
#define POPC_ADMITTANCE_PLANT_H

#include "popc/core/plant.h"
#include "popc/util/error.h"

typedef enum popc_servo_kind { POPC_SERVO_POSITION, POPC_SERVO_VELOCITY } popc_servo_kind;

/* Names in scenes ("position", "velocity"), index = value, NULL-terminated. */
extern const char *const popc_servo_kind_names[];

typedef struct popc_admittance_plant_config {
	double hand_mass_kg, hand_damping_Nspm, hand_stiffness_Npm;
	double dev_mass_kg, dev_damping_Nspm, dev_stiffness_Npm;
	popc_servo_kind servo;
	double servo_stiffness_Npm, servo_damping_Nspm; /* K_p (position servo only), K_v */
	double omega_radps;       /* the sine intent's w (0: none) */
	popc_integrator method;
	int substeps;
	double period_s;
	double x_origin_m;        /* the state is y = x - x_origin (sim_axis.c's reason) */
} popc_admittance_plant_config;

typedef struct popc_admittance_plant {
	popc_admittance_plant_config cfg;
	popc_plant plant;         /* the lumped body with the servo folded in */
	double k_total_Npm;       /* K_HO + K_HI + K_p */
} popc_admittance_plant;

/* Builds the lumped plant (popc_plant_init's checks and messages). */
int popc_admittance_plant_init(popc_admittance_plant *p, const popc_admittance_plant_config *cfg,
			       popc_error *err);

/* The plant input over a segment that starts tau0_s into the period: the
 * hand's input (intent.h, without any command) plus the servo's command,
 * in the state's coordinate y. */
void popc_admittance_plant_input(const popc_admittance_plant *p, const popc_plant_input *hand,
				 double x_cmd_m, double v_cmd_mps, double tau0_s,
				 popc_plant_input *u);

/* The sensed force f_s at tau into a segment with inputs hand and u
 * (popc_admittance_plant_input's), the state st at that instant. */
double popc_admittance_plant_sensed_N(const popc_admittance_plant *p, const popc_plant_state *st,
				      const popc_plant_input *hand, const popc_plant_input *u,
				      double tau_s);

#endif
