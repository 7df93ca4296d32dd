/* Names of a teleoperation scene's choices (teleop.h). */
#include "popc/core/teleop.h"
#include "popc/core/tdpa_drift.h"

#include <stddef.h>

const char *const popc_teleop_architecture_names[] = {"off", "position-force", "position-position", NULL};
const char *const popc_teleop_link_names[] = {"channel", "direct", NULL};

const char *popc_teleop_variant_name(int tdpa_on, popc_drift_law drift_law)
{
	/* index: drift law (tdpa_drift.h's order), then the PCs off or on */
	static const char *const names[][2] = {
		{"none", "tdpa"},
		{"none-artigas2010", "tdpa-artigas2010"},
		{"none-coelho2018", "tdpa-coelho2018"},
	};
	_Static_assert(sizeof names / sizeof names[0] == POPC_DRIFT_LAW_COUNT, "a name per law");
	const unsigned law = (unsigned)drift_law < POPC_DRIFT_LAW_COUNT ? (unsigned)drift_law : 0u;
	return names[law][tdpa_on ? 1 : 0];
}
