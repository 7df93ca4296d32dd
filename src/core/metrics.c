/* Streaming run metrics (metrics.h). */
#include "popc/core/metrics.h"

#include <math.h>
#include <string.h>

void popc_metrics_init(popc_metrics *m, const popc_environment *env, double period_s,
		       double late_from_s)
{
	memset(m, 0, sizeof *m);
	m->env = *env;
	m->period_s = period_s;
	m->late_from_s = late_from_s;
	m->w_minus_eref_min_J = (double)INFINITY;
}

static void window_add(popc_metrics_window *w, const popc_tick *t, int in_contact, int sign_change)
{
	w->ticks++;
	if (t->f_pc_N != 0.0)
		w->active_ticks++;
	popc_sum_squares_add(&w->pc_sq, t->f_pc_N);
	if (fabs(t->f_pc_N) > w->pc_max_N)
		w->pc_max_N = fabs(t->f_pc_N);
	if (in_contact) {
		w->contact_ticks++;
		w->vsign_changes += sign_change;
	}
}

void popc_metrics_add(popc_metrics *m, const popc_tick *t)
{
	int sign_change = 0;
	if (m->started) {
		double dx = t->x_m - m->x_prev_m;
		/* energy the PC took out: f_pc(k-1) held over the step dx(k) */
		m->pc_energy_J += m->f_pc_prev_N * dx;
		/* velocity sign: the sign of the last nonzero displacement */
		int s = dx > 0 ? 1 : dx < 0 ? -1 : 0;
		if (s != 0) {
			if (m->last_sign != 0 && s != m->last_sign)
				sign_change = 1;
			m->last_sign = s;
		}
	}
	int contact = popc_environment_in_contact(&m->env, t->x_m);
	if (contact) {
		double pen = t->x_m - m->env.position_m;
		m->fc_pen_sum_Nm += t->f_c_N * pen;
		m->pen_sq_sum_m2 += pen * pen;
	}
	window_add(&m->all, t, contact, sign_change);
	if (t->t_s >= m->late_from_s)
		window_add(&m->late, t, contact, sign_change);
	double d = t->W_J - t->E_ref_J;
	if (d < m->w_minus_eref_min_J)
		m->w_minus_eref_min_J = d;
	m->w_minus_eref_end_J = d;
	m->t_end_s = t->t_s;
	m->x_prev_m = t->x_m;
	m->f_pc_prev_N = t->f_pc_N;
	m->started = 1;
}

double popc_metrics_pc_rms(const popc_metrics_window *w)
{
	return w->ticks ? popc_sum_squares_rms(&w->pc_sq, (double)w->ticks) : 0.0;
}

double popc_metrics_active_fraction(const popc_metrics_window *w)
{
	return w->ticks ? (double)w->active_ticks / (double)w->ticks : 0.0;
}

double popc_metrics_rendered_stiffness(const popc_metrics *m)
{
	if (!(m->pen_sq_sum_m2 > 0.0))
		return 0.0;
	double k = m->fc_pen_sum_Nm / m->pen_sq_sum_m2;
	return isfinite(k) ? k : 0.0; /* never an inf in a summary cell */
}

double popc_metrics_vsign_rate(const popc_metrics_window *w, double period_s)
{
	return w->contact_ticks ? (double)w->vsign_changes / ((double)w->contact_ticks * period_s)
				: 0.0;
}
