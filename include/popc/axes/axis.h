/* An axis closes the control loop: the simulated plant, or a servo drive over
 * Modbus. A small vtable plus private state (the dav1d plug-in pattern).
 *
 * The runner calls sample() once for tick 0, then exchange() once per tick:
 * it applies the command f_c(k) for the coming period and returns the sample
 * of tick k+1. stop() brings the axis to a safe state (zero force, drive
 * disabled) and is called on every way out. */
#ifndef POPC_AXIS_H
#define POPC_AXIS_H

#include "popc/util/error.h"
#include "popc/scene/scene.h"

typedef struct popc_axis_sample {
	long long count;
	double x_true_m;      /* NaN when unknown (real axis) */
	double dt_s;          /* measured period before this sample (0 for a simulated axis) */
	double rtt_s;         /* transaction time of the exchange (0 for a simulated axis) */
} popc_axis_sample;

typedef struct popc_axis popc_axis;

typedef struct popc_axis_ops {
	const char *name;         /* "sim", "modbus": the log's source */
	unsigned log_columns;     /* enum popc_log_columns the axis fills */
	int (*start)(popc_axis *a, popc_error *err);
	int (*sample)(popc_axis *a, popc_axis_sample *out, popc_error *err);
	int (*exchange)(popc_axis *a, double f_c_N, popc_axis_sample *next, popc_error *err);
	int (*stop)(popc_axis *a, popc_error *err);
	/* Appends a human summary and CSV fields of axis statistics (may be NULL). */
	void (*report)(popc_axis *a, FILE *human, char *csv_names, char *csv_values, size_t cap);
	void (*destroy)(popc_axis *a);
} popc_axis_ops;

struct popc_axis {
	const popc_axis_ops *ops;
	void *priv;
	double force_limit_N; /* the largest |f_c| the axis sends (0: none); the
				 runner clamps and flags the command to it */
};

/* The simulated axis: plant, operator intent and encoder of the scene. */
int popc_sim_axis_create(popc_axis **out, const popc_scene *s, popc_error *err);

/* Integrator error against the exact discretization, measured by the sim axis
 * alongside the run (0 for the exact method). */
double popc_sim_axis_max_error(const popc_axis *a);

/* Turns the exact shadow of a simulated axis with a fixed-step integrator off
 * (on = 0) or back on, so that a benchmark times the integrator alone; with
 * the shadow off popc_sim_axis_max_error reports NaN and only the growth bound
 * and the divergence check guard the run. No effect on an exact or non-sim axis. */
void popc_sim_axis_set_shadow(popc_axis *a, int on);

void popc_axis_destroy(popc_axis **a);

#endif
