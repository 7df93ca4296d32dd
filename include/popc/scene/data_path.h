/* Installed data found by name (src/scene/data_path.c): the scenes in
 * DATADIR/popc/scenes and the drive maps in DATADIR/popc/drives, so that an
 * installed popc runs `popc run paper` and `--map generic` from any directory.
 *
 * The rule (popc(1), popc-scene(5)):
 *   - a name with a '/' is a path and is never looked up;
 *   - a name that exists where a relative path points (the working directory
 *     for a command-line argument, the scene file's directory for axis.map in
 *     a scene file) is that file: a local file always wins;
 *   - otherwise each data directory in turn is asked for KIND/NAME, then
 *     KIND/NAME.ini (unless NAME ends in .ini). The data directories are
 *     the data path's colon-separated entries, an empty entry standing for
 *     the built-in one (MANPATH's convention: "POPC_DATA_PATH=$HOME/popc:"
 *     searches $HOME/popc, then the installed data); with an empty or NULL
 *     data path, the built-in POPC_DATADIR (meson's prefix/datadir/popc)
 *     alone. The data path is the caller's (an argument below; a scene's
 *     data_path): the programs pass POPC_DATA_PATH, the library layers read
 *     no environment.
 * A name found is given as an absolute path, which is what the resolved scene
 * (a log header, a sweep's scene.ini and plan) then records. */
#ifndef POPC_SCENE_DATA_PATH_H
#define POPC_SCENE_DATA_PATH_H

#include <stddef.h>
#include <stdio.h>

#include "popc/util/error.h"

typedef enum popc_data_kind {
	POPC_DATA_SCENES, /* DIR/scenes */
	POPC_DATA_DRIVES, /* DIR/drives: Modbus register maps */
	POPC_DATA_TRACES, /* DIR/traces: a channel's delay traces (forward.trace) */
} popc_data_kind;

/* The subdirectory name of a kind: "scenes", "drives" or "traces". */
const char *popc_data_kind_dir(popc_data_kind kind);

/* Looks name up by the rule above. base_dir: the directory a relative name is
 * relative to (NULL: the working directory). Returns 1 with the absolute path
 * of the data file in out; 0 when name is not looked up (empty, holds a '/',
 * or exists relative to base_dir: use it as it is); POPC_ERR_INVALID when it
 * is looked up and found nowhere, err naming every place searched. */
int popc_data_find(popc_data_kind kind, const char *name, const char *base_dir,
		   const char *data_path, char *out, size_t cap, popc_error *err);

/* The data directories in search order, ':'-separated, as the help and the
 * error messages name them. */
void popc_data_dirs(const char *data_path, char *out, size_t cap);

/* Writes "NAME\tPATH\n" for every file of kind in the data directories (NAME
 * without a trailing .ini), the first directory's winning where two hold a
 * name, sorted by name within each directory. A name or path holding a
 * control character (a tab or a newline would break the NAME<TAB>PATH
 * lines) is not listed: a note on notes (when not NULL), after who, names
 * it, its control characters written as \t, \n or \xHH. Returns the count
 * listed. */
int popc_data_list(popc_data_kind kind, const char *data_path, FILE *f, FILE *notes,
		   const char *who);

#endif
