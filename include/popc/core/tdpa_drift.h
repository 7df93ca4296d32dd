/* Position-drift compensation at an admittance-type port of the two-port
 * network (issue 26, docs/TELEOPERATION.md "Drift compensation"), within the
 * energy the port's observer allows, so that the two-port condition of
 * tdpa.h still holds at every tick.
 *
 * The admittance-type PC at the slave adds a velocity d to the velocity the
 * network proposes; the position command, the sum of the commands times T,
 * keeps every d: the slave ends short of (or past) the master, the drift.
 * After Artigas, Ryu, Preusche and Hirzinger, "Position drift compensation
 * in time domain passivity based teleoperation", IROS 2010: the drift is the
 * difference between the position the master sent and the position the
 * slave is commanded to, and a compensating velocity v_dc is added to the
 * proposed output only as far as the observer has energy to spare for it;
 * Coelho, Singh, Kirchner, Ott, Preusche and Artigas, "Smoother
 * position-drift compensation for time domain passivity approach based
 * teleoperation", IROS 2018: the same energy limit, and the compensating
 * velocity at most a fraction of the velocity the slave is commanded to, so
 * the drift is taken back while the slave moves and never as a jump.
 *
 * In tdpa.h's orientation (u the network's output, c the measured conjugate,
 * u c T the energy delivered), at a port whose output is a velocity and
 * whose position command is x_cmd(k+1) = x_cmd(k) + u' T:
 *
 *     drift  x_d = x_rx - (x_cmd + u T)         (x_rx: the position received)
 *     wanted v_w = x_d / T                       (all of it this tick)
 *     limit  |v_dc| <= v_max                     (artigas2010)
 *            |v_dc| <= min(v_max, rho |u|)       (coelho2018)
 *     energy v_dc c T <= max(W_0, 0)             (W_0 the observer with u)
 *
 * where W_0 = E_in,remote + E_excess - (E_out + max(u c T, 0)). A v_dc that
 * takes energy in (v_dc c <= 0) costs nothing and is limited only by its
 * velocity bound. The port then steps u + v_dc as tdpa.h does (observer, PC
 * when W < 0), so the condition holds whatever the rounding of v_dc. The
 * compensation costs nothing in free space (c = 0): the Artigas law then
 * takes the whole drift back in one period (a jump of the position command),
 * the Coelho law in steps of at most rho |u|. */
#ifndef POPC_CORE_TDPA_DRIFT_H
#define POPC_CORE_TDPA_DRIFT_H

#include "popc/core/tdpa.h"

typedef enum popc_drift_law {
	POPC_DRIFT_OFF,          /* no compensation: the drift stays (every scene before) */
	POPC_DRIFT_ARTIGAS2010,  /* the whole drift within energy and v_max */
	POPC_DRIFT_COELHO2018,   /* ... and at most rho |u| a tick */
	POPC_DRIFT_LAW_COUNT
} popc_drift_law;

/* Names in scenes ("off", "artigas2010", "coelho2018"), index = value,
 * NULL-terminated. */
extern const char *const popc_drift_law_names[];

typedef struct popc_drift_config {
	popc_drift_law law;
	double v_max_mps; /* |v_dc| at most this (> 0) */
	double ratio;     /* coelho2018: |v_dc| at most ratio |u| (> 0) */
} popc_drift_config;

/* The compensating velocity v_dc of a tick (the equations above): side after
 * popc_tdpa_receive of this tick, u the proposed output, c the conjugate, T
 * the period, x_rx the position received, x_cmd the position command before
 * this tick's output. 0 with the law off, and when any input is not finite. */
double popc_drift_velocity(const popc_tdpa_side *s, const popc_drift_config *cfg, double u,
			   double c, double T, double x_rx, double x_cmd);

/* A drift-compensated port's tick: the received energy, v_dc, then u + v_dc
 * stepped as popc_teleop_port does (corrected when pc_on, else observed).
 * *v_dc_out the compensation; the step's u is u + v_dc + d. The same function
 * online and in popc-analyze energy --check. */
popc_tdpa_step popc_drift_port(popc_tdpa_side *s, const popc_drift_config *cfg, double remote_in_J,
			       double u, double c, double T, int pc_on, double x_rx, double x_cmd,
			       double *v_dc_out);

#endif
