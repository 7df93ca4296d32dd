/* Names of the virtual environments (environment.h); the force is inline. */
#include "popc/core/environment.h"

#include <stddef.h>

const char *const popc_environment_kind_names[] = {"wall", "spring", NULL};
