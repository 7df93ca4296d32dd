/* Files that appear whole or not at all: written to a temporary name next to
 * the file, in the same directory (so on the same file system), then renamed
 * over it, so a reader (another shard, a resumed sweep, a merge) never sees
 * half a file. Not fsynced: a crash of the machine may leave the old file or
 * an empty one, never a mix. */
#ifndef POPC_UTIL_ATOMIC_FILE_H
#define POPC_UTIL_ATOMIC_FILE_H

#include <stddef.h>
#include <stdio.h>

#include "popc/util/error.h"

typedef struct popc_atomic_file {
	FILE *f;        /* write the contents here */
	char *tmp_path; /* "<path>.tmp.<host>.<pid>" */
	char *path;
} popc_atomic_file;

/* This host's name as part of a file name ('/' made '_'; "host" when it has
 * none), cut to cap - 1 characters: with the pid it names a process across
 * the nodes that share a directory. */
void popc_host_name_for_files(char *buf, size_t cap);

/* Opens a temporary file for path. The name is unique to this process on this
 * host: shards on several nodes may write the same file (sweep.plan) into a
 * shared directory at once, and pids repeat across nodes. */
int popc_atomic_file_open(popc_atomic_file *a, const char *path, popc_error *err);

/* Closes the temporary file and renames it to the path; on any error (also a
 * write error met earlier) removes it and leaves the path as it was. Frees a
 * either way. */
int popc_atomic_file_commit(popc_atomic_file *a, popc_error *err);

/* Closes and removes the temporary file; frees a. */
void popc_atomic_file_abort(popc_atomic_file *a);

/* Writes data (n bytes) to path atomically. */
int popc_write_file_atomic(const char *path, const void *data, size_t n, popc_error *err);

/* Creates a directory and its missing parents (mode 0777 less the umask), the
 * directory an atomic file is then written into. An existing one is fine. */
int popc_mkdir_p(const char *path, popc_error *err);

#endif
