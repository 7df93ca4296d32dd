/* File-system helpers of the sweep directory (src/sweep/sweep_files.c):
 * whole-file reads. They know nothing of sweeps. Atomic writes and mkdir -p
 * are popc/util/atomic_file.h's. */
#ifndef POPC_SWEEP_FILES_H
#define POPC_SWEEP_FILES_H

#include <stddef.h>

#include "popc/util/error.h"

/* Reads a whole (small: at most 128 MiB) file into *out, NUL-terminated, its
 * length in *out_len; the caller frees. Returns 1, 0 if it does not exist
 * (*out NULL), or a negative popc_status. */
int popc_sweep_read_file(const char *path, char **out, size_t *out_len, popc_error *err);

#endif
