/* The environment the programs read on the library's behalf: the library
 * layers read none (docs/LIBRARY.md, "What the library never does"), so the
 * programs take POPC_DATA_PATH here and pass it in (a scene's data_path,
 * data_path.h's data_path arguments). */
#ifndef POPC_PROGRAMS_ENV_H
#define POPC_PROGRAMS_ENV_H

#include "popc/scene/scene.h"
#include "popc/util/error.h"

/* The variable that names the data directories (popc(1), ENVIRONMENT). */
#define POPC_DATA_PATH_ENV "POPC_DATA_PATH"

/* POPC_DATA_PATH's value, or NULL when it is not set. */
const char *popc_env_data_path(void);

/* popc_scene_defaults, then the data path from POPC_DATA_PATH: every scene
 * a program reads starts here. POPC_ERR_INVALID when POPC_DATA_PATH is
 * longer than a scene holds (the message names the variable). */
int popc_env_scene_defaults(popc_scene *s, popc_error *err);

#endif
