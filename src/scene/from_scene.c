/* Scene to core configurations (from_scene.h), and the table intent's file. */
#include "popc/scene/from_scene.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "popc/scene/delay_trace.h"
#include "popc/util/parse.h"
#include "popc/util/text.h"

#define POPC_TWO_PI 6.283185307179586476925286766559

void popc_plant_config_from_scene(popc_plant_config *cfg, const popc_scene *s)
{
	memset(cfg, 0, sizeof *cfg);
	/* One rigid body (README, "The plant"): the hand holds the device. */
	cfg->mass_kg = s->op_mass_kg + s->dev_mass_kg;
	cfg->damping_Nspm = s->op_damping_Nspm + s->dev_damping_Nspm;
	cfg->stiffness_Npm = s->op_stiffness_Npm + s->dev_stiffness_Npm;
	cfg->omega_radps = s->intent == POPC_INTENT_SINE ? POPC_TWO_PI * s->op_frequency_Hz : 0.0;
	cfg->method = s->integrator;
	cfg->substeps = s->substeps;
	cfg->period_s = popc_scene_period_s(s);
	cfg->coulomb_N = s->dev_coulomb_N;
	cfg->stiction_N = s->dev_stiction_N;
}

void popc_environment_from_scene(popc_environment *e, const popc_scene *s)
{
	e->kind = s->env_kind;
	e->stiffness_Npm = s->env_stiffness_Npm;
	e->damping_Nspm = s->env_damping_Nspm;
	e->position_m = s->env_position_m;
}

void popc_controller_config_from_scene(popc_controller_config *c, const popc_scene *s)
{
	memset(c, 0, sizeof *c);
	c->variant = s->variant;
	c->pc_bound_N = s->pc_bound_N;
	c->ignore_mode = s->ignore_mode;
	c->resolution_m = s->enc_resolution_m;
	c->period_s = popc_scene_period_s(s);
	c->foaw_window = s->foaw_window;
	c->foaw_noise_m = s->foaw_noise_m > 0 ? s->foaw_noise_m : s->enc_resolution_m;
	c->reversal_count = s->reversal_count;
	c->reversal_window_ticks = s->reversal_window;
	/* energy-bounding: the damping of the one rigid body the plant is */
	c->damping_Nspm = s->op_damping_Nspm + s->dev_damping_Nspm;
	c->eb_margin = s->eb_margin;
	c->po_window_ticks = s->po_window;
	c->po_velocity_floor_mps = s->po_velocity_floor_mps;
	c->po_damping_max_Nspm = s->po_damping_max_Nspm;
	popc_environment_from_scene(&c->env, s);
}

void popc_admittance_config_from_scene(popc_admittance_config *c, const popc_scene *s)
{
	memset(c, 0, sizeof *c);
	c->variant = s->adm_variant;
	c->period_s = popc_scene_period_s(s);
	c->force_resolution_N = s->adm_force_resolution_N;
	c->virtual_mass_kg = s->adm_virtual_mass_kg;
	c->virtual_damping_Nspm = s->adm_virtual_damping_Nspm;
	c->pc_velocity_bound_mps = s->adm_pc_velocity_bound_mps;
	popc_environment_from_scene(&c->env, s);
}

void popc_admittance_plant_config_from_scene(popc_admittance_plant_config *c, const popc_scene *s,
					     double x_origin_m)
{
	memset(c, 0, sizeof *c);
	c->hand_mass_kg = s->op_mass_kg;
	c->hand_damping_Nspm = s->op_damping_Nspm;
	c->hand_stiffness_Npm = s->op_stiffness_Npm;
	c->dev_mass_kg = s->dev_mass_kg;
	c->dev_damping_Nspm = s->dev_damping_Nspm;
	c->dev_stiffness_Npm = s->dev_stiffness_Npm;
	c->servo = s->adm_servo;
	c->servo_stiffness_Npm = s->adm_servo_stiffness_Npm;
	c->servo_damping_Nspm = s->adm_servo_damping_Nspm;
	c->omega_radps = s->intent == POPC_INTENT_SINE ? POPC_TWO_PI * s->op_frequency_Hz : 0.0;
	c->method = s->integrator;
	c->substeps = s->substeps;
	c->period_s = popc_scene_period_s(s);
	c->x_origin_m = x_origin_m;
}

void popc_teleop_slave_plant_config_from_scene(popc_admittance_plant_config *c,
					       const popc_scene *s, double x_origin_m)
{
	memset(c, 0, sizeof *c);
	c->dev_mass_kg = s->slave_mass_kg;
	c->dev_damping_Nspm = s->slave_damping_Nspm;
	c->servo = s->slave_servo;
	c->servo_stiffness_Npm = s->slave_servo_stiffness_Npm;
	c->servo_damping_Nspm = s->slave_servo_damping_Nspm;
	c->method = s->integrator;
	c->substeps = s->substeps;
	const int n = popc_scene_slave_substeps(s);
	c->period_s = popc_scene_period_s(s) / (double)(n > 0 ? n : 1); /* T / 1 is T, bit for bit */
	c->x_origin_m = x_origin_m;
}

void popc_channel_config_from_scene(popc_channel_config *c, const popc_scene_channel *dir)
{
	memset(c, 0, sizeof *c);
	c->delay_ticks = dir->delay_ticks;
	c->jitter_ticks = dir->jitter_ticks;
	c->loss = dir->loss;
	c->in_order = dir->in_order;
	c->seed = (uint64_t)dir->seed;
	c->jitter_walk = dir->jitter_model; /* delay_trace.h converts delay_s and reads trace */
}

/* delay_trace.h does the seconds and reads the trace */
int popc_channel_config_load(popc_channel_config *c, const popc_scene *s,
			     const popc_scene_channel *dir, const char *name, popc_delay_trace *trace,
			     popc_error *err)
{
	memset(trace, 0, sizeof *trace);
	popc_channel_config_from_scene(c, dir);
	int st = popc_scene_channel_ticks(s, dir, name, &c->delay_ticks, &c->jitter_ticks, err);
	if (st || !dir->trace[0])
		return st;
	if ((st = popc_delay_trace_load(dir->trace, s->rate_Hz, trace, err)) != 0)
		return st;
	c->trace_ticks = trace->ticks;
	c->n_trace = trace->n;
	return 0;
}

/* The keys behind each popc_plant_config field, as the two adapters above sum
 * them (a sum in parentheses: the message divides by it). */
static const popc_error_name impedance_plant_keys[] = {
	{"mass_kg", "(operator.mass + device.mass)"},
	{"damping_Nspm", "(operator.damping + device.damping)"},
	{"stiffness_Npm", "(operator.stiffness + device.stiffness)"},
	{"period_s", "1 / run.rate"},
	{"coulomb_N", "device.coulomb"},
	{"stiction_N", "device.stiction"},
};
static const popc_error_name admittance_position_plant_keys[] = {
	{"mass_kg", "(operator.mass + device.mass)"},
	{"damping_Nspm", "(operator.damping + device.damping + admittance.servo_damping)"},
	{"stiffness_Npm", "(operator.stiffness + device.stiffness + admittance.servo_stiffness)"},
	{"period_s", "1 / run.rate"},
};
static const popc_error_name admittance_velocity_plant_keys[] = {
	{"mass_kg", "(operator.mass + device.mass)"},
	{"damping_Nspm", "(operator.damping + device.damping + admittance.servo_damping)"},
	{"stiffness_Npm", "(operator.stiffness + device.stiffness)"},
	{"period_s", "1 / run.rate"},
};

void popc_plant_name_keys(const popc_scene *s, popc_error *err)
{
#define NAME_WITH(t) popc_error_name_params(err, t, sizeof t / sizeof t[0])
	if (s->causality != POPC_CAUSALITY_ADMITTANCE)
		NAME_WITH(impedance_plant_keys);
	else if (s->adm_servo == POPC_SERVO_POSITION)
		NAME_WITH(admittance_position_plant_keys);
	else
		NAME_WITH(admittance_velocity_plant_keys);
#undef NAME_WITH
}

static const char *skip_blanks(const char *p)
{
	while (*p == ' ' || *p == '\t')
		p++;
	return p;
}

/* A table intent's file (popc_intent_table_load, from_scene.h). Reads "t,value" rows: columns separated by ',', ';' or a tab (blanks around
 * them allowed), '#' comments and blank lines skipped, one header line allowed
 * before the first row, CRLF or LF. Numbers as everywhere (popc/util/parse.h:
 * decimal, C locale, finite); times increase strictly; values within the
 * range of the scene key they stand for. Call with is_force set. Lines have any length
 * (getline), so every message names the real line. */
int popc_intent_table_load(const char *path, popc_table_quantity quantity, double k_op_Npm,
			   double b_op_Nspm, popc_intent_points *out, popc_error *err)
{
	const int is_force = quantity == POPC_TABLE_FORCE;
	out->n = 0;
	out->t_s = out->q = NULL;
	/* the value column has the range of the scene key it stands for
	 * (src/scene/scene.c): a position as operator.x0, a force as operator.force */
	const double q_max = is_force ? 1e6 : 1e3;
	const char *q_unit = is_force ? "N" : "m";
	const char *q_key = is_force ? "operator.force" : "operator.x0";
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
		if (popc_parse_double(p, end, &tv) == 0) { /* no number starts here: text */
			if (n == 0 && !header_seen) {
				header_seen = 1; /* the header: the first line that is not a row */
				continue;
			}
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: column 1: expected a time in seconds", path, lineno);
			break;
		}
		/* column 1 ends at a blank or a delimiter: a number as everywhere
		 * (popc/util/parse.h) */
		const char *d = p + strcspn(p, " \t,;");
		if (popc_parse_double_span(p, d, &tv) != 0) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: column 1: expected a finite number", path, lineno);
			break;
		}
		/* the delimiter: ',' or ';' (blanks around it), or blanks holding a tab */
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
		popc_trim_blanks(&p, &end);
		if (popc_parse_double_span(p, end, &qv) != 0) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: column 2: expected a finite number", path, lineno);
			break;
		}
		if (!(fabs(qv) <= q_max)) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: column 2: %g %s is out of range; allowed [%g, %g] "
						"%s (as %s; operator.table_quantity = %s)",
						path, lineno, qv, q_unit, -q_max, q_max, q_unit, q_key,
						is_force ? "force" : "position");
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
			double u1 = is_force ? slope : k_op_Npm * slope;
			double u0 = is_force ? qv : k_op_Npm * qv + b_op_Nspm * slope;
			double u0_prev = is_force ? q[n - 1] : k_op_Npm * q[n - 1] + b_op_Nspm * slope;
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
	if (status) {
		free(t);
		free(q);
		return status;
	}
	out->n = n;
	out->t_s = t;
	out->q = q;
	return 0;
}

void popc_intent_points_free(popc_intent_points *p)
{
	free(p->t_s);
	free(p->q);
	p->t_s = p->q = NULL;
	p->n = 0;
}

double popc_scene_reach_m(const popc_scene *s, const popc_intent *in, char *why, size_t cap)
{
	char none[1];
	if (!why) {
		why = none;
		cap = sizeof none;
	}
	double x = fmax(fabs(s->op_x0_m), fabs(s->env_position_m));
	snprintf(why, cap, "the largest of |operator.x0|, |environment.position|");
	if (s->intent == POPC_INTENT_RAMP) {
		x = fmax(x, fabs(s->op_x_end_m));
		snprintf(why, cap, "the largest of |operator.x0|, |operator.x_end|, |environment.position|");
	} else if (s->intent == POPC_INTENT_SINE) {
		x = fmax(x, fabs(s->op_x0_m) + s->op_amplitude_m);
		snprintf(why, cap, "the largest of |operator.x0| + operator.amplitude, "
				   "|environment.position|");
	}
	if (in->q_is_force) {
		/* the hand rests at x0 and pushes with f(t): the static equilibrium
		 * (K_HO x0 + f) / K on the plant's spring, or on a bilateral spring */
		double f = 0.0;
		for (size_t i = 0; i < in->n; i++)
			f = fmax(f, fabs(in->q[i]));
		const char *force = s->intent == POPC_INTENT_TABLE ? "the table's largest |force|"
								   : "|operator.force|";
		double pull = fabs(s->op_stiffness_Npm * s->op_x0_m) + f;
		double k = s->op_stiffness_Npm + s->dev_stiffness_Npm;
		if (k > 0.0) {
			x = fmax(x, pull / k);
			snprintf(why, cap, "(operator.stiffness |operator.x0| + %s) / (operator.stiffness "
					   "+ device.stiffness) = %g m, or a position key",
				 force, pull / k);
		} else if (s->env_kind == POPC_ENV_SPRING && s->env_stiffness_Npm > 0.0) {
			x = fmax(x, fabs(s->env_position_m) + pull / s->env_stiffness_Npm);
			snprintf(why, cap, "|environment.position| + %s / environment.stiffness = %g m",
				 force, fabs(s->env_position_m) + pull / s->env_stiffness_Npm);
		} else {
			snprintf(why, cap, "a force with no spring to hold it: no bound");
			return (double)INFINITY;
		}
	} else if (s->intent == POPC_INTENT_TABLE) {
		double q = 0.0;
		for (size_t i = 0; i < in->n; i++)
			q = fmax(q, fabs(in->q[i]));
		x = fmax(x, q);
		snprintf(why, cap, "the largest of the table's |x_d| (%g m), |operator.x0|, "
				   "|environment.position|",
			 q);
	}
	return 10.0 * x + 1.0;
}

int popc_intent_from_scene(popc_intent *in, const popc_scene *s, popc_error *err)
{
	popc_intent_config cfg = {
		.kind = s->intent,
		.k_op_Npm = s->op_stiffness_Npm,
		.b_op_Nspm = s->op_damping_Nspm,
		.x0_m = s->op_x0_m,
		.t0_s = s->op_t0_s,
		.speed_mps = s->op_speed_mps,
		.x_end_m = s->op_x_end_m,
		.force_N = s->op_force_N,
		.force_rate_Nps = s->op_force_rate_Nps,
		.amplitude_m = s->op_amplitude_m,
		.frequency_Hz = s->op_frequency_Hz,
		.table_quantity = s->op_table_quantity,
	};
	popc_intent_points points = {0};
	if (s->intent == POPC_INTENT_TABLE) {
		memset(in, 0, sizeof *in);
		int status = popc_intent_table_load(s->op_table, s->op_table_quantity,
						    s->op_stiffness_Npm, s->op_damping_Nspm, &points, err);
		if (status)
			return status;
		cfg.table_n = points.n;
		cfg.table_t_s = points.t_s;
		cfg.table_q = points.q;
	}
	int status = popc_intent_init(in, &cfg, err);
	popc_intent_points_free(&points);
	if (status)
		return status;
	/* the run's positions, up to where the simulated axis stops it as
	 * diverged, must be counts below 2^53; a force without a spring has no
	 * bound to check here (the run stops when its count would overflow) */
	char why[300];
	const double reach_m = popc_scene_reach_m(s, in, why, sizeof why);
	const double counts_max = 9007199254740992.0; /* 2^53 */
	if (isfinite(reach_m) && !(reach_m / s->enc_resolution_m <= counts_max)) {
		popc_intent_free(in);
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: encoder.resolution = %g m is too fine for this %s intent: "
				      "positions up to %g m (10 x %s, + 1 m) would exceed 2^53 counts; "
				      "use encoder.resolution >= %.3g m",
				      s->source[0] ? s->source : "scene", s->enc_resolution_m,
				      popc_intent_kind_names[s->intent], reach_m, why,
				      reach_m / counts_max * 1.001);
	}
	return 0;
}
