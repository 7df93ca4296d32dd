/* Position-drift compensation within the observer's energy (tdpa_drift.h
 * has the law and its sources). */
#include "popc/core/tdpa_drift.h"

#include <math.h>
#include <stddef.h>

const char *const popc_drift_law_names[] = {"off", "artigas2010", "coelho2018", NULL};

double popc_drift_velocity(const popc_tdpa_side *s, const popc_drift_config *cfg, double u,
			   double c, double T, double x_rx, double x_cmd)
{
	if (cfg->law == POPC_DRIFT_OFF || !isfinite(x_rx) || !isfinite(x_cmd) || !isfinite(u) ||
	    !isfinite(c) || !(T > 0.0))
		return 0.0;
	/* the drift after this tick's proposed motion, and all of it as a velocity */
	double v = (x_rx - (x_cmd + u * T)) / T;
	double lim = cfg->v_max_mps;
	if (cfg->law == POPC_DRIFT_COELHO2018 && cfg->ratio * fabs(u) < lim)
		lim = cfg->ratio * fabs(u);
	if (!isfinite(v))
		return 0.0;
	if (fabs(v) > lim)
		v = v > 0.0 ? lim : -lim;
	/* the energy it would deliver, v c T, at most what the observer spares
	 * after the proposed output: W_0 with u's energy counted */
	const double e = v * c * T;
	if (e > 0.0) {
		const double e0 = u * c * T;
		const double W0 = s->remote_in_J + s->excess_J -
				  (popc_energy_flow_out(&s->flow) + (e0 > 0.0 ? e0 : 0.0));
		if (!(W0 > 0.0))
			return 0.0;
		if (e > W0)
			v = W0 / (c * T); /* same sign as v: c T has v's sign here */
	}
	return v + 0.0; /* never -0 */
}

popc_tdpa_step popc_drift_port(popc_tdpa_side *s, const popc_drift_config *cfg, double remote_in_J,
			       double u, double c, double T, int pc_on, double x_rx, double x_cmd,
			       double *v_dc_out)
{
	popc_tdpa_receive(s, remote_in_J);
	const double v_dc = popc_drift_velocity(s, cfg, u, c, T, x_rx, x_cmd);
	*v_dc_out = v_dc;
	const double uc = u + v_dc;
	return pc_on ? popc_tdpa_correct(s, uc, c, T) : popc_tdpa_observe(s, uc, c, T);
}
