/* Time-domain passivity of a two-port network (issue 26): the energy at each
 * port split into input and output, the receiver's monotone copy of the
 * other side's input energy, and the network passivity controller at a port
 * of either causality. From Ryu, Artigas and Preusche, "A passive bilateral
 * control scheme for a teleoperator with time-varying communication delay",
 * Mechatronics 20(7), 2010 (the energy split and the observer of each side
 * against the received input energy of the other), after Ryu, Kwon and
 * Hannaford, IEEE T-RA 20(2), 2004 (the PO/PC at the ports of a network).
 *
 * Orientation: at a port the network sets an output u (a force at an
 * impedance-type master, a velocity at an admittance-type slave) and the
 * device's conjugate c is measured (a velocity, a force), signed so that
 * u c is the power the network delivers through the port. Over a period T
 * the energy e = u c T leaves the network when positive (E_out += e) and
 * enters it when negative (E_in -= e).
 *
 * The network is passive when what leaves it at each side is bounded by what
 * entered it at the other, as received: E_out,S(k) <= E_in,M(k - D_f) and
 * E_out,M(k) <= E_in,S(k - D_b) (Ryu et al. 2010, the condition on the two
 * observers). Each side receives the other's E_in with every packet and
 * keeps the largest received (a cumulative energy never decreases, so a lost,
 * late or reordered packet can only keep an older, smaller value: safe). The
 * observer of a side is W = E_in,remote(received) - E_out,local with this
 * tick's output counted, and when W < 0 the PC corrects u by the amount that
 * makes this tick's output exactly what W allows:
 *
 *     u' = u + d,   d c T = W   (d = W / (c T)),
 *
 * which is the one-port PC of port.h (popc_port_pc with threshold 0 and the
 * conjugate increment -c T): the series PC's alpha v at a master, the
 * parallel PC's beta f at a slave. With |d| bounded the guarantee holds only
 * while the bound is not reached (the step says when it was). */
#ifndef POPC_CORE_TDPA_H
#define POPC_CORE_TDPA_H

#include "popc/core/compensated.h"
#include "popc/core/port.h"

/* A port's energy split, each a compensated sum (J). */
typedef struct popc_energy_flow {
	double in_J, in_comp;
	double out_J, out_comp;
} popc_energy_flow;

/* Adds the energy e_J the network delivered through the port (negative:
 * received): to E_out when positive, to E_in (as -e_J) when negative. */
static inline void popc_energy_flow_add(popc_energy_flow *f, double e_J)
{
	if (e_J > 0.0)
		popc_compensated_add(&f->out_J, &f->out_comp, e_J);
	else if (e_J < 0.0)
		popc_compensated_add(&f->in_J, &f->in_comp, -e_J);
}

static inline double popc_energy_flow_in(const popc_energy_flow *f)
{
	return f->in_J + f->in_comp;
}

static inline double popc_energy_flow_out(const popc_energy_flow *f)
{
	return f->out_J + f->out_comp;
}

/* One side of the network. */
typedef struct popc_tdpa_side {
	popc_energy_flow flow; /* this port's */
	double remote_in_J;    /* the other side's E_in, the largest received */
	double bound;          /* |d| at most this (> 0), or 0: unbounded */
	double excess_J;       /* the passivity excess: energy the side may deliver beyond
				* what it received, E(0) of the passivity definition (0:
				* Ryu et al. 2010's condition; docs/TELEOPERATION.md) */
} popc_tdpa_side;

enum {
	POPC_TDPA_ACTIVE = 1,  /* W < 0: u corrected */
	POPC_TDPA_CLAMPED = 2, /* |d| reached the bound: the guarantee did not hold this tick */
};

typedef struct popc_tdpa_step {
	double u;    /* the output sent to the device: u + d */
	double d;    /* the PC's correction */
	double W_J;  /* the observer before the correction */
	double e_J;  /* the energy u c T delivered (after the correction) */
	int flags;   /* POPC_TDPA_* */
} popc_tdpa_step;

void popc_tdpa_side_init(popc_tdpa_side *s, double bound);

/* popc_tdpa_side_init with a passivity excess E_0 >= 0 (J): the observer is
 * W = E_in,remote + E_0 - E_out (E_0 = 0: the same bits as without). */
void popc_tdpa_side_init_excess(popc_tdpa_side *s, double bound, double excess_J);

/* A received E_in of the other side: kept when larger (a non-finite value,
 * which no sender makes, is ignored). */
void popc_tdpa_receive(popc_tdpa_side *s, double remote_in_J);

/* One tick: the network's proposed output u, the measured conjugate c, the
 * period T. Corrects u when the observer is negative, then adds the energy
 * delivered to the port's split. u and c finite. */
popc_tdpa_step popc_tdpa_correct(popc_tdpa_side *s, double u, double c, double T);

/* The same tick with the PC off: the observer as popc_tdpa_correct computes
 * it, u delivered unchanged (d = 0, no flag), its energy added to the split. */
popc_tdpa_step popc_tdpa_observe(popc_tdpa_side *s, double u, double c, double T);

#endif
