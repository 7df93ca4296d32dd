/* What the files of src/lib share: the public handles' insides, the
 * copy of an internal error into the caller's, and the impedance tick's two
 * halves (the port's step and the device's exchange), inline so that
 * popc_lib_port_step, popc_lib_sim_exchange and the two in one
 * (popc_lib_sim_tick, lib_loop.c) are each one call deep. */
#ifndef POPC_LIB_PRIVATE_H
#define POPC_LIB_PRIVATE_H

#include <stddef.h>
#include <string.h>

#include "popc/axes/axis.h"
#include "popc/core/admittance.h"
#include "popc/core/controller.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/popc.h"
#include "popc/scene/scene.h"
#include "popc/util/error.h"

struct popc_lib_scene {
	popc_scene scene;
};

/* Returns st, with err's message copied into out (when both are there). */
static inline int popc_lib_fail(popc_lib_error *out, int st, const popc_error *err)
{
	if (out && st) {
		_Static_assert(sizeof out->msg == sizeof err->msg, "the public message holds the internal one");
		memcpy(out->msg, err->msg, sizeof out->msg);
		out->msg[sizeof out->msg - 1] = '\0';
	}
	return st;
}

/* A message of the library's own, e.g. for a NULL argument. */
int popc_lib_error_set(popc_lib_error *out, int st, const char *what);

struct popc_lib_port {
	union {
		popc_controller *ctl; /* sized for its variant and window at create */
		struct {
			popc_admittance_config cfg;
			popc_admittance_controller ctl; /* initialised at tick 0 */
		} adm;
	} u;
	popc_lib_causality causality;
	double period_s, resolution_m;
	long long k;         /* the next tick */
};

struct popc_lib_sim {
	popc_axis *axis;
	int admittance;   /* the admittance-type device: a velocity is exchanged */
	int port_energy;  /* E_port kept (not POPC_LIB_SIM_NO_PORT_ENERGY) */
	/* E_port as popc_run computes it: the update with tick k's true
	 * position, then the commit of the command sent after it */
	popc_port_energy port;
};

/* The public tick is the internal one field by field (the internal layout
 * may change; the public one may not). Copied field by field, not as one
 * struct: the whole struct's copy (memcpy) had fewer instructions but
 * measured about 12 ns a tick slower, likely its 16-byte loads of the
 * stores popc_controller_step has just made failing store-to-load
 * forwarding (docs/BENCHMARKS.md 11.1). The asserts keep the two alike. */
#define POPC_LIB_SAME_FIELD(pub, in)                                                                \
	_Static_assert(offsetof(popc_lib_tick, pub) == offsetof(popc_tick, in) &&                  \
			       sizeof(((popc_lib_tick *)0)->pub) == sizeof(((popc_tick *)0)->in),   \
		       "popc_lib_tick." #pub " is popc_tick." #in)
POPC_LIB_SAME_FIELD(t_s, t_s);
POPC_LIB_SAME_FIELD(x_m, x_m);
POPC_LIB_SAME_FIELD(count, count);
POPC_LIB_SAME_FIELD(v_mps, v_mps);
POPC_LIB_SAME_FIELD(f_e_N, f_e_N);
POPC_LIB_SAME_FIELD(f_pc_N, f_pc_N);
POPC_LIB_SAME_FIELD(f_c_N, f_c_N);
POPC_LIB_SAME_FIELD(W_J, W_J);
POPC_LIB_SAME_FIELD(E_ref_J, E_ref_J);
POPC_LIB_SAME_FIELD(flags, flags);
_Static_assert(sizeof(popc_lib_tick) == sizeof(popc_tick), "popc_lib_tick is popc_tick");
#undef POPC_LIB_SAME_FIELD

/* The tick's halves are inlined into each caller, popc_lib_sim_tick too,
 * whatever the compiler's estimate of their size (a call and its register
 * saves were some 20 instructions of a tick: docs/BENCHMARKS.md 11.1). */
#if defined(__GNUC__) || defined(__clang__)
#define POPC_LIB_INLINE static inline __attribute__((always_inline))
#else
#define POPC_LIB_INLINE static inline
#endif

/* Tick k of an impedance port (p->causality checked by the caller): t and x
 * exactly as popc_run computes them, k T and count x resolution. */
POPC_LIB_INLINE void popc_lib_port_step_impedance(popc_lib_port *p, long long count,
						popc_lib_tick *out)
{
	popc_tick t;
	t.t_s = (double)p->k * p->period_s;
	popc_controller_step(p->u.ctl, count, popc_encoder_position(count, p->resolution_m), &t);
	p->k++;
	out->t_s = t.t_s;
	out->x_m = t.x_m;
	out->count = t.count;
	out->v_mps = t.v_mps;
	out->f_e_N = t.f_e_N;
	out->f_pc_N = t.f_pc_N;
	out->f_c_N = t.f_c_N;
	out->W_J = t.W_J;
	out->E_ref_J = t.E_ref_J;
	out->flags = t.flags;
}

/* The public sample of an impedance device, with E_port(k) updated by the
 * true position of the tick sampled; 0 without E_port (as popc_run leaves
 * the summary's E_port unmade when nothing reads it). */
POPC_LIB_INLINE void popc_lib_sample_out(popc_lib_sim *sim, const popc_axis_sample *in,
				       popc_lib_sample *out)
{
	out->count = in->count;
	out->x_true_m = in->x_true_m;
	out->E_port_J = sim->port_energy ? popc_port_energy_update(&sim->port, in->x_true_m) : 0.0;
}

/* The exchange of an impedance device (sim->admittance and f_c_N's
 * finiteness checked by the caller): E_port's commit of the command, the
 * axis' exchange, the next sample. The sample's dissipated_J, which the
 * simulated axis always sets (sim_sample) and the library never reads, is
 * not preset to NaN as popc_run presets it for every axis kind. */
POPC_LIB_INLINE int popc_lib_sim_exchange_impedance(popc_lib_sim *sim, double f_c_N,
						   popc_lib_sample *next, popc_lib_error *err)
{
	popc_error e;
	popc_axis_sample smp;
	popc_port_energy_commit(&sim->port, f_c_N);
	int st = sim->axis->ops->exchange(sim->axis, f_c_N, &smp, &e);
	if (st)
		return popc_lib_fail(err, st, &e);
	popc_lib_sample_out(sim, &smp, next);
	return 0;
}

#endif
