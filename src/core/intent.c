/* The operator's intent (intent.h). */
#include "popc/core/intent.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>


#define POPC_TWO_PI 6.283185307179586476925286766559

static int set_points(popc_intent *in, size_t n, const double *t, const double *q)
{
	in->t = malloc(n * sizeof *in->t);
	in->q = malloc(n * sizeof *in->q);
	if (!in->t || !in->q)
		return POPC_ERR_NOMEM;
	memcpy(in->t, t, n * sizeof *t);
	memcpy(in->q, q, n * sizeof *q);
	in->n = n;
	return 0;
}

const char *const popc_intent_kind_names[] = {"ramp", "force", "table", "sine", NULL};
const char *const popc_table_quantity_names[] = {"position", "force", NULL};

int popc_intent_init(popc_intent *in, const popc_intent_config *cfg, popc_error *err)
{
	memset(in, 0, sizeof *in);
	in->kind = cfg->kind;
	in->k_op = cfg->k_op_Npm;
	in->b_op = cfg->b_op_Nspm;
	in->x0 = cfg->x0_m;
	in->t0 = cfg->t0_s;
	int status = POPC_ERR_INVALID;
	switch (cfg->kind) {
	case POPC_INTENT_RAMP: {
		double t_end = cfg->t0_s + fabs(cfg->x_end_m - cfg->x0_m) / cfg->speed_mps;
		double t[3] = {0.0, cfg->t0_s, t_end}, q[3] = {cfg->x0_m, cfg->x0_m, cfg->x_end_m};
		status = set_points(in, 3, t, q);
		break;
	}
	case POPC_INTENT_FORCE: {
		in->q_is_force = 1;
		double t_end = cfg->t0_s + fabs(cfg->force_N) / cfg->force_rate_Nps;
		double t[3] = {0.0, cfg->t0_s, t_end}, q[3] = {0.0, 0.0, cfg->force_N};
		status = set_points(in, 3, t, q);
		break;
	}
	case POPC_INTENT_TABLE:
		in->q_is_force = cfg->table_quantity == POPC_TABLE_FORCE;
		if (cfg->table_n == 0)
			return popc_error_set(err, POPC_ERR_INVALID, "the table has no rows");
		status = set_points(in, cfg->table_n, cfg->table_t_s, cfg->table_q);
		break;
	case POPC_INTENT_SINE: {
		in->amplitude = cfg->amplitude_m;
		in->omega = POPC_TWO_PI * cfg->frequency_Hz;
		double t[2] = {0.0, cfg->t0_s}, q[2] = {cfg->x0_m, cfg->x0_m};
		status = set_points(in, 2, t, q);
		break;
	}
	default:
		return popc_error_set(err, POPC_ERR_INVALID, "unknown operator intent");
	}
	if (status == POPC_ERR_NOMEM)
		return popc_error_set(err, POPC_ERR_NOMEM, "operator intent: out of memory");
	return status;
}

void popc_intent_free(popc_intent *in)
{
	free(in->t);
	free(in->q);
	in->t = in->q = NULL;
	in->n = 0;
}

/* Index i of the segment [t_i, t_i+1) holding t; n - 1 past the last point,
 * and -1 before the first. Intents are read at increasing times: the cursor
 * makes this O(1) amortized. */
static long segment(popc_intent *in, double t)
{
	if (t < in->t[0])
		return -1;
	size_t i = in->cursor < in->n ? in->cursor : 0;
	if (in->t[i] > t)
		i = 0;
	while (i + 1 < in->n && in->t[i + 1] <= t)
		i++;
	in->cursor = i;
	return (long)i;
}

static void pl_value(popc_intent *in, double t, double *q, double *slope, double *next_break)
{
	long i = segment(in, t);
	if (i < 0) {
		*q = in->q[0];
		*slope = 0.0;
		*next_break = in->t[0];
	} else if ((size_t)i + 1 >= in->n) {
		*q = in->q[in->n - 1];
		*slope = 0.0;
		*next_break = (double)INFINITY;
	} else {
		double t0 = in->t[i], t1 = in->t[i + 1];
		*slope = (in->q[i + 1] - in->q[i]) / (t1 - t0);
		*q = in->q[i] + *slope * (t - t0);
		*next_break = t1;
	}
}

void popc_intent_input(popc_intent *in, double t, popc_plant_input *u, double *next_break)
{
	double q, slope;
	pl_value(in, t, &q, &slope, next_break);
	u->us_N = u->uc_N = 0.0;
	if (in->kind == POPC_INTENT_SINE && t >= in->t0) {
		/* x_d = x0 + A sin(phi + w tau), phi = w (t - t0):
		 * u = K x_d + B x_d' = K x0 + us sin(w tau) + uc cos(w tau) */
		double phi = in->omega * (t - in->t0), sp = sin(phi), cp = cos(phi);
		double ka = in->k_op * in->amplitude, bw = in->b_op * in->amplitude * in->omega;
		u->u0_N = in->k_op * in->x0;
		u->u1_Nps = 0.0;
		u->us_N = ka * cp - bw * sp;
		u->uc_N = ka * sp + bw * cp;
		*next_break = (double)INFINITY;
	} else if (in->q_is_force) {
		/* the hand rests at x0 and pushes with f(t) */
		u->u0_N = in->k_op * in->x0 + q;
		u->u1_Nps = slope;
	} else {
		/* first-order hold of x_d: u = K x_d(t + tau) + B x_d' */
		u->u0_N = in->k_op * q + in->b_op * slope;
		u->u1_Nps = in->k_op * slope;
	}
}

void popc_intent_segment_at(popc_intent *in, double t, popc_intent_segment *g)
{
	memset(g, 0, sizeof *g);
	if (in->kind == POPC_INTENT_SINE && t >= in->t0) {
		g->affine = 0;
		g->t_lo_s = t;
		g->t_next_s = t; /* never valid: popc_intent_input on every step */
		return;
	}
	long i = segment(in, t);
	g->affine = 1;
	g->is_force = in->q_is_force;
	if (i < 0) {
		g->constant = 1;
		g->q_i = in->q[0];
		g->t_lo_s = -(double)INFINITY;
		g->t_next_s = in->t[0];
	} else if ((size_t)i + 1 >= in->n) {
		g->constant = 1;
		g->q_i = in->q[in->n - 1];
		g->t_lo_s = in->t[i];
		g->t_next_s = (double)INFINITY;
	} else {
		/* the operations of pl_value, split into per-segment and per-step parts */
		g->t_i = in->t[i];
		g->q_i = in->q[i];
		g->slope = (in->q[i + 1] - in->q[i]) / (in->t[i + 1] - in->t[i]);
		g->t_lo_s = in->t[i];
		g->t_next_s = in->t[i + 1];
	}
	if (in->kind == POPC_INTENT_SINE) /* a sine before its start holds x0 */
		g->t_next_s = g->t_next_s < in->t0 ? g->t_next_s : in->t0;
	/* popc_intent_input: force u0 = k x0 + q, u1 = q'; position u0 = k q + b q', u1 = k q' */
	g->k_q = in->k_op;
	g->b_slope = in->b_op * g->slope;
	g->k_x0 = in->k_op * in->x0;
	g->u1_Nps = in->q_is_force ? g->slope : in->k_op * g->slope;
}

double popc_intent_xd(popc_intent *in, double t)
{
	if (in->kind == POPC_INTENT_SINE)
		return t >= in->t0 ? in->x0 + in->amplitude * sin(in->omega * (t - in->t0)) : in->x0;
	if (in->q_is_force)
		return in->x0;
	double q, slope, nb;
	pl_value(in, t, &q, &slope, &nb);
	return q;
}

double popc_intent_x_initial(const popc_intent *in)
{
	if (in->kind == POPC_INTENT_SINE || in->q_is_force)
		return in->x0;
	return in->q[0];
}
