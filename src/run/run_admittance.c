/* The loop of an admittance scene (run_admittance.h; docs/ADMITTANCE.md):
 * sample (position count, force count) -> admittance controller (VE,
 * observer, parallel PC) -> log -> velocity command. Its own loop, not a
 * branch in popc_run's: the impedance tick keeps its code and its speed. */
#include "run_admittance.h"
#include "run_stop.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "popc/core/admittance.h"
#include "popc/core/encoder.h"
#include "popc/core/sum_squares.h"
#include "popc/scene/from_scene.h"
#include "popc/util/clock.h"

/* The PC's velocity over the run and its second half (run.h) */
typedef struct adm_stats {
	long long ticks, active, ticks_late;
	popc_sum_squares sq, sq_late;
	double max_mps;
} adm_stats;

static void stats_add(adm_stats *a, double v_pc, int late)
{
	a->ticks++;
	a->active += v_pc != 0.0;
	popc_sum_squares_add(&a->sq, v_pc);
	if (fabs(v_pc) > a->max_mps)
		a->max_mps = fabs(v_pc);
	if (late) {
		a->ticks_late++;
		popc_sum_squares_add(&a->sq_late, v_pc);
	}
}

int popc_run_admittance(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
			popc_run_summary *sum, popc_error *err)
{
	memset(sum, 0, sizeof *sum);
	const double T = popc_scene_period_s(s);
	const long long n_ticks = popc_scene_ticks(s) + 1;
	sum->integrator = s->integrator;
	sum->substeps = s->substeps;
	sum->has_admittance = 1;
	if (!(axis->ops->log_columns & POPC_LOG_COL_ADMITTANCE))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: device.causality = admittance: the %s axis has no force sensor",
				      s->source, axis->ops->name);

	popc_admittance_config acfg;
	popc_admittance_config_from_scene(&acfg, s);
	popc_admittance_controller ctl;
	popc_metrics_init(&sum->metrics, &acfg.env, T, 0.5 * s->duration_s);
	adm_stats stats;
	memset(&stats, 0, sizeof stats);

	popc_log_writer *log = opt ? opt->log : NULL;
	int st;
	const char *why = "completed";
	double t0 = popc_now_s();
	popc_axis_sample smp;
	memset(&smp, 0, sizeof smp);
	st = axis->ops->start(axis, err);
	if (st)
		why = "axis start failed";
	if (!st && (st = axis->ops->sample(axis, &smp, err)) != 0)
		why = popc_run_sample_failure(st);
	if (!st)
		popc_admittance_init(&ctl, &acfg, popc_encoder_position(smp.count, s->enc_resolution_m));
	for (long long k = 0; !st && k < n_ticks; k++) {
		if (opt && opt->stop_flag && *opt->stop_flag) {
			st = popc_error_set(err, POPC_ERR_INTERRUPTED, "interrupted by a signal at t = %g s",
					    (double)k * T);
			why = "signal";
			break;
		}
		popc_log_row row; /* every cell an admittance log has is set below */
		popc_admittance_step(&ctl, smp.force_count, &row.adm);
		/* the columns every log has, in their admittance meaning
		 * (docs/ADMITTANCE.md, "The log"): v the velocity command, f_e the
		 * VE's environment force, no force command (f_pc = f_c = 0), W the
		 * admittance observer's, E_ref 0, the admittance flags */
		row.tick.t_s = (double)k * T;
		row.tick.count = smp.count;
		row.tick.x_m = popc_encoder_position(smp.count, s->enc_resolution_m);
		row.tick.v_mps = row.adm.v_c_mps;
		row.tick.f_e_N = row.adm.f_env_N;
		row.tick.f_pc_N = 0.0;
		row.tick.f_c_N = 0.0;
		row.tick.E_ref_J = 0.0;
		row.tick.W_J = row.adm.W_J;
		row.tick.flags = row.adm.flags;
		row.x_true_m = smp.x_true_m;
		row.x_cmd_m = smp.x_cmd_m;
		row.dt_s = smp.dt_s; /* a real axis' timing columns */
		row.rtt_s = smp.rtt_s;
		popc_metrics_add(&sum->metrics, &row.tick);
		stats_add(&stats, row.adm.v_pc_mps, row.tick.t_s >= sum->metrics.late_from_s);
		if (opt && opt->on_tick) {
			/* a streaming analysis (the chatter detector of a sweep or a
			 * test) sees the PC's output v_pc in the place of f_pc: the
			 * detector's thresholds are shares of the PC's bound, which
			 * the caller gives as admittance.pc_velocity_bound */
			popc_tick pc = row.tick;
			pc.f_pc_N = row.adm.v_pc_mps;
			opt->on_tick(opt->tick_user, &pc);
		}
		if (log && (st = popc_log_write_row(log, &row, err)) != 0) {
			why = "log write failed";
			break;
		}
		sum->ticks = k + 1;
		if (k + 1 < n_ticks && (st = axis->ops->exchange(axis, row.adm.v_c_mps, &smp, err)) != 0) {
			why = popc_run_sample_failure(st);
			break;
		}
	}
	sum->adm_active = stats.ticks ? (double)stats.active / (double)stats.ticks : 0.0;
	sum->adm_v_pc_rms_mps = stats.ticks ? popc_sum_squares_rms(&stats.sq, (double)stats.ticks) : 0.0;
	sum->adm_v_pc_rms_late_mps =
		stats.ticks_late ? popc_sum_squares_rms(&stats.sq_late, (double)stats.ticks_late) : 0.0;
	sum->adm_v_pc_max_mps = stats.max_mps;
	/* every way out: safe state first, then the summary and the log */
	st = popc_run_finish(axis, log, sum, st, why, t0, T, err);
	return st;
}
