/* Names of a teleoperation scene's choices (teleop.h). */
#include "popc/core/teleop.h"

#include <stddef.h>

const char *const popc_teleop_architecture_names[] = {"off", "position-force", "position-position", NULL};
const char *const popc_teleop_link_names[] = {"channel", "direct", NULL};
