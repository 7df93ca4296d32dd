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
 * this tick: the same rows. */
#include "run_teleop.h"
#include "run_stop.h"

#include <math.h>
#include <string.h>

#include "popc/axes/sim_axis.h"
#include "popc/core/channel.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/core/teleop.h"
#include "popc/scene/from_scene.h"
#include "popc/util/clock.h"

/* One direction: a channel, or the direct link (the packet sent is held). */
typedef struct link {
	int direct;
	popc_channel ch;
	popc_packet held;
} link;

static int link_init(link *l, const popc_scene *s, const popc_scene_channel *dir, popc_error *err)
{
	memset(l, 0, sizeof *l);
	l->held.seq = -1;
	l->direct = s->tele_link == POPC_TELEOP_LINK_DIRECT;
	if (l->direct)
		return 0;
	popc_channel_config c;
	popc_channel_config_from_scene(&c, dir);
	return popc_channel_init(&l->ch, &c, err);
}

static void link_free(link *l)
{
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

static double held_energy(const link *l)
{
	return l->held.seq < 0 ? 0.0 : l->held.energy_J;
}

int popc_run_teleop(const popc_scene *s, popc_axis *master, const popc_run_options *opt,
		    popc_run_summary *sum, popc_error *err)
{
	memset(sum, 0, sizeof *sum);
	const double T = popc_scene_period_s(s);
	const long long n_ticks = popc_scene_ticks(s) + 1;
	sum->integrator = s->integrator;
	sum->substeps = s->substeps;
	sum->has_teleop = 1;
	const double late_from_s = s->duration_s - 1.0;
	sum->tele_xs_late_min_m = (double)INFINITY;
	sum->tele_xs_late_max_m = -(double)INFINITY;
	popc_environment env;
	popc_environment_from_scene(&env, s);
	popc_metrics_init(&sum->metrics, &env, T, 0.5 * s->duration_s);

	popc_log_writer *log = opt ? opt->log : NULL;
	const char *why = "completed";
	double t0 = popc_now_s();
	popc_axis *slave = NULL;
	link fwd, bwd;
	memset(&fwd, 0, sizeof fwd);
	memset(&bwd, 0, sizeof bwd);
	fwd.direct = bwd.direct = 1; /* nothing to free until made */
	popc_axis_sample sm, ss;
	memset(&sm, 0, sizeof sm);
	memset(&ss, 0, sizeof ss);
	int st = master->ops->start(master, err);
	if (st)
		why = st == POPC_ERR_INTERRUPTED ? "signal" : "axis start failed";
	if (!st && (st = master->ops->sample(master, &sm, err)) != 0)
		why = popc_run_sample_failure(st);
	/* the slave starts where the master does, at rest, its servo holding it */
	if (!st && (st = popc_sim_slave_axis_create(&slave, s, sm.x_true_m, err)) != 0)
		why = "slave create failed";
	if (!st && (st = slave->ops->sample(slave, &ss, err)) != 0)
		why = popc_run_sample_failure(st);
	if (!st && (st = link_init(&fwd, s, &s->fwd, err)) != 0)
		why = "channel create failed";
	if (!st && (st = link_init(&bwd, s, &s->bwd, err)) != 0)
		why = "channel create failed";

	popc_tdpa_side side_m, side_s;
	popc_tdpa_side_init(&side_m, s->tele_master_bound_N);
	popc_tdpa_side_init(&side_s, s->tele_slave_bound_mps);
	const int pc_on = s->tele_tdpa;
	popc_port_energy port;
	popc_port_energy_init(&port);
	double xm_prev = 0.0;
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
		r->xs_true_m = ss.x_true_m;
		r->xs_cmd_m = ss.x_cmd_m;
		r->fs_count = ss.force_count;
		r->fs_N = (double)ss.force_count * s->slave_force_resolution_N;

		/* each side's packet, with its input energy through tick k-1 */
		popc_packet pf, pb;
		memset(&pf, 0, sizeof pf);
		memset(&pb, 0, sizeof pb);
		pf.value[POPC_TELEOP_FWD_X] = m->x_m;
		pf.value[POPC_TELEOP_FWD_V] = m->v_mps;
		pf.energy_J = popc_energy_flow_in(&side_m.flow);
		pb.value[POPC_TELEOP_BWD_F] = r->fs_N;
		pb.energy_J = popc_energy_flow_in(&side_s.flow);
		unsigned flags = link_tick(&fwd, k, &pf, POPC_TELEOP_FLAG_FWD_LOST, POPC_TELEOP_FLAG_FWD_FRESH);
		flags |= link_tick(&bwd, k, &pb, POPC_TELEOP_FLAG_BWD_LOST, POPC_TELEOP_FLAG_BWD_FRESH);
		r->fwd_age = fwd.held.seq < 0 ? -1 : k - fwd.held.seq;
		r->bwd_age = bwd.held.seq < 0 ? -1 : k - bwd.held.seq;

		/* the slave's port: u = v_c, c = -f_s */
		r->vs_rx_mps = held_value(&fwd, POPC_TELEOP_FWD_V);
		popc_tdpa_step ps = popc_teleop_port(&side_s, held_energy(&fwd), r->vs_rx_mps, -r->fs_N, T, pc_on);
		r->vs_pc_mps = ps.d;
		r->vs_c_mps = ps.u;
		r->Ws_J = ps.W_J;
		/* the master's port: u = f_c, c = -v_m (the device receives -f_c) */
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
		row.E_port_J = popc_port_energy_update(&port, sm.x_true_m);
		popc_port_energy_commit(&port, m->f_c_N);

		/* the summary's two-port condition and bounds */
		const double mm = r->Em_rx_J - r->Em_out_J, ms = r->Es_rx_J - r->Es_out_J;
		if (mm < sum->tele_margin_min_J[0])
			sum->tele_margin_min_J[0] = mm;
		if (ms < sum->tele_margin_min_J[1])
			sum->tele_margin_min_J[1] = ms;
		if (!popc_teleop_condition_holds(r->Em_rx_J, r->Em_out_J) ||
		    !popc_teleop_condition_holds(r->Es_rx_J, r->Es_out_J))
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
			sum->tele_xs_late_min_m = fmin(sum->tele_xs_late_min_m, ss.x_true_m);
			sum->tele_xs_late_max_m = fmax(sum->tele_xs_late_max_m, ss.x_true_m);
		}
		sum->tele_drift_end_m = m->x_m - r->xs_m;
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
	if (slave) {
		popc_error serr;
		slave->ops->stop(slave, &serr);
		popc_axis_destroy(&slave);
	}
	/* every way out: the master's safe stop first, then the summary and the log */
	st = popc_run_finish(master, log, sum, st, why, t0, T, err);
	sum->integrator_error_m =
		master->ops->integrator_error_m ? master->ops->integrator_error_m(master) : 0.0;
	return st;
}
