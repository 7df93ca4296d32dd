/* File-system helpers of the sweep directory (src/sweep/sweep_files.c):
 * atomic writes, mkdir -p, whole-file reads. They know nothing of sweeps. */
#ifndef POPC_SWEEP_FILES_H
#define POPC_SWEEP_FILES_H

#include <stddef.h>

#include "popc/util/error.h"

/* Writes path atomically: data to "path.tmp.<host>.<pid>", then rename(). */
int popc_sweep_write_atomic(const char *path, const char *data, size_t n, popc_error *err);

/* The temporary name popc_sweep_write_atomic uses for path, unique to this
 * process on this host: shards on several nodes may write the same file
 * (sweep.plan) into a shared directory at once, and pids repeat across
 * nodes. Returns 0, or -1 when it does not fit in cap. */
int popc_sweep_temp_name(char *tmp, size_t cap, const char *path);

/* Creates a directory and its missing parents (mode 0777 less the umask). */
int popc_sweep_mkdir_p(const char *path, popc_error *err);

/* Reads a whole (small: at most 128 MiB) file into *out, NUL-terminated, its
 * length in *out_len; the caller frees. Returns 1, 0 if it does not exist
 * (*out NULL), or a negative popc_status. */
int popc_sweep_read_file(const char *path, char **out, size_t *out_len, popc_error *err);

#endif
