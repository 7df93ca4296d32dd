/* Virtual environments (impedance causality: position in, force out).
 * f_e > 0 pushes the device back towards negative x (the device receives -f_c). */
#ifndef POPC_ENVIRONMENT_H
#define POPC_ENVIRONMENT_H

#include "popc/scene.h"

typedef struct popc_environment {
	popc_environment_kind kind;
	double stiffness_Npm, damping_Nspm, position_m;
} popc_environment;

void popc_environment_from_scene(popc_environment *e, const popc_scene *s);

/* Wall: f_e = max(0, K_e (x - p) + B_e v) for x >= p, else 0 (unilateral, never pulls).
 * Spring: f_e = K_e (x - p) + B_e v. */
double popc_environment_force(const popc_environment *e, double x_m, double v_mps);

/* Whether x is in contact (wall: x >= p; spring: always). */
int popc_environment_in_contact(const popc_environment *e, double x_m);

#endif
