/* The one-port both causalities share (docs/ARCHITECTURE.md, "The port";
 * docs/ADMITTANCE.md).
 *
 * A haptic device meets its virtual environment (VE) at one port whose power
 * is effort x flow, P = f v. Which of the two the device measures and which
 * the VE computes is the port's causality:
 *
 *   impedance:  the device measures motion (flow), the VE returns a force
 *               (effort); the force is held over a period, the motion is
 *               measured as a position increment (controller.h);
 *   admittance: the device measures force (effort), the VE returns a motion
 *               (flow); the velocity is held over a period, the force is
 *               measured at the tick (admittance.h).
 *
 * The passivity observer of either sums effort x flow increments into W, and
 * the passivity controller of either adds, in the variable the VE returns, the
 * correction that dissipates a negative W over the coming period through the
 * measured conjugate: the series PC of impedance causality, f = f_VE + alpha v
 * with alpha v = -W / (v T) (Hannaford and Ryu 2002, eq. 11); the parallel PC
 * of admittance causality, v = v_VE + beta f with beta f = -W / (f T) (eq. 17).
 * Both are the same two inline functions below, with the same floating-point
 * operations the impedance controller has always made (its logs keep their
 * bits: tests/behaviour, tests/bitwise). */
#ifndef POPC_PORT_H
#define POPC_PORT_H

#include "popc/core/compensated.h"

typedef enum popc_causality {
	POPC_CAUSALITY_IMPEDANCE,  /* motion in, force out (the paper's devices; the default) */
	POPC_CAUSALITY_ADMITTANCE, /* force in, motion out */
	POPC_CAUSALITY_COUNT
} popc_causality;

/* Names in scenes ("impedance", "admittance"), index = value, NULL-terminated. */
extern const char *const popc_causality_names[];

/* The observer's step: adds the energy effort x flow_increment (J) to the
 * compensated sum (sum, comp) and returns W rounded to double. Impedance:
 * f_c(k-1) (x(k) - x(k-1)); admittance: f(k) (v T). */
static inline double popc_port_observe(double *sum, double *comp, double effort,
				       double flow_increment)
{
	return popc_compensated_add(sum, comp, effort * flow_increment);
}

/* The PC's correction while W is below threshold: the value c of the
 * returned variable with c x conjugate_increment = threshold - W, so that
 * the coming period dissipates the deficit; 0 when W is not below threshold
 * or the conjugate increment is 0 (never a division by zero). Impedance: the
 * force f_pc over the displacement dx; admittance: the velocity v_pc over the
 * impulse f T. */
static inline double popc_port_pc(double W, double threshold, double conjugate_increment)
{
	if (W < threshold && conjugate_increment != 0.0)
		return (threshold - W) / conjugate_increment;
	return 0.0;
}

#endif
