/* The true energy into the virtual environment's port, from the simulated
 * plant's true position (the log's E_port column).
 *
 * Under zero-order hold the command f_c(k) acts unchanged over period k while
 * the device moves from x_true(k) to x_true(k+1), so the energy the VE really
 * absorbed in that period is exactly the integral of f_c v over it:
 *
 *     f_c(k) (x_true(k+1) - x_true(k))      (f_c v > 0: the VE absorbs, as W)
 *
 * E_port(k) = sum over j < k of these, aligned with the observer's W(k) =
 * sum over j < k of f_c(j) (x(j+1) - x(j)) on measured positions: W(k) -
 * E_port(k) is the observer's error at tick k. Summed with the same
 * compensated sum as W (compensated.h). */
#ifndef POPC_PORT_ENERGY_H
#define POPC_PORT_ENERGY_H

#include "popc/core/compensated.h"

typedef struct popc_port_energy {
	int started;
	double x_prev_m;       /* x_true(k-1) */
	double f_c_prev_N;     /* f_c(k-1), held over period k-1 */
	double sum_J, comp_J;  /* compensated running sum */
	double E_J;            /* E_port(k) rounded: sum_J + comp_J */
} popc_port_energy;

static inline void popc_port_energy_init(popc_port_energy *p)
{
	*p = (popc_port_energy){0, 0.0, 0.0, 0.0, 0.0, 0.0};
}

/* E_port(k) at tick k from the true position x_true(k); E_port(0) = 0. */
static inline double popc_port_energy_update(popc_port_energy *p, double x_true_m)
{
	if (p->started)
		p->E_J = popc_compensated_add(&p->sum_J, &p->comp_J,
					      p->f_c_prev_N * (x_true_m - p->x_prev_m));
	p->started = 1;
	p->x_prev_m = x_true_m;
	return p->E_J;
}

/* The command f_c(k) sent at tick k, held over the coming period. */
static inline void popc_port_energy_commit(popc_port_energy *p, double f_c_N)
{
	p->f_c_prev_N = f_c_N;
}

#endif
