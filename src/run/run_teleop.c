/* The loop of a teleoperation scene (run_teleop.h; docs/TELEOPERATION.md):
 * each tick both devices are sampled, each side sends its packet into its
 * channel, each receives what arrives, each network port is stepped (the
 * received energy, then the output against the conjugate, with the PC when
 * teleop.tdpa = on: core/teleop.h), the row is logged, and the master gets
 * its force and the slave its velocity. Its own loop, as run_admittance.c:
 * the one-port ticks keep their code and their speed.
 *
 * Within tick k: the master sends (x_m(k), v_m(k), E_in,M through k-1), the
 * slave (f_s(k), E_in,S through k-1), then each receives (channel.h: a delay
 * of 0 arrives in the tick it is sent), so with teleop.link = direct, or a
 * channel of no delay and no loss, each side holds the other's packet of
 * this tick: the same rows.
 *
 * Position-position (teleop.h, popc_teleop_coupling_N): the slave also sends
 * its position and velocity, each side's coupling computes the force on its
 * own device, and both ports are of impedance type; the slave's command is
 * that force (sim_slave_axis.c). */
#include "run_teleop.h"
#include "channel_log.h"
#include "run_stop.h"

#include <math.h>
#include <string.h>

#include "popc/axes/sim_axis.h"
#include "popc/core/channel.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/core/tdpa_drift.h"
#include "popc/core/teleop.h"
#include "popc/scene/delay_trace.h"
#include "popc/scene/from_scene.h"
#include "popc/util/clock.h"

/* One direction: a channel, or the direct link (the packet sent is held). */
typedef struct link {
	int direct;
	popc_channel ch;
	popc_packet held;
	popc_channel_log_dir *log; /* the channel log (NULL, or f NULL: none) */
} link;

/* name: "forward" or "backward", for messages and the channel log; chlog
 * (may be NULL) the channel log's file */
static int link_init(link *l, const popc_scene *s, const popc_scene_channel *dir, const char *name,
		     popc_channel_log_dir *chlog, popc_error *err)
{
	memset(l, 0, sizeof *l);
	l->held.seq = -1;
	l->direct = s->tele_link == POPC_TELEOP_LINK_DIRECT;
	l->log = chlog;
	if (l->direct)
		return 0;
	popc_channel_config c;
	popc_delay_trace trace; /* delays in seconds, a trace file: delay_trace.h */
	int st = popc_channel_config_load(&c, s, dir, name, &trace, err);
	if (!st)
		st = popc_channel_init(&l->ch, &c, err);
	popc_delay_trace_free(&trace); /* init copied it */
	if (!st && chlog && chlog->f) {
		l->ch.on_event = popc_channel_log_event;
		l->ch.event_user = chlog;
	}
	return st;
}

static void link_free(link *l)
{
	if (l->log && l->log->f) /* what is still travelling when the run ends */
		popc_channel_log_in_flight(l->log->f, l->log->name,
					   l->direct ? 0 : popc_channel_in_flight(&l->ch));
	if (!l->direct)
		popc_channel_free(&l->ch);
}

/* Sends p at tick k and receives what arrives: the lost and fresh flags */
static unsigned link_tick(link *l, long long k, const popc_packet *p, unsigned lost_flag,
			  unsigned fresh_flag)
{
	if (l->direct) {
		l->held = *p;
		l->held.seq = k;
		if (l->log && l->log->f) { /* the direct link: sent, delivered at once */
			popc_channel_log_event(l->log, k, k, POPC_CHANNEL_SENT, 0);
			popc_channel_log_event(l->log, k, k, POPC_CHANNEL_DELIVERED, 0);
		}
		return fresh_flag;
	}
	unsigned f = popc_channel_send(&l->ch, k, p) ? lost_flag : 0u;
	int fresh = 0;
	popc_channel_receive(&l->ch, k, &l->held, &fresh);
	return f | (fresh ? fresh_flag : 0u);
}

/* what a side holds before its first packet: nothing moves, nothing may leave */
static double held_value(const link *l, int i)
{
	return l->held.seq < 0 ? 0.0 : l->held.value[i];
}

/* a position before the first packet: the common start (both sides start
 * there at rest), so that no coupling pulls before anything arrived */
static double held_position(const link *l, int i, double start_m)
{
	return l->held.seq < 0 ? start_m : l->held.value[i];
}

static double held_energy(const link *l)
{
	return l->held.seq < 0 ? 0.0 : l->held.energy_J;
}

int popc_run_teleop_axis_is_slave(const popc_axis *axis)
{
	return (axis->ops->log_columns & POPC_LOG_COL_ADMITTANCE) != 0;
}

/* The side the program did not give: the simulated slave, at rest where the
 * master starts (x0_m), or the simulated master of a Modbus slave. */
static int make_other_side(const popc_scene *s, int axis_is_slave, double x0_m, popc_axis **out,
			   popc_error *err)
{
	return axis_is_slave ? popc_sim_axis_create(out, s, err)
			     : popc_sim_slave_axis_create(out, s, x0_m, err);
}

int popc_run_teleop(const popc_scene *s, popc_axis *axis, const popc_run_options *opt,
		    popc_run_summary *sum, popc_error *err)
{
	memset(sum, 0, sizeof *sum);
	const double T = popc_scene_period_s(s);
	const long long n_ticks = popc_scene_ticks(s) + 1;
	sum->integrator = s->integrator;
	sum->substeps = s->substeps;
	sum->has_teleop = 1;
	const int pp = s->tele_arch == POPC_TELEOP_POSITION_POSITION;
	sum->tele_pp = pp;
	const double late_from_s = s->duration_s - 1.0;
	sum->tele_xs_late_min_m = (double)INFINITY;
	sum->tele_xs_late_max_m = -(double)INFINITY;
	popc_environment env;
	popc_environment_from_scene(&env, s);
	popc_metrics_init(&sum->metrics, &env, T, 0.5 * s->duration_s);

	popc_log_writer *log = opt ? opt->log : NULL;
	const char *why = "completed";
	double t0 = popc_now_s();
	/* the program's axis is one side; the runner makes the other
	 * (own), simulated */
	const int axis_is_slave = popc_run_teleop_axis_is_slave(axis);
	popc_axis *own = NULL;
	popc_axis *master = axis_is_slave ? NULL : axis, *slave = axis_is_slave ? axis : NULL;
	link fwd, bwd;
	memset(&fwd, 0, sizeof fwd);
	memset(&bwd, 0, sizeof bwd);
	fwd.direct = bwd.direct = 1; /* nothing to free until made */
	popc_axis_sample sm, ss;
	memset(&sm, 0, sizeof sm);
	memset(&ss, 0, sizeof ss);
	int st = 0;
	if (axis_is_slave && (st = make_other_side(s, 1, 0.0, &own, err)) != 0)
		why = "master create failed";
	else
		master = axis_is_slave ? own : master;
	if (!st && (st = master->ops->start(master, err)) != 0)
		why = st == POPC_ERR_INTERRUPTED ? "signal" : "axis start failed";
	if (!st && (st = master->ops->sample(master, &sm, err)) != 0)
		why = popc_run_sample_failure(st);
	/* a simulated slave starts where the master does, at rest, its servo
	 * holding it; a drive where it stands (popc-servo-sim's teleoperation
	 * plant starts where the simulated master does) */
	if (!st && !axis_is_slave && (st = make_other_side(s, 0, sm.x_true_m, &own, err)) != 0)
		why = "slave create failed";
	else if (!st && !axis_is_slave)
		slave = own;
	if (!st && (st = slave->ops->start(slave, err)) != 0)
		why = st == POPC_ERR_INTERRUPTED ? "signal" : "axis start failed";
	if (!st && (st = slave->ops->sample(slave, &ss, err)) != 0)
		why = popc_run_sample_failure(st);
	popc_channel_log_dir chlog[2] = {{opt ? opt->channel_log : NULL, "forward"},
					 {opt ? opt->channel_log : NULL, "backward"}};
	if (chlog[0].f)
		popc_channel_log_header(chlog[0].f, s);
	if (!st && (st = link_init(&fwd, s, &s->fwd, "forward", &chlog[0], err)) != 0)
		why = "channel create failed";
	if (!st && (st = link_init(&bwd, s, &s->bwd, "backward", &chlog[1], err)) != 0)
		why = "channel create failed";

	popc_tdpa_side side_m, side_s;
	popc_tdpa_side_init_excess(&side_m, s->tele_master_bound_N, s->tele_excess_J);
	popc_tdpa_side_init_excess(&side_s, pp ? s->tele_slave_bound_N : s->tele_slave_bound_mps,
				   s->tele_excess_J);
	/* the slave's drift compensation (tdpa_drift.h), teleop.drift */
	const popc_drift_config drift = {s->tele_drift, s->tele_drift_max_mps, s->tele_drift_ratio};
	const int pc_on = s->tele_tdpa;
	popc_port_energy port;
	popc_port_energy_init(&port);
	/* scenes that ask for less pay for less (as run.c): without a reader of
	 * the summary its impedance metrics are not kept (the two-port figures
	 * are, for the run's own verdicts) */
	const int summary_read = !(opt && opt->summary_unread);
	double xm_prev = 0.0;
	double xs_prev = 0.0, v_s = 0.0, xm_start = 0.0, xs_start = 0.0;
	for (long long k = 0; !st && k < n_ticks; k++) {
		if (opt && opt->stop_flag && *opt->stop_flag) {
			st = popc_error_set(err, POPC_ERR_INTERRUPTED, "interrupted by a signal at t = %g s",
					    (double)k * T);
			why = "signal";
			break;
		}
		popc_log_row row; /* every cell a teleoperation log has is set below */
		popc_tick *m = &row.tick;
		popc_teleop_row *r = &row.tele;
		m->t_s = (double)k * T;
		m->count = sm.count;
		m->x_m = popc_encoder_position(sm.count, s->enc_resolution_m);
		/* the master's velocity, backward difference of the encoder (0 at k = 0) */
		m->v_mps = k ? (m->x_m - xm_prev) / T : 0.0;
		xm_prev = m->x_m;
		r->xs_m = popc_encoder_position(ss.count, s->enc_resolution_m);
		/* a drive has no true position (NaN in its sample; the column is
		 * not in its log): the summary's late window takes the measured one */
		r->xs_true_m = axis_is_slave ? r->xs_m : ss.x_true_m;
		r->xs_cmd_m = ss.x_cmd_m;
		r->fs_count = ss.force_count;
		r->fs_N = (double)ss.force_count * s->slave_force_resolution_N;
		/* the slave's velocity, as the master's (position-position only) */
		v_s = k ? (r->xs_m - xs_prev) / T : 0.0;
		xs_prev = r->xs_m;
		if (k == 0) {
			xm_start = m->x_m;
			xs_start = r->xs_m;
		}

		/* each side's packet, with its input energy through tick k-1 */
		popc_packet pf, pb;
		memset(&pf, 0, sizeof pf);
		memset(&pb, 0, sizeof pb);
		pf.value[POPC_TELEOP_FWD_X] = m->x_m;
		pf.value[POPC_TELEOP_FWD_V] = m->v_mps;
		pf.energy_J = popc_energy_flow_in(&side_m.flow);
		pb.value[POPC_TELEOP_BWD_F] = r->fs_N;
		pb.value[POPC_TELEOP_BWD_X] = r->xs_m;
		pb.value[POPC_TELEOP_BWD_V] = v_s;
		pb.energy_J = popc_energy_flow_in(&side_s.flow);
		unsigned flags = link_tick(&fwd, k, &pf, POPC_TELEOP_FLAG_FWD_LOST, POPC_TELEOP_FLAG_FWD_FRESH);
		flags |= link_tick(&bwd, k, &pb, POPC_TELEOP_FLAG_BWD_LOST, POPC_TELEOP_FLAG_BWD_FRESH);
		r->fwd_age = fwd.held.seq < 0 ? -1 : k - fwd.held.seq;
		r->bwd_age = bwd.held.seq < 0 ? -1 : k - bwd.held.seq;

		/* the slave's port: u = v_c, c = -f_s; position-position: u = F_S,
		 * c = v_s, and xs_cmd, vs_pc, vs_c hold x_m,rx, d_S (N), F_S + d_S (N) */
		r->vs_rx_mps = held_value(&fwd, POPC_TELEOP_FWD_V);
		popc_tdpa_step ps;
		r->xm_rx_m = held_value(&fwd, POPC_TELEOP_FWD_X);
		r->vs_dc_mps = 0.0;
		if (pp) {
			r->xs_cmd_m = held_position(&fwd, POPC_TELEOP_FWD_X, xs_start);
			const double F_S = popc_teleop_coupling_N(s->tele_coupling_K_Npm, s->tele_coupling_B_Nspm,
								  r->xs_cmd_m, r->xs_m, r->vs_rx_mps, v_s);
			ps = popc_teleop_port(&side_s, held_energy(&fwd), F_S, v_s, T, pc_on);
		} else if (drift.law != POPC_DRIFT_OFF) { /* toward the master position held; none before the first */
			ps = popc_drift_port(&side_s, &drift, held_energy(&fwd), r->vs_rx_mps, -r->fs_N, T,
					     pc_on, fwd.held.seq < 0 ? (double)NAN : r->xm_rx_m,
					     r->xs_cmd_m, &r->vs_dc_mps);
		} else {
			ps = popc_teleop_port(&side_s, held_energy(&fwd), r->vs_rx_mps, -r->fs_N, T, pc_on);
		}
		r->vs_pc_mps = ps.d;
		r->vs_c_mps = ps.u;
		r->Ws_J = ps.W_J;
		/* the master's port: u = f_c, c = -v_m (the device receives -f_c);
		 * position-position: f_c = -F_M, the master's coupling force */
		if (pp)
			m->f_e_N = -popc_teleop_coupling_N(s->tele_coupling_K_Npm, s->tele_coupling_B_Nspm,
							   held_position(&bwd, POPC_TELEOP_BWD_X, xm_start), m->x_m,
							   held_value(&bwd, POPC_TELEOP_BWD_V), m->v_mps);
		else
			m->f_e_N = 0.0 - held_value(&bwd, POPC_TELEOP_BWD_F); /* +0 when f_s = 0 */
		popc_tdpa_step pm = popc_teleop_port(&side_m, held_energy(&bwd), m->f_e_N, -m->v_mps, T, pc_on);
		m->f_pc_N = pm.d;
		m->f_c_N = pm.u;
		m->W_J = pm.W_J;
		m->E_ref_J = 0.0;
		flags |= (pm.flags & POPC_TDPA_ACTIVE ? POPC_TELEOP_FLAG_M_ACTIVE : 0u) |
			 (pm.flags & POPC_TDPA_CLAMPED ? POPC_TELEOP_FLAG_M_CLAMPED : 0u) |
			 (ps.flags & POPC_TDPA_ACTIVE ? POPC_TELEOP_FLAG_S_ACTIVE : 0u) |
			 (ps.flags & POPC_TDPA_CLAMPED ? POPC_TELEOP_FLAG_S_CLAMPED : 0u);
		m->flags = flags;
		r->Em_in_J = popc_energy_flow_in(&side_m.flow);
		r->Em_out_J = popc_energy_flow_out(&side_m.flow);
		r->Em_rx_J = side_m.remote_in_J;
		r->Es_in_J = popc_energy_flow_in(&side_s.flow);
		r->Es_out_J = popc_energy_flow_out(&side_s.flow);
		r->Es_rx_J = side_s.remote_in_J;
		/* no NaN or infinity reaches a command: the received values are
		 * finite (each side checks what it sends), the PC's d is bounded or
		 * 0; a failure here is a bug, stopped before the command goes out */
		if (!isfinite(m->f_c_N) || !isfinite(r->vs_c_mps)) {
			st = popc_error_set(err, POPC_ERR_NUMERIC,
					    "teleoperation: a non-finite command (f_c = %g N, v_c = %g m/s) "
					    "at t = %g s",
					    m->f_c_N, r->vs_c_mps, m->t_s);
			why = "integrator unstable";
			break;
		}
		row.x_true_m = sm.x_true_m;
		row.dt_s = ss.dt_s; /* a Modbus slave's (POPC_LOG_COL_TIMING) */
		row.rtt_s = ss.rtt_s;
		/* the master's E_port is a log column only */
		row.E_port_J = log ? popc_port_energy_update(&port, sm.x_true_m) : 0.0;
		if (log)
			popc_port_energy_commit(&port, m->f_c_N);

		/* the summary's two-port condition and bounds */
		/* with the passivity excess E_0 (0: the same bits) */
		const double rm = r->Em_rx_J + side_m.excess_J, rs = r->Es_rx_J + side_s.excess_J;
		const double mm = rm - r->Em_out_J, ms = rs - r->Es_out_J;
		if (mm < sum->tele_margin_min_J[0])
			sum->tele_margin_min_J[0] = mm;
		if (ms < sum->tele_margin_min_J[1])
			sum->tele_margin_min_J[1] = ms;
		if (!popc_teleop_condition_holds(rm, r->Em_out_J) ||
		    !popc_teleop_condition_holds(rs, r->Es_out_J))
			sum->tele_violations++;
		sum->tele_active[0] += (pm.flags & POPC_TDPA_ACTIVE) != 0;
		sum->tele_active[1] += (ps.flags & POPC_TDPA_ACTIVE) != 0;
		sum->tele_clamped[0] += (pm.flags & POPC_TDPA_CLAMPED) != 0;
		sum->tele_clamped[1] += (ps.flags & POPC_TDPA_CLAMPED) != 0;
		sum->tele_d_max[0] = fmax(sum->tele_d_max[0], fabs(pm.d));
		sum->tele_d_max[1] = fmax(sum->tele_d_max[1], fabs(ps.d));
		if (fabs(m->f_c_N) > sum->tele_f_c_max_N)
			sum->tele_f_c_max_N = fabs(m->f_c_N);
		if (fabs(r->vs_c_mps) > sum->tele_v_c_max_mps)
			sum->tele_v_c_max_mps = fabs(r->vs_c_mps);
		if (m->t_s >= late_from_s) {
			sum->tele_xs_late_min_m = fmin(sum->tele_xs_late_min_m, r->xs_true_m);
			sum->tele_xs_late_max_m = fmax(sum->tele_xs_late_max_m, r->xs_true_m);
		}
		sum->tele_drift_end_m = m->x_m - r->xs_m;
		if (summary_read)
			popc_metrics_add(&sum->metrics, m);
		if (opt && opt->on_tick)
			opt->on_tick(opt->tick_user, m);
		if (log && (st = popc_log_write_row(log, &row, err)) != 0) {
			why = "log write failed";
			break;
		}
		sum->ticks = k + 1;
		if (k + 1 < n_ticks) {
			if ((st = master->ops->exchange(master, m->f_c_N, &sm, err)) != 0 ||
			    (st = slave->ops->exchange(slave, r->vs_c_mps, &ss, err)) != 0) {
				why = popc_run_sample_failure(st);
				break;
			}
		}
	}
	link_free(&fwd);
	link_free(&bwd);
	/* every way out: the simulated side's stop (a simulated master: zero
	 * force, before the drive is held), then the program's axis' safe stop
	 * (a Modbus slave: zero velocity or the last measured position held,
	 * then disable; a stop it cannot confirm is the run's error), the
	 * summary and the log */
	if (own) {
		popc_error oerr;
		own->ops->stop(own, &oerr);
	}
	sum->integrator_error_m = master && master->ops->integrator_error_m
					  ? master->ops->integrator_error_m(master)
					  : 0.0;
	st = popc_run_finish(axis, log, sum, st, why, t0, T, err);
	popc_axis_destroy(&own);
	return st;
}
