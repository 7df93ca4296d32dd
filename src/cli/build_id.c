/* Which popc this is: its version and build id (popc_build_id.h.in). */
#include "cli.h"
#include "popc_build_id.h"
#include "popc_config.h"

const char *popc_cli_version(void)
{
	return POPC_VERSION;
}

const char *popc_cli_build_id(void)
{
	return POPC_BUILD_ID;
}
