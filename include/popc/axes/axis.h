/* An axis closes the control loop: the simulated plant, or a servo drive over
 * Modbus. A small vtable plus private state (the dav1d plug-in pattern), made
 * by one factory from the scene's axis.kind, so that no program or runner
 * needs to know which kinds exist.
 *
 * The runner calls sample() once for tick 0, then exchange() once per tick:
 * it applies the command f_c(k) for the coming period and returns the sample
 * of tick k+1. An admittance-type axis (device.causality = admittance) takes
 * the velocity command v_c(k), m/s, in the same place. stop() brings the axis to a safe state (zero force, drive
 * disabled) and is called on every way out. */
#ifndef POPC_AXIS_H
#define POPC_AXIS_H

#include <signal.h>
#include <stdio.h>

#include "popc/util/error.h"
#include "popc/scene/scene.h"

typedef struct popc_axis_sample {
	long long count;
	double x_true_m;      /* NaN when unknown (real axis) */
	/* energy the plant's damping dissipated over the period before this
	 * sample, J (plant_dissipation.h; 0 at tick 0). NaN when the axis cannot
	 * say (a real axis, a fixed-step integrator, friction): the runner sets
	 * NaN before every call, so an axis without it leaves it alone. */
	double dissipated_J;
	double dt_s;          /* measured period before this sample (0 for a simulated axis) */
	double rtt_s;         /* transaction time of the exchange (0 for a simulated axis) */
	/* an admittance-type axis (POPC_LOG_COL_ADMITTANCE in its log_columns):
	 * the force sensor's count, and the position command the servo tracks
	 * from this tick on (docs/ADMITTANCE.md) */
	long long force_count;
	double x_cmd_m;
} popc_axis_sample;

typedef struct popc_axis popc_axis;

typedef struct popc_axis_ops {
	const char *name;         /* "sim", "modbus": the log's source */
	unsigned log_columns;     /* enum popc_log_columns the axis fills */
	int (*start)(popc_axis *a, popc_error *err);
	int (*sample)(popc_axis *a, popc_axis_sample *out, popc_error *err);
	int (*exchange)(popc_axis *a, double f_c_N, popc_axis_sample *next, popc_error *err);
	int (*stop)(popc_axis *a, popc_error *err);
	void (*destroy)(popc_axis *a);

	/* Optional operations: NULL where the axis has nothing to say, and the
	 * caller then does without (the runner reports an integrator error of 0). */

	/* The largest |x - x_exact| at the samples so far, m, of an axis that
	 * integrates a model and checks it against the exact discretization
	 * (the simulated plant); 0 for the exact method, NaN with the check off
	 * (set_shadow). */
	double (*integrator_error_m)(const popc_axis *a);
	/* Appends a human summary (to human, unless NULL) and CSV fields
	 * (",name..." and ",value...", each buffer cap bytes) of the axis'
	 * statistics: period and latency percentiles of a real axis. */
	void (*report)(popc_axis *a, FILE *human, char *csv_names, char *csv_values, size_t cap);
	/* Turns that exact check off (on = 0) or back on, so that a benchmark
	 * times the model alone; with it off integrator_error_m reports NaN and
	 * only the axis' other stability guards watch the run. */
	void (*set_shadow)(popc_axis *a, int on);
} popc_axis_ops;

struct popc_axis {
	const popc_axis_ops *ops;
	void *priv;
	double force_limit_N; /* the largest |f_c| the axis sends (0: none); the
				 runner clamps and flags the command to it */
};

/* What only the program knows about the axis it makes: how a real axis is
 * paced and where its notes go. All zero (or a NULL pointer to the options)
 * is the default: paced, no real-time scheduling, no notes, no stop flag. A
 * simulated axis ignores them. The drive's map and URI are scene keys
 * (axis.map, axis.connect; --map and --connect set them), so that the log
 * header's resolved scene names them. */
typedef struct popc_axis_create_options {
	int free_run;       /* 1: no deadlines, each tick as soon as the last one is
			       done (lockstep dry runs); 0: absolute deadlines at run.rate */
	int realtime;       /* 1: try SCHED_FIFO and mlockall (a note says if denied) */
	FILE *notes;        /* where notes go (real-time granted or not, reconnects); may be NULL */
	/* set by the program's signal handler (NULL: none): a real axis looks at
	 * it between the attempts of a failing transaction and while it waits
	 * for the drive, since its link calls are not interrupted by signals */
	volatile sig_atomic_t *stop_flag;
} popc_axis_create_options;

/* Creates the axis the scene's axis.kind names: checks what it needs (a
 * drive's register map and URI) but does not connect (start() does). A kind
 * this build was made without (Modbus without libmodbus) is refused with
 * POPC_ERR_INVALID naming it. The caller frees the axis with
 * popc_axis_destroy. Returns 0 or a negative popc_status. */
int popc_axis_create(popc_axis **out, const popc_scene *s, const popc_axis_create_options *opt,
		     popc_error *err);

/* 1 when the scene's axis is simulated: no hardware, deterministic, any
 * number of runs at once (a sweep, a benchmark); 0 for a real axis. Known
 * from axis.kind alone, without creating the axis. */
int popc_axis_is_simulated(const popc_scene *s);

/* Destroys *a (NULL or an axis) and sets *a to NULL. */
void popc_axis_destroy(popc_axis **a);

#endif
