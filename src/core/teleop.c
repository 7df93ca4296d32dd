/* Names of a teleoperation scene's choices (teleop.h). */
#include "popc/core/teleop.h"
#include "popc/core/tdpa_drift.h"

#include <stddef.h>

const char *const popc_teleop_architecture_names[] = {"off", "position-force", "position-position", NULL};
const char *const popc_teleop_link_names[] = {"channel", "direct", NULL};

const char *popc_teleop_variant_name(int tdpa_on, int drift_law)
{
	/* index: drift law (tdpa_drift.h's order), then the PCs off or on */
	static const char *const names[][2] = {
		{"none", "tdpa"},
		{"none-artigas2010", "tdpa-artigas2010"},
		{"none-coelho2018", "tdpa-coelho2018"},
	};
	_Static_assert(sizeof names / sizeof names[0] == POPC_DRIFT_LAW_COUNT, "a name per law");
	if (drift_law < 0 || drift_law >= (int)(sizeof names / sizeof names[0]))
		drift_law = 0;
	return names[drift_law][tdpa_on ? 1 : 0];
}
