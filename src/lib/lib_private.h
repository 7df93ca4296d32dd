/* What the files of src/lib share: the public handles' insides and the
 * copy of an internal error into the caller's. */
#ifndef POPC_LIB_PRIVATE_H
#define POPC_LIB_PRIVATE_H

#include <string.h>

#include "popc/popc.h"
#include "popc/scene/scene.h"
#include "popc/util/error.h"

struct popc_lib_scene {
	popc_scene scene;
};

/* Returns st, with err's message copied into out (when both are there). */
static inline int popc_lib_fail(popc_lib_error *out, int st, const popc_error *err)
{
	if (out && st) {
		_Static_assert(sizeof out->msg == sizeof err->msg, "the public message holds the internal one");
		memcpy(out->msg, err->msg, sizeof out->msg);
		out->msg[sizeof out->msg - 1] = '\0';
	}
	return st;
}

/* A message of the library's own, e.g. for a NULL argument. */
int popc_lib_error_set(popc_lib_error *out, int st, const char *what);

#endif
