/* The environment the programs pass to the library layers (env.h). */
#include "popc/programs/env.h"

#include <stdlib.h>

const char *popc_env_data_path(void)
{
	return getenv(POPC_DATA_PATH_ENV);
}

int popc_env_scene_defaults(popc_scene *s, popc_error *err)
{
	popc_scene_defaults(s);
	return popc_scene_set_data_path(s, popc_env_data_path(), POPC_DATA_PATH_ENV, err);
}
