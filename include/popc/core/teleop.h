/* Bilateral teleoperation over a delayed channel (issue 26,
 * docs/TELEOPERATION.md): the names of a teleoperation scene's choices, and
 * the one tick of each side's network port. The channel is channel.h, the
 * passivity of the network tdpa.h; this header ties them to the two
 * devices' variables.
 *
 * Position-force architecture (Artigas, Ryu, Preusche et al. 2010): the
 * master (impedance type: encoder in, force out) sends its velocity
 * v_m(k) = (x_m(k) - x_m(k-1)) / T and position each tick; the slave
 * (admittance type: force sensor in, motion out) takes the velocity it
 * holds as its velocity command, its servo's position command the sum of
 * those commands times T; the slave sends the force f_s its sensor reads
 * (the environment's force on the slave), which the master renders,
 * f_c = -f_s (the device receives -f_c: log_columns.h).
 *
 * Each port in tdpa.h's orientation (u the network's output, c the
 * conjugate, u c the power the network delivers to the device):
 *   master: u = f_c, c = -v_m (the device receives -f_c, moving at v_m);
 *   slave:  u = v_c, c = -f_s (the slave pushes the environment with -f_s). */
#ifndef POPC_CORE_TELEOP_H
#define POPC_CORE_TELEOP_H

#include "popc/core/tdpa.h"
#include "popc/core/tdpa_drift.h"

typedef enum popc_teleop_architecture {
	POPC_TELEOP_OFF,            /* not a teleoperation scene (every one-port scene) */
	POPC_TELEOP_POSITION_FORCE, /* master motion forward, slave force back */
	POPC_TELEOP_POSITION_POSITION, /* motion both ways, a coupling controller at each side */
	POPC_TELEOP_ARCHITECTURE_COUNT
} popc_teleop_architecture;

/* Names in scenes ("off", "position-force", "position-position"), index = value, NULL-terminated. */
extern const char *const popc_teleop_architecture_names[];

typedef enum popc_teleop_link {
	POPC_TELEOP_LINK_CHANNEL, /* each direction a popc_channel ([forward], [backward]) */
	POPC_TELEOP_LINK_DIRECT,  /* what is sent at tick k is received at tick k: no channel */
} popc_teleop_link;

extern const char *const popc_teleop_link_names[];

/* The packet's values (channel.h's value[]) of each direction. */
enum {
	POPC_TELEOP_FWD_X = 0, /* master position x_m(k), m */
	POPC_TELEOP_FWD_V = 1, /* master velocity v_m(k), m/s */
	POPC_TELEOP_BWD_F = 0, /* slave sensed force f_s(k), N */
	POPC_TELEOP_BWD_X = 1, /* position-position: slave position x_s(k), m */
	POPC_TELEOP_BWD_V = 2, /* position-position: slave velocity v_s(k), m/s */
};

/* Bits of a teleoperation log's flags column: each side's tdpa.h flags, and
 * the channel's events of the tick. */
enum popc_teleop_flag {
	POPC_TELEOP_FLAG_M_ACTIVE = 1,   /* the master's PC corrected f_c */
	POPC_TELEOP_FLAG_M_CLAMPED = 2,  /* ... at its bound (no guarantee this tick) */
	POPC_TELEOP_FLAG_S_ACTIVE = 4,   /* the slave's PC corrected v_c */
	POPC_TELEOP_FLAG_S_CLAMPED = 8,
	POPC_TELEOP_FLAG_FWD_LOST = 16,  /* the packet the master sent this tick is lost */
	POPC_TELEOP_FLAG_BWD_LOST = 32,  /* the packet the slave sent this tick is lost */
	POPC_TELEOP_FLAG_FWD_FRESH = 64, /* the slave received a newer packet this tick */
	POPC_TELEOP_FLAG_BWD_FRESH = 128,/* the master received a newer packet this tick */
};

/* One side's port for a tick, in either architecture (u a velocity at the
 * position-force slave, a force at every other port): the received energy
 * first (popc_tdpa_receive), then the output u against the conjugate c,
 * corrected when pc_on (tdpa.h) or only observed when not (d = 0, the
 * energies split the same way, W may go below 0). The same function online
 * and in popc-analyze energy --check. */
static inline popc_tdpa_step popc_teleop_port(popc_tdpa_side *s, double remote_in_J, double u,
					      double c, double T, int pc_on)
{
	popc_tdpa_receive(s, remote_in_J);
	return pc_on ? popc_tdpa_correct(s, u, c, T) : popc_tdpa_observe(s, u, c, T);
}

/* Position-position (Artigas, Ryu, Preusche and Hirzinger, Presence 19(5),
 * 2010; docs/TELEOPERATION.md, "Position-position"): the coupling
 * controller of a side, a spring K_c and a damper B_c between the remote
 * position and velocity it holds and its own measured ones, the force on its
 * own device,
 *
 *     F = K_c (x_rx - x) + B_c (v_rx - v),
 *
 * at the master F_M (the device receives -f_c: f_e = -F_M, c = -v_m), at the
 * slave F_S (its force command: u = F_S, c = v_s). Both ports are then of
 * impedance type (a force out, a velocity in), each stepped by
 * popc_teleop_port, the same function as position-force's. The same
 * expression online and in popc-analyze energy --check. */
static inline double popc_teleop_coupling_N(double K_Npm, double B_Nspm, double x_rx_m, double x_m,
					    double v_rx_mps, double v_mps)
{
	return K_Npm * (x_rx_m - x_m) + B_Nspm * (v_rx_mps - v_mps);
}

/* The two-port condition at a side after its tick (Ryu et al. 2010): what
 * left the network here never exceeds what the other side put in, as
 * received, E_out,local - E_in,remote <= tol; the margin remote - out (J). */
static inline double popc_teleop_margin_J(const popc_tdpa_side *s)
{
	return s->remote_in_J + s->excess_J - popc_energy_flow_out(&s->flow);
}

/* The name of a teleoperation run's controllers, the log's `variant` line and
 * the summary's variant cell: "tdpa" (the PCs on) or "none" (observed only),
 * with "-" and the drift law's name when one compensates (tdpa_drift.h's
 * names: "tdpa-coelho2018"). */
const char *popc_teleop_variant_name(int tdpa_on, popc_drift_law drift_law);

/* Whether the condition holds within rounding: the margin remote_J - out_J
 * at least -(1e-12 J + 1e-12 x the larger energy). When the PC sets this
 * tick's output to exactly what W allows, out = remote up to the rounding of
 * u' c T and of the compensated sums, a few units in the last place of the
 * energies (docs/TELEOPERATION.md). */
static inline int popc_teleop_condition_holds(double remote_J, double out_J)
{
	const double big = remote_J > out_J ? remote_J : out_J;
	return remote_J - out_J >= -(1e-12 + 1e-12 * big);
}

#endif
