/* The experiment loop: axis -> controller -> log, with the end-of-run summary. */
#ifndef POPC_RUN_H
#define POPC_RUN_H

#include <signal.h>
#include <stdio.h>

#include "popc/axes/axis.h"
#include "popc/log/log.h"
#include "popc/core/metrics.h"
#include "popc/scene/scene.h"
#include "popc/util/json.h"
#include "popc/util/text_builder.h"

typedef struct popc_run_summary {
	double sim_time_s, wall_time_s;
	long long ticks;
	popc_integrator integrator;
	int substeps;
	double integrator_error_m;    /* max |x - x_exact| at the samples; 0 when exact */
	popc_metrics metrics;
	/* the true port energy (port_energy.h), for an axis with a true
	 * position (has_port_energy; all 0 otherwise): E_port at the last tick,
	 * the observer's error W - E_port there, and its largest magnitude;
	 * the smallest E_port of the run */
	int has_port_energy;
	double port_energy_J, po_error_end_J, po_error_max_J;
	double port_energy_min_J;     /* min over the run of E_port (0 at t = 0) */
	/* the device port's energy E_dev = E_port + D (D: the energy the
	 * plant's damping dissipated, plant_dissipation.h), for an axis that
	 * gave D at every tick (has_device_energy; 0 otherwise): at the last
	 * tick and its minimum (0 at t = 0) */
	int has_device_energy;
	double device_energy_J, device_energy_min_J;
	/* admittance causality (has_admittance): the parallel PC's velocity
	 * v_pc over the run and its second half (the chatter detector sees it
	 * through on_tick: run_admittance.c) */
	int has_admittance;
	double adm_active, adm_v_pc_rms_mps, adm_v_pc_max_mps, adm_v_pc_rms_late_mps;
	/* a teleoperation scene (has_teleop; run_teleop.c): kept in the
	 * struct, not in RUN_SUMMARY_FIELDS (every summary keeps its columns).
	 * The smallest two-port margin E_in,remote - E_out of each side
	 * (master, slave) over the run; the ticks where either margin was
	 * below its rounding allowance (core/teleop.h); ticks a PC acted and was clamped; the
	 * largest |f_c| and |v_c|, and of each PC's |d|; the slave's true position's range over the
	 * last second (an oscillation's peak to peak) */
	int has_teleop;
	double tele_margin_min_J[2];
	long long tele_violations, tele_active[2], tele_clamped[2];
	double tele_f_c_max_N, tele_v_c_max_mps; /* position-position: |v_c| is the slave's |F_S| (N) */
	int tele_pp;                  /* position-position (the slave's command a force) */
	double tele_d_max[2];          /* the largest |d| of each PC (N, m/s) */
	double tele_xs_late_min_m, tele_xs_late_max_m;
	double tele_drift_end_m;       /* x_m - x_s (encoder) at the last tick logged */
	int status;                   /* 0 or the popc_status that stopped the run */
	char stop_reason[POPC_ERROR_MSG_MAX + 64];
} popc_run_summary;

typedef struct popc_run_options {
	popc_log_writer *log;              /* NULL: no log */
	volatile sig_atomic_t *stop_flag;  /* set by a signal handler: stop safely */
	/* called with every tick after it is logged (NULL: none); for streaming
	 * analyses such as the chatter detector of a sweep */
	void (*on_tick)(void *user, const popc_tick *tick);
	void *tick_user;
	/* 1: nobody reads the summary's metrics and energies (popc run -q
	 * without --summary): the run does not compute them, and E_port only
	 * for the log's column; its status, stop reason, ticks and times are
	 * filled as always. 0 (the default): everything. */
	int summary_unread;
	/* a teleoperation run's channel log (NULL: none): one row per packet
	 * event (popc run --channel-log; docs/TELEOPERATION.md); the caller
	 * opens and closes it */
	FILE *channel_log;
} popc_run_options;

/* The log's column set for a run of scene s on axis: the axis' columns, and
 * in a teleoperation scene the slave's and the network's (log_columns.h);
 * there the axis is the simulated master, or the Modbus slave (axis.kind =
 * modbus: the master is then simulated by the runner), and the column set
 * the simulated master's, the TELEOP ones, and the simulated slave's true
 * position or the Modbus slave's timing. */
unsigned popc_run_log_columns(const popc_scene *s, const popc_axis *axis);

/* Runs the scene on the axis. Always calls the axis' stop() and writes the
 * stop reason to the log before returning. Returns 0 or a negative popc_status. */
int popc_run(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
	     popc_run_summary *sum, popc_error *err);

/* Human summary (several lines) and one CSV row with its header. */
/* The variant's name as the log and summary give it: controller.variant, or
 * admittance.variant in an admittance scene. */
const char *popc_run_variant_name(const popc_scene *s);
void popc_run_summary_print(const popc_run_summary *sum, const popc_scene *s, FILE *f);
void popc_run_summary_csv_header(FILE *f);
void popc_run_summary_csv_row(const popc_run_summary *sum, const popc_scene *s, FILE *f);
/* The same row into buf (cap bytes), NUL-terminated when cap > 0; returns
 * its length, which is >= cap when it did not fit (as snprintf). */
size_t popc_run_summary_csv_row_text(const popc_run_summary *sum, const popc_scene *s, char *buf,
				     size_t cap);
/* The summary's field NAME (a column of its CSV row): its index, or -1 when
 * no field has that name. */
int popc_run_summary_field(const char *name);
/* Appends field FIELD's cell (an index from popc_run_summary_field) to t,
 * the bytes popc_run_summary_csv_row_text writes for it: a sweep makes its
 * row from the fields it takes without the text of the whole row. */
void popc_run_summary_put_cell(popc_text_builder *t, const popc_run_summary *sum,
			       const popc_scene *s, int field);
/* The JSON kind of the summary column NAME (RUN_SUMMARY_FIELDS): a string for
 * a TEXT field, a number for INT and REAL; POPC_JSON_AUTO for a name that is
 * not a field (a real axis' columns appended after the run's). */
popc_json_kind popc_run_summary_json_kind(const char *name);

#endif
