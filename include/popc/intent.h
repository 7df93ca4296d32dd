/* The operator's intent as a function of time, turned into the plant's
 * generalized input force u(t) = K_HO x_d(t) + B_HO x_d'(t) + f_op(t).
 *
 * Piecewise-linear intents (ramp, force, table) are affine between
 * breakpoints; the runner splits a control period at a breakpoint so that the
 * exact discretization stays exact. The sine intent is exact through the
 * plant's sine input columns. */
#ifndef POPC_INTENT_H
#define POPC_INTENT_H

#include <stddef.h>

#include "popc/error.h"
#include "popc/plant.h"
#include "popc/scene.h"

typedef struct popc_intent {
	popc_intent_kind kind;
	double k_op, b_op;           /* K_HO, B_HO */
	double x0, t0;
	/* breakpoints of the piecewise-linear quantity q(t) (x_d or f_op) */
	size_t n;                    /* number of points (>= 1) */
	double *t, *q;               /* owned */
	int q_is_force;
	double amplitude, omega;     /* sine */
	size_t cursor;               /* segment hint: intents are evaluated at increasing t */
} popc_intent;

int popc_intent_init(popc_intent *in, const popc_scene *s, popc_error *err);
void popc_intent_free(popc_intent *in);

/* The operator's input over [t, t + h) as plant input coefficients (without
 * the command f_c, which the caller subtracts from u0), and the first
 * breakpoint strictly inside (t, t + h), or a value >= t + h if none. */
void popc_intent_input(popc_intent *in, double t, popc_plant_input *u, double *next_break);

/* Desired position x_d(t) (m) and the exogenous force f_op(t) (N), for logs and tests. */
double popc_intent_xd(popc_intent *in, double t);

/* Initial position of the device: x_d(0) (or x0 for a force intent). */
double popc_intent_x_initial(const popc_intent *in);

#endif
