/* The operator's intent (intent.h). */
#include "popc/intent.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "popc/numfmt.h"

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

static const char *skip_blanks(const char *p)
{
	while (*p == ' ' || *p == '\t')
		p++;
	return p;
}

/* Reads "t,value" rows: columns separated by ',', ';' or a tab (blanks around
 * them allowed), '#' comments and blank lines skipped, one header line allowed
 * before the first row, CRLF or LF. Numbers are decimal, C locale
 * (popc_parse_double), finite; times increase strictly; values within the
 * range of the scene key they stand for. Call with in->q_is_force set. Lines have any length
 * (getline), so every message names the real line. */
static int load_table(popc_intent *in, const char *path, popc_error *err)
{
	/* the value column has the range of the scene key it stands for
	 * (src/scene.c): a position as operator.x0, a force as operator.force */
	const double q_max = in->q_is_force ? 1e6 : 1e3;
	const char *q_unit = in->q_is_force ? "N" : "m";
	const char *q_key = in->q_is_force ? "operator.force" : "operator.x0";
	FILE *f = fopen(path, "r");
	if (!f) /* a missing table is bad input, as a missing scene is (exit 2) */
		return popc_error_set(err, POPC_ERR_INVALID, "%s: cannot open table: %s", path,
				      strerror(errno));
	size_t cap = 64, n = 0;
	double *t = malloc(cap * sizeof *t), *q = malloc(cap * sizeof *q);
	char *line = NULL;
	size_t line_cap = 0;
	ssize_t len;
	int lineno = 0, status = 0, header_seen = 0, oom = 0;
	while (t && q && (len = getline(&line, &line_cap, f)) >= 0) {
		lineno++;
		while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r'))
			line[--len] = '\0';
		if (memchr(line, '\0', (size_t)len)) { /* the text after it would be dropped */
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: a NUL byte in the line (a table is a text file)",
						path, lineno);
			break;
		}
		const char *p = line, *end = line + len;
		if (lineno == 1 && strncmp(p, "\xEF\xBB\xBF", 3) == 0)
			p += 3; /* a UTF-8 byte order mark */
		p = skip_blanks(p);
		if (*p == '#' || *p == '\0')
			continue;
		double tv, qv;
		size_t used = popc_parse_double(p, end, &tv);
		if (used == 0) {
			if (n == 0 && !header_seen) {
				header_seen = 1; /* the header: the first line that is not a row */
				continue;
			}
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: column 1: expected a time in seconds", path, lineno);
			break;
		}
		/* the delimiter: ',' or ';' (blanks around it), or blanks holding a tab */
		const char *d = p + used;
		int tab = 0;
		while (*d == ' ' || *d == '\t')
			tab |= *d++ == '\t';
		if (*d == ',' || *d == ';')
			d++;
		else if (!tab || *d == '\0') {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: expected two columns t,value (separated by ',', ';' "
						"or a tab)", path, lineno);
			break;
		}
		p = skip_blanks(d);
		used = popc_parse_double(p, end, &qv);
		if (used == 0 || *skip_blanks(p + used) != '\0' || !isfinite(tv) || !isfinite(qv)) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: %s: expected a finite number", path, lineno,
						isfinite(tv) ? "column 2" : "column 1");
			break;
		}
		if (!(fabs(qv) <= q_max)) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: column 2: %g %s is out of range; allowed [%g, %g] "
						"%s (as %s; operator.table_quantity = %s)",
						path, lineno, qv, q_unit, -q_max, q_max, q_unit, q_key,
						in->q_is_force ? "force" : "position");
			break;
		}
		if (n > 0 && !(tv > t[n - 1])) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: time %g does not increase (previous %g)", path,
						lineno, tv, t[n - 1]);
			break;
		}
		if (n > 0) {
			/* the operator's input between rows uses the slope (pl_value):
			 * rows too close in time for their change in value (1 m in
			 * 1e-310 s) make it infinite, and u = K_HO x_d + B_HO x_d' NaN */
			double slope = (qv - q[n - 1]) / (tv - t[n - 1]);
			double u1 = in->q_is_force ? slope : in->k_op * slope;
			double u0 = in->q_is_force ? qv : in->k_op * qv + in->b_op * slope;
			double u0_prev = in->q_is_force ? q[n - 1] : in->k_op * q[n - 1] + in->b_op * slope;
			if (!isfinite(slope) || !isfinite(u1) || !isfinite(u0) || !isfinite(u0_prev)) {
				status = popc_error_set(
					err, POPC_ERR_INVALID,
					"%s:%d: %g %s at time %g s after %g %s at %g s: the rows are too "
					"close in time for the change (the operator's input would not be a "
					"finite number)",
					path, lineno, qv, q_unit, tv, q[n - 1], q_unit, t[n - 1]);
				break;
			}
		}
		if (n == cap) {
			cap *= 2;
			double *nt = realloc(t, cap * sizeof *t), *nq = realloc(q, cap * sizeof *q);
			if (nt)
				t = nt;
			if (nq)
				q = nq;
			if (!nt || !nq) {
				oom = 1;
				break;
			}
		}
		t[n] = tv;
		q[n] = qv;
		n++;
	}
	/* getline ends at the end of the file and on a read error (a directory:
	 * EISDIR), which must not read as an empty table; a table that cannot
	 * be read is bad input (exit 2), like one that cannot be opened */
	int read_failed = ferror(f), read_errno = errno;
	free(line);
	fclose(f);
	if (!status && read_failed)
		status = popc_error_set(err, POPC_ERR_INVALID, "%s: cannot read table: %s", path,
					strerror(read_errno));
	if (!status && (!t || !q || oom))
		status = popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	if (!status && n == 0)
		status = popc_error_set(err, POPC_ERR_INVALID, "%s: the table has no rows", path);
	if (!status)
		status = set_points(in, n, t, q);
	free(t);
	free(q);
	return status;
}

int popc_intent_init(popc_intent *in, const popc_scene *s, popc_error *err)
{
	memset(in, 0, sizeof *in);
	in->kind = s->intent;
	in->k_op = s->op_stiffness_Npm;
	in->b_op = s->op_damping_Nspm;
	in->x0 = s->op_x0_m;
	in->t0 = s->op_t0_s;
	switch (s->intent) {
	case POPC_INTENT_RAMP: {
		double t_end = s->op_t0_s + fabs(s->op_x_end_m - s->op_x0_m) / s->op_speed_mps;
		double t[3] = {0.0, s->op_t0_s, t_end}, q[3] = {s->op_x0_m, s->op_x0_m, s->op_x_end_m};
		return set_points(in, 3, t, q);
	}
	case POPC_INTENT_FORCE: {
		in->q_is_force = 1;
		double t_end = s->op_t0_s + fabs(s->op_force_N) / s->op_force_rate_Nps;
		double t[3] = {0.0, s->op_t0_s, t_end}, q[3] = {0.0, 0.0, s->op_force_N};
		return set_points(in, 3, t, q);
	}
	case POPC_INTENT_TABLE:
		in->q_is_force = s->op_table_quantity == POPC_TABLE_FORCE;
		return load_table(in, s->op_table, err);
	case POPC_INTENT_SINE: {
		in->amplitude = s->op_amplitude_m;
		in->omega = POPC_TWO_PI * s->op_frequency_Hz;
		double t[2] = {0.0, s->op_t0_s}, q[2] = {s->op_x0_m, s->op_x0_m};
		return set_points(in, 2, t, q);
	}
	}
	return popc_error_set(err, POPC_ERR_INVALID, "unknown operator intent");
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
		*next_break = INFINITY;
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
		*next_break = INFINITY;
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
		g->t_lo_s = -INFINITY;
		g->t_next_s = in->t[0];
	} else if ((size_t)i + 1 >= in->n) {
		g->constant = 1;
		g->q_i = in->q[in->n - 1];
		g->t_lo_s = in->t[i];
		g->t_next_s = INFINITY;
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
