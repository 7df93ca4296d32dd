/* Streaming summary metrics of a run or a log: the numbers the end-of-run
 * summary prints and that popc-analyze compare tabulates. Memory is constant
 * in the length of the run. */
#ifndef POPC_METRICS_H
#define POPC_METRICS_H

#include <stdio.h>

#include "popc/core/controller.h"
#include "popc/core/environment.h"
#include "popc/core/sum_squares.h"

typedef struct popc_metrics_window {
	long long ticks, active_ticks;
	popc_sum_squares pc_sq;     /* sum f_pc^2, finite for any finite f_pc */
	double pc_max_N;            /* max |f_pc| */
	long long vsign_changes;    /* sign changes of the moving displacement, in contact */
	long long contact_ticks;
} popc_metrics_window;

typedef struct popc_metrics {
	double period_s;
	double late_from_s;         /* start of the "late" window (low-velocity phase) */
	popc_environment env;
	popc_metrics_window all, late;
	double pc_energy_J;         /* sum f_pc(k-1) (x(k) - x(k-1)): energy the PC dissipated */
	double w_minus_eref_min_J, w_minus_eref_end_J;
	double t_end_s;
	/* rendered stiffness: least squares of f_c = K_r p through the origin
	 * over the ticks in contact, p = x - environment.position */
	double fc_pen_sum_Nm, pen_sq_sum_m2;
	/* running state */
	int started;
	double x_prev_m, f_pc_prev_N;
	int last_sign;
} popc_metrics;

/* late_from_s: ticks at t >= late_from_s also count in the late window. */
void popc_metrics_init(popc_metrics *m, const popc_environment *env, double period_s,
		       double late_from_s);
void popc_metrics_add(popc_metrics *m, const popc_tick *t);

double popc_metrics_pc_rms(const popc_metrics_window *w);
double popc_metrics_active_fraction(const popc_metrics_window *w);
/* The stiffness the device received: sum f_c p / sum p^2 over the ticks in
 * contact (N/m; 0 without penetration). Equals environment.stiffness for
 * variant none on a wall without damping. */
double popc_metrics_rendered_stiffness(const popc_metrics *m);
/* Velocity sign changes per second of contact. */
double popc_metrics_vsign_rate(const popc_metrics_window *w, double period_s);

#endif
