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

/* A whole file's bytes [text, text + len), NOT NUL-terminated: a large
 * regular file is mapped (its page cache pages, no copy), anything else read
 * (popc_sweep_read_file). For files that are appended to, never cut short (a
 * mapped file cut under the mapping would end the process with SIGBUS):
 * sweeps' rows files. */
typedef struct popc_sweep_file_view {
	const char *text;
	size_t len;
	void *map;      /* the mapping, or NULL */
	size_t map_len;
	char *buf;      /* the text read (or given), or NULL */
} popc_sweep_file_view;

/* Returns 1, 0 if the file does not exist, or a negative popc_status. */
int popc_sweep_view_file(const char *path, popc_sweep_file_view *v, popc_error *err);
void popc_sweep_file_view_free(popc_sweep_file_view *v);

#endif
