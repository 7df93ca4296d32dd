/* Atomic file replacement (atomic_file.h): temporary file, then rename(2). */
#include "popc/util/atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void atomic_free(popc_atomic_file *a)
{
	free(a->tmp_path);
	free(a->path);
	a->tmp_path = a->path = NULL;
	a->f = NULL;
}

void popc_host_name_for_files(char *buf, size_t cap)
{
	if (gethostname(buf, cap) != 0)
		snprintf(buf, cap, "host");
	buf[cap - 1] = '\0'; /* gethostname need not terminate a cut name */
	for (char *c = buf; *c; c++)
		if (*c == '/')
			*c = '_';
}

int popc_atomic_file_open(popc_atomic_file *a, const char *path, popc_error *err)
{
	a->f = NULL;
	a->path = strdup(path);
	char host[64];
	popc_host_name_for_files(host, sizeof host);
	size_t cap = strlen(path) + sizeof ".tmp.." + strlen(host) + 24;
	a->tmp_path = malloc(cap);
	if (!a->path || !a->tmp_path) {
		atomic_free(a);
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	}
	snprintf(a->tmp_path, cap, "%s.tmp.%s.%ld", path, host, (long)getpid());
	a->f = fopen(a->tmp_path, "w");
	if (!a->f) {
		int st = popc_error_set(err, POPC_ERR_IO, "%s: %s", a->tmp_path, strerror(errno));
		atomic_free(a);
		return st;
	}
	return 0;
}

int popc_atomic_file_commit(popc_atomic_file *a, popc_error *err)
{
	int st = 0;
	if (ferror(a->f) | (fclose(a->f) != 0))
		st = popc_error_set(err, POPC_ERR_IO, "%s: %s", a->tmp_path, strerror(errno));
	if (!st && rename(a->tmp_path, a->path) != 0)
		st = popc_error_set(err, POPC_ERR_IO, "%s: %s", a->path, strerror(errno));
	if (st)
		unlink(a->tmp_path);
	atomic_free(a);
	return st;
}

void popc_atomic_file_abort(popc_atomic_file *a)
{
	fclose(a->f);
	unlink(a->tmp_path);
	atomic_free(a);
}

int popc_write_file_atomic(const char *path, const void *data, size_t n, popc_error *err)
{
	popc_atomic_file a;
	int st = popc_atomic_file_open(&a, path, err);
	if (st)
		return st;
	fwrite(data, 1, n, a.f);
	return popc_atomic_file_commit(&a, err);
}

int popc_mkdir_p(const char *path, popc_error *err)
{
	size_t len = strlen(path);
	char *buf = malloc(len + 1);
	if (!buf)
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	memcpy(buf, path, len + 1);
	int st = 0;
	/* each parent (the text before each '/' but a leading one), then the
	 * directory itself (k == len) */
	for (size_t k = 1; k <= len && !st; k++) {
		if (k < len && buf[k] != '/')
			continue;
		buf[k] = '\0';
		if (mkdir(buf, 0777) != 0 && errno != EEXIST)
			st = popc_error_set(err, POPC_ERR_IO, "cannot create directory %s: %s", buf,
					    strerror(errno));
		if (k < len)
			buf[k] = '/';
	}
	if (len == 0)
		st = popc_error_set(err, POPC_ERR_IO, "cannot create a directory with no name");
	free(buf);
	return st;
}
