/* The two-port network's time-domain passivity (tdpa.h has the equations). */
#include "popc/core/tdpa.h"

#include <math.h>
#include <string.h>

void popc_tdpa_side_init(popc_tdpa_side *s, double bound)
{
	memset(s, 0, sizeof *s);
	s->bound = bound;
}

void popc_tdpa_side_init_excess(popc_tdpa_side *s, double bound, double excess_J)
{
	popc_tdpa_side_init(s, bound);
	s->excess_J = excess_J;
}

void popc_tdpa_receive(popc_tdpa_side *s, double remote_in_J)
{
	if (isfinite(remote_in_J) && remote_in_J > s->remote_in_J)
		s->remote_in_J = remote_in_J;
}

/* the observer with this tick's output e counted: what may still leave,
 * minus what would */
static double observer_J(const popc_tdpa_side *s, double e)
{
	/* remote + 0.0 is remote's bits (>= +0): no excess, the same W */
	return s->remote_in_J + s->excess_J - (popc_energy_flow_out(&s->flow) + (e > 0.0 ? e : 0.0));
}

popc_tdpa_step popc_tdpa_observe(popc_tdpa_side *s, double u, double c, double T)
{
	popc_tdpa_step st;
	st.e_J = u * c * T;
	st.W_J = observer_J(s, st.e_J);
	st.d = 0.0;
	st.flags = 0;
	st.u = u;
	popc_energy_flow_add(&s->flow, st.e_J);
	return st;
}

popc_tdpa_step popc_tdpa_correct(popc_tdpa_side *s, double u, double c, double T)
{
	popc_tdpa_step st;
	st.W_J = observer_J(s, u * c * T);
	st.flags = 0;
	/* d c T = W: port.h's PC, threshold 0, over the conjugate increment -c T */
	st.d = popc_port_pc(st.W_J, 0.0, -(c * T));
	if (st.d != 0.0) {
		st.flags |= POPC_TDPA_ACTIVE;
		if (s->bound > 0.0 && fabs(st.d) > s->bound) {
			st.d = st.d > 0.0 ? s->bound : -s->bound;
			st.flags |= POPC_TDPA_CLAMPED;
		}
	}
	st.u = u + st.d;
	st.e_J = st.u * c * T;
	popc_energy_flow_add(&s->flow, st.e_J);
	return st;
}
