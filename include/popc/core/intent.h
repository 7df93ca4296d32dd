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

#include "popc/util/error.h"
#include "popc/core/plant.h"

typedef enum popc_intent_kind {
	POPC_INTENT_RAMP,  /* hold x0 until t0, move at speed until x_end, hold */
	POPC_INTENT_FORCE, /* exogenous force: 0 until t0, rise at force_rate to force, hold */
	POPC_INTENT_TABLE, /* piecewise-linear x_d(t) or f(t) given as points */
	POPC_INTENT_SINE,  /* x_d = x0 + amplitude sin(2 pi frequency (t - t0)) for t >= t0 */
} popc_intent_kind;

typedef enum popc_table_quantity { POPC_TABLE_POSITION, POPC_TABLE_FORCE } popc_table_quantity;

/* Names in scenes, index = value, NULL-terminated. */
extern const char *const popc_intent_kind_names[];
extern const char *const popc_table_quantity_names[];

/* What the operator wants, in SI units. A table's points are copied by
 * popc_intent_init; reading them from a file is the scene layer's job
 * (popc_intent_table_load in popc/scene/from_scene.h). */
typedef struct popc_intent_config {
	popc_intent_kind kind;
	double k_op_Npm, b_op_Nspm;                 /* K_HO, B_HO */
	double x0_m, t0_s;                          /* rest position, start time */
	double speed_mps, x_end_m;                  /* ramp */
	double force_N, force_rate_Nps;             /* force */
	double amplitude_m, frequency_Hz;           /* sine */
	popc_table_quantity table_quantity;         /* table: q is x_d (m) or f_op (N) */
	size_t table_n;                             /* table: points (>= 1) */
	const double *table_t_s, *table_q;          /* table: times strictly increasing */
} popc_intent_config;

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

/* Builds the intent from its configuration (a table's points are copied).
 * Returns 0, POPC_ERR_NOMEM, or POPC_ERR_INVALID for an unknown kind or an
 * empty table. Free with popc_intent_free. */
int popc_intent_init(popc_intent *in, const popc_intent_config *cfg, popc_error *err);
void popc_intent_free(popc_intent *in);

/* The operator's input over [t, t + h) as plant input coefficients (without
 * the command f_c, which the caller subtracts from u0), and the first
 * breakpoint strictly inside (t, t + h), or a value >= t + h if none. */
void popc_intent_input(popc_intent *in, double t, popc_plant_input *u, double *next_break);

/* The operator's input on one segment of a piecewise-linear intent, so that
 * the simulated axis can skip popc_intent_input between breakpoints (the hot
 * path of a long run). For every t in [t_lo_s, t_next_s) popc_intent_input
 * gives, bitwise, u0 = k_q * (q_i + slope (t - t_i)) + b_slope (position) or
 * u0 = k_x0 + (q_i + slope (t - t_i)) (force), u1 = u1_Nps, us = uc = 0, and
 * next_break = t_next_s. affine = 0 (a sine) means: call popc_intent_input. */
typedef struct popc_intent_segment {
	int affine;
	int is_force;
	int constant;                /* before the first or after the last point: q = q_i */
	double t_lo_s, t_next_s;
	double t_i, q_i, slope;
	double k_q, b_slope, k_x0, u1_Nps;
} popc_intent_segment;

/* The segment holding t (see popc_intent_segment). */
void popc_intent_segment_at(popc_intent *in, double t, popc_intent_segment *g);

/* u over [t, t + h) from a segment holding t: the same operations, in the same
 * order, as popc_intent_input (bitwise equal). */
static inline void popc_intent_segment_input(const popc_intent_segment *g, double t,
					     popc_plant_input *u)
{
	double q = g->constant ? g->q_i : g->q_i + g->slope * (t - g->t_i);
	u->u0_N = g->is_force ? g->k_x0 + q : g->k_q * q + g->b_slope;
	u->u1_Nps = g->u1_Nps;
	u->us_N = u->uc_N = 0.0;
}

/* A profile breakpoint closer than this many control periods to a tick is
 * taken as on the tick (the simulated axis' rule). */
#define POPC_INTENT_TICK_TOL_PERIODS 1e-9

/* u over the whole period [t, t_end) from the cached segment *g, looked up
 * again when t has left it, when no breakpoint falls inside the period (one
 * within tol_s of t_end counts as on the tick): then popc_intent_input would
 * give exactly this input with no split. Returns 0 when the period needs
 * popc_intent_input's split path (or the intent is a sine). Inline: the
 * simulated axis calls it every tick. */
static inline int popc_intent_period_input(popc_intent *in, popc_intent_segment *g, double t,
					   double t_end, double tol_s, popc_plant_input *u)
{
	if (!(t >= g->t_lo_s && t < g->t_next_s && g->t_next_s >= t_end - tol_s)) {
		popc_intent_segment_at(in, t, g);
		if (!g->affine || !(g->t_next_s >= t_end - tol_s))
			return 0;
	}
	popc_intent_segment_input(g, t, u);
	return 1;
}

/* Desired position x_d(t) (m) and the exogenous force f_op(t) (N), for logs and tests. */
double popc_intent_xd(popc_intent *in, double t);

/* Initial position of the device: x_d(0) (or x0 for a force intent). */
double popc_intent_x_initial(const popc_intent *in);

#endif
