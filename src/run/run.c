/* The experiment loop (run.h): sample -> controller -> log -> command. */
#include "popc/run/run.h"

#include <math.h>
#include <string.h>

#include "popc/core/controller.h"
#include "popc/core/encoder.h"
#include "popc/util/numfmt.h"
#include "popc/util/clock.h"
#include "popc/scene/from_scene.h"

int popc_run(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
	     popc_run_summary *sum, popc_error *err)
{
	memset(sum, 0, sizeof *sum);
	const double T = popc_scene_period_s(s);
	const long long n_ticks = popc_scene_ticks(s) + 1; /* t = 0, T, ..., duration */
	sum->integrator = s->integrator;
	sum->substeps = s->substeps;

	popc_controller_config ccfg;
	popc_controller_config_from_scene(&ccfg, s);
	ccfg.force_limit_N = axis->force_limit_N;
	popc_controller ctl;
	popc_controller_init(&ctl, &ccfg);
	/* the "late" window: the second half of the run, the seed's low-velocity phase */
	popc_metrics_init(&sum->metrics, &ccfg.env, T, 0.5 * s->duration_s);

	popc_log_writer *log = opt ? opt->log : NULL;
	int st = 0;
	const char *why = "completed";
	double t0 = popc_now_s();
	popc_axis_sample smp;
	st = axis->ops->start(axis, err);
	if (st)
		why = st == POPC_ERR_INTERRUPTED ? "signal" : "axis start failed";
	if (!st) {
		st = axis->ops->sample(axis, &smp, err);
		if (st)
			why = st == POPC_ERR_INTERRUPTED ? "signal" : "axis sample failed";
	}
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
		popc_controller_step(&ctl, smp.count, popc_encoder_position(smp.count, s->enc_resolution_m),
				     &row.tick);
		row.x_true_m = smp.x_true_m;
		row.dt_s = smp.dt_s;
		row.rtt_s = smp.rtt_s;
		popc_metrics_add(&sum->metrics, &row.tick);
		if (opt && opt->on_tick)
			opt->on_tick(opt->tick_user, &row.tick);
		if (log && (st = popc_log_write_row(log, &row, err)) != 0) {
			why = "log write failed";
			break;
		}
		sum->ticks = k + 1;
		if (k + 1 < n_ticks && (st = axis->ops->exchange(axis, row.tick.f_c_N, &smp, err)) != 0) {
			why = st == POPC_ERR_NUMERIC ? "integrator unstable"
			      : st == POPC_ERR_DIVERGED ? "closed loop diverged"
			      : st == POPC_ERR_SAFETY ? "safety stop"
			      : st == POPC_ERR_COMM   ? "communication lost"
			      : st == POPC_ERR_INTERRUPTED ? "signal" /* seen by the axis mid-transaction */
						      : "axis error";
			break;
		}
	}
	/* every way out: safe state first, then the log */
	popc_error stop_err;
	int stop_st = axis->ops->stop(axis, &stop_err);
	if (stop_st && !st) {
		st = stop_st;
		why = "axis stop failed";
		if (err)
			*err = stop_err;
	}
	sum->wall_time_s = popc_now_s() - t0;
	sum->sim_time_s = sum->ticks > 0 ? (double)(sum->ticks - 1) * T : 0.0;
	sum->integrator_error_m = popc_sim_axis_max_error(axis);
	sum->status = st;
	if (st && err)
		snprintf(sum->stop_reason, sizeof sum->stop_reason, "%s: %s", why, err->msg);
	else
		snprintf(sum->stop_reason, sizeof sum->stop_reason, "%s", why);
	if (log) {
		popc_error lerr;
		int lst = popc_log_write_comment(log, "stop", sum->stop_reason, &lerr);
		if (!lst)
			lst = popc_log_flush(log, &lerr);
		if (lst && !st) {
			st = lst;
			if (err)
				*err = lerr;
		}
	}
	return st;
}

static void fmt(char *buf, double v)
{
	popc_format_double(v, buf);
}

void popc_run_summary_print(const popc_run_summary *sum, const popc_scene *s, FILE *f)
{
	const popc_metrics *m = &sum->metrics;
	double rtf = sum->wall_time_s > 0 ? sum->sim_time_s / sum->wall_time_s : (double)INFINITY;
	fprintf(f, "popc run: %s, variant %s, %lld ticks at %g Hz\n", sum->stop_reason,
		popc_variant_name(s->variant), sum->ticks, s->rate_Hz);
	fprintf(f, "  simulated %.6g s in %.6g s wall: %.4g x real time, %.4g ns per tick\n",
		sum->sim_time_s, sum->wall_time_s, rtf,
		sum->ticks ? 1e9 * sum->wall_time_s / (double)sum->ticks : 0.0);
	if (sum->integrator == POPC_INTEGRATOR_EXACT)
		fprintf(f, "  integrator: exact (ZOH/FOH discretization)\n");
	else
		fprintf(f, "  integrator: %s, %d substeps; max position error against exact: %.3g m\n",
			popc_integrator_name(sum->integrator), sum->substeps, sum->integrator_error_m);
	fprintf(f, "  PC active %.4g %% of ticks; f_pc RMS %.4g N, max %.4g N; late half RMS %.4g N\n",
		100.0 * popc_metrics_active_fraction(&m->all), popc_metrics_pc_rms(&m->all),
		m->all.pc_max_N, popc_metrics_pc_rms(&m->late));
	fprintf(f, "  W - E_ref: final %.4g J, minimum %.4g J; velocity sign changes in contact %.4g /s\n",
		m->w_minus_eref_end_J, isfinite(m->w_minus_eref_min_J) ? m->w_minus_eref_min_J : 0.0,
		popc_metrics_vsign_rate(&m->all, m->period_s));
}

void popc_run_summary_csv_header(FILE *f)
{
	fputs("variant,integrator,substeps,status,ticks,sim_time_s,wall_time_s,realtime_factor,"
	      "ns_per_tick,integrator_error_m,pc_active,pc_rms,pc_max,pc_rms_late,pc_energy,"
	      "w_minus_eref_min,w_minus_eref_end,vsign_rate,vsign_rate_late\n",
	      f);
}

void popc_run_summary_csv_row(const popc_run_summary *sum, const popc_scene *s, FILE *f)
{
	const popc_metrics *m = &sum->metrics;
	double v[14] = {
		sum->sim_time_s,
		sum->wall_time_s,
		sum->wall_time_s > 0 ? sum->sim_time_s / sum->wall_time_s : 0.0,
		sum->ticks ? 1e9 * sum->wall_time_s / (double)sum->ticks : 0.0,
		sum->integrator_error_m,
		popc_metrics_active_fraction(&m->all),
		popc_metrics_pc_rms(&m->all),
		m->all.pc_max_N,
		popc_metrics_pc_rms(&m->late),
		m->pc_energy_J,
		isfinite(m->w_minus_eref_min_J) ? m->w_minus_eref_min_J : 0.0,
		m->w_minus_eref_end_J,
		popc_metrics_vsign_rate(&m->all, m->period_s),
		popc_metrics_vsign_rate(&m->late, m->period_s),
	};
	fprintf(f, "%s,%s,%d,%d,%lld", popc_variant_name(s->variant),
		popc_integrator_name(sum->integrator), sum->substeps, sum->status, sum->ticks);
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
		char b[POPC_DOUBLE_TEXT_MAX + 1];
		fmt(b, v[i]);
		fprintf(f, ",%s", b);
	}
	fputc('\n', f);
}
