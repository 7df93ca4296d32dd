/* The port's causality names (port.h). */
#include "popc/core/port.h"

#include <stddef.h>

const char *const popc_causality_names[] = {"impedance", "admittance", NULL};
