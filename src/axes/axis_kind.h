/* One kind of axis as the factory (axis.c) knows it; each backend defines
 * its own descriptor next to its code, and a build without a backend's
 * library links a descriptor whose create() says so (modbus_absent.c).
 * Private to the axes layer. */
#ifndef POPC_AXIS_KIND_H
#define POPC_AXIS_KIND_H

#include "popc/axes/axis.h"

typedef struct popc_axis_kind {
	const char *name;   /* axis.kind in a scene */
	int simulated;      /* popc_axis_is_simulated */
	int (*create)(popc_axis **out, const popc_scene *s, const popc_axis_create_options *opt,
		      popc_error *err);
} popc_axis_kind;

extern const popc_axis_kind popc_axis_kind_sim;

/* The simulated admittance-type device, which the sim kind makes for a
 * scene with device.causality = admittance, is declared in
 * popc/axes/sim_axis.h (libpopc makes it too). */
extern const popc_axis_kind popc_axis_kind_modbus;

#endif
