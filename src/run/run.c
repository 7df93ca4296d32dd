/* The experiment loop (run.h): sample -> controller -> log -> command. The
 * run summary's table and its text, CSV and JSON output: run_summary.c. */
#include "popc/run/run.h"

#include <math.h>
#include <string.h>

#include "popc/core/controller.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/util/clock.h"
#include "popc/scene/from_scene.h"

#include "run_admittance.h"
#include "run_stop.h"
#include "run_teleop.h"

unsigned popc_run_log_columns(const popc_scene *s, const popc_axis *axis)
{
	if (s->tele_arch == POPC_TELEOP_OFF)
		return axis->ops->log_columns;
	/* a teleoperation scene (run_teleop.c): the master is simulated (its
	 * true position); the axis is the master, with the simulated slave's
	 * true position too, or an admittance-type one, the Modbus slave, whose
	 * measured period and round trip are logged (its other columns are the
	 * TELEOP ones); with drift compensation, its two columns */
	return POPC_LOG_COL_X_TRUE | POPC_LOG_COL_TELEOP |
	       (popc_run_teleop_axis_is_slave(axis) ? axis->ops->log_columns & POPC_LOG_COL_TIMING
						    : POPC_LOG_COL_SLAVE_TRUE) |
	       (s->tele_drift != POPC_DRIFT_OFF ? POPC_LOG_COL_DRIFT : 0u);
}

int popc_run(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
	     popc_run_summary *sum, popc_error *err)
{
	if (s->causality == POPC_CAUSALITY_ADMITTANCE)
		return popc_run_admittance(s, axis, opt, sum, err);
	if (s->tele_arch != POPC_TELEOP_OFF)
		return popc_run_teleop(s, axis, opt, sum, err);
	memset(sum, 0, sizeof *sum);
	const double T = popc_scene_period_s(s);
	const long long n_ticks = popc_scene_ticks(s) + 1; /* t = 0, T, ..., duration */
	sum->integrator = s->integrator;
	sum->substeps = s->substeps;

	popc_controller_config ccfg;
	popc_controller_config_from_scene(&ccfg, s);
	ccfg.force_limit_N = axis->force_limit_N;
	popc_controller *ctl;
	int st = popc_controller_create(&ccfg, &ctl, err);
	if (st)
		return st; /* before the axis starts: nothing to stop, nothing logged */
	/* the "late" window: the second half of the run, the seed's low-velocity phase */
	popc_metrics_init(&sum->metrics, &ccfg.env, T, 0.5 * s->duration_s);

	popc_log_writer *log = opt ? opt->log : NULL;
	const char *why = "completed";
	double t0 = popc_now_s();
	popc_axis_sample smp;
	st = axis->ops->start(axis, err);
	if (st)
		why = st == POPC_ERR_INTERRUPTED ? "signal" : "axis start failed";
	smp.dissipated_J = (double)NAN; /* unless the axis says */
	if (!st) {
		st = axis->ops->sample(axis, &smp, err);
		if (st)
			why = popc_run_sample_failure(st);
	}
	/* the true port energy, for an axis that knows its true position (the
	 * log's E_port column is filled by the same axes as x_true) */
	const int has_true_x = (axis->ops->log_columns & POPC_LOG_COL_X_TRUE) != 0;
	/* scenes that ask for less pay for less (issue 23): without a reader of
	 * the summary, no metrics and no energies but the log's E_port */
	const int summary_read = !(opt && opt->summary_unread);
	const int port_needed = has_true_x && (summary_read || log);
	popc_port_energy port;
	popc_port_energy_init(&port);
	sum->has_port_energy = has_true_x;
	/* E_dev = E_port + D, while the axis gives D at every tick */
	sum->has_device_energy = has_true_x;
	double diss_sum_J = 0.0, diss_comp_J = 0.0;
	/* run.delay_ticks = d: the command of tick k reaches the axis with the
	 * exchange of tick k + d (sent after tick k + d's sample), so it acts
	 * from t = (k + 1 + d) T, d periods later than without delay; the first
	 * d exchanges send 0 N (nothing computed yet). A ring of d commands in
	 * the loop, so every axis kind sees the same delayed command stream;
	 * d = 0 sends f_c(k) itself, today's loop bit for bit. */
	const int delay = s->delay_ticks;
	double delayed_N[POPC_SCENE_MAX_DELAY_TICKS];
	int delay_next = 0;
	for (int i = 0; i < delay; i++)
		delayed_N[i] = 0.0;
	long long k = 0;
	for (; !st && k < n_ticks; k++) {
		if (opt && opt->stop_flag && *opt->stop_flag) {
			st = popc_error_set(err, POPC_ERR_INTERRUPTED, "interrupted by a signal at t = %g s",
					    (double)k * T);
			why = "signal";
			break;
		}
		popc_log_row row;
		row.tick.t_s = (double)k * T;
		popc_controller_step(ctl, smp.count, popc_encoder_position(smp.count, s->enc_resolution_m),
				     &row.tick);
		/* the command that acts over this period: f_c(k), or f_c(k - d) */
		double command_N = row.tick.f_c_N;
		if (delay > 0) {
			command_N = delayed_N[delay_next];
			delayed_N[delay_next] = row.tick.f_c_N;
			delay_next = delay_next + 1 == delay ? 0 : delay_next + 1;
		}
		row.x_true_m = smp.x_true_m;
		row.E_port_J = 0.0;
		if (port_needed) {
			/* the port's energy is that of the force the plant really
			 * receives over the period: the delayed command */
			row.E_port_J = popc_port_energy_update(&port, smp.x_true_m);
			popc_port_energy_commit(&port, command_N);
		}
		if (has_true_x && summary_read) {
			/* W(k) - E_port(k): the observer's error at tick k */
			double e = row.tick.W_J - row.E_port_J;
			sum->port_energy_J = row.E_port_J;
			/* E_port(0) = 0, so the minimum starts at 0 (memset) */
			if (row.E_port_J < sum->port_energy_min_J)
				sum->port_energy_min_J = row.E_port_J;
			sum->po_error_end_J = e;
			if (fabs(e) > sum->po_error_max_J)
				sum->po_error_max_J = fabs(e);
			if (sum->has_device_energy && isfinite(smp.dissipated_J)) {
				/* D(k) = sum of the periods' dissipations before tick k
				 * (the sample of tick 0 says 0: axis.h) */
				double d = popc_compensated_add(&diss_sum_J, &diss_comp_J,
								smp.dissipated_J);
				double dev = row.E_port_J + d;
				sum->device_energy_J = dev;
				if (dev < sum->device_energy_min_J)
					sum->device_energy_min_J = dev;
			} else {
				sum->has_device_energy = 0;
			}
		}
		row.dt_s = smp.dt_s;
		row.rtt_s = smp.rtt_s;
		if (summary_read)
			popc_metrics_add(&sum->metrics, &row.tick);
		if (opt && opt->on_tick)
			opt->on_tick(opt->tick_user, &row.tick);
		if (log && (st = popc_log_write_row(log, &row, err)) != 0) {
			why = "log write failed";
			break;
		}
		sum->ticks = k + 1;
		smp.dissipated_J = (double)NAN;
		if (k + 1 < n_ticks && (st = axis->ops->exchange(axis, command_N, &smp, err)) != 0) {
			why = popc_run_sample_failure(st);
			break;
		}
	}
	/* every way out: safe state first, then the summary and the log */
	popc_controller_free(ctl);
	st = popc_run_finish(axis, log, sum, st, why, t0, T, err);
	/* an axis without a model to check has no integrator error */
	sum->integrator_error_m =
		axis->ops->integrator_error_m ? axis->ops->integrator_error_m(axis) : 0.0;
	return st;
}
