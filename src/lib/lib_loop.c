/* libpopc: a simulated impedance loop's tick in one call (popc/popc.h,
 * popc_lib_sim_tick): the port's step and the device's exchange that
 * popc_lib_port_step and popc_lib_sim_exchange make, in the order popc_run's
 * loop makes them (src/run/run.c), with the handles' kinds checked once and
 * no second call or finiteness check between them (docs/BENCHMARKS.md
 * section 11.1: the wrappers' cost). */
#include "lib_private.h"

POPC_API int popc_lib_sim_tick(popc_lib_port *p, popc_lib_sim *sim, popc_lib_sample *smp,
			       popc_lib_tick *out, popc_lib_error *err)
{
	if (p->causality != POPC_LIB_CAUSALITY_IMPEDANCE || sim->admittance)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_sim_tick: the port and the device must be "
					  "impedance-type (an admittance loop: "
					  "popc_lib_port_step_admittance, "
					  "popc_lib_sim_exchange_admittance); nothing stepped");
	popc_lib_port_step_impedance(p, smp->count, out);
	/* no finiteness check of the command, which popc_lib_sim_exchange makes
	 * of a caller's: the port's f_c is finite whatever the count
	 * (popc_controller_step commands 0 N when f_e overflowed) */
	return popc_lib_sim_exchange_impedance(sim, out->f_c_N, smp, err);
}
