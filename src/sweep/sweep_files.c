/* File-system helpers of the sweep directory (sweep_files.h). */
#include "popc/sweep/sweep_files.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popc/scene/scene.h" /* POPC_PATH_MAX */

/* A temporary name next to path, unique to this process on this host: shards
 * on several nodes may write the same file (sweep.plan) into a shared
 * directory at once, and pids repeat across nodes. */
int popc_sweep_temp_name(char *tmp, size_t cap, const char *path)
{
	char host[64];
	if (gethostname(host, sizeof host) != 0)
		strcpy(host, "host");
	host[sizeof host - 1] = '\0';
	for (char *c = host; *c; c++)
		if (*c == '/')
			*c = '_';
	return (size_t)snprintf(tmp, cap, "%s.tmp.%s.%ld", path, host, (long)getpid()) < cap ? 0 : -1;
}

int popc_sweep_write_atomic(const char *path, const char *data, size_t n, popc_error *err)
{
	char tmp[POPC_PATH_MAX + 96];
	if (popc_sweep_temp_name(tmp, sizeof tmp, path) != 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: path too long", path);
	int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0666);
	if (fd < 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", tmp, strerror(errno));
	size_t done = 0;
	while (done < n) {
		ssize_t w = write(fd, data + done, n - done);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0) {
			int e = errno;
			close(fd);
			unlink(tmp);
			return popc_error_set(err, POPC_ERR_IO, "%s: %s", tmp, strerror(e));
		}
		done += (size_t)w;
	}
	if (close(fd) != 0 || rename(tmp, path) != 0) {
		int e = errno;
		unlink(tmp);
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(e));
	}
	return 0;
}

int popc_sweep_mkdir_p(const char *path, popc_error *err)
{
	char buf[POPC_PATH_MAX];
	if (strlen(path) >= sizeof buf)
		return popc_error_set(err, POPC_ERR_IO, "%s: path too long", path);
	strcpy(buf, path);
	for (char *p = buf + 1; *p; p++) {
		if (*p != '/')
			continue;
		*p = '\0';
		if (mkdir(buf, 0777) != 0 && errno != EEXIST)
			return popc_error_set(err, POPC_ERR_IO, "cannot create directory %s: %s", buf,
					      strerror(errno));
		*p = '/';
	}
	if (mkdir(buf, 0777) != 0 && errno != EEXIST)
		return popc_error_set(err, POPC_ERR_IO, "cannot create directory %s: %s", buf,
				      strerror(errno));
	return 0;
}

/* Reads a whole (small) file, NUL-terminated. Returns 1, 0 if it does not
 * exist, or a negative popc_status. */
int popc_sweep_read_file(const char *path, char **out, size_t *out_len, popc_error *err)
{
	*out = NULL;
	int fd = open(path, O_RDONLY);
	if (fd < 0) {
		if (errno == ENOENT || errno == ENOTDIR)
			return 0;
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
	}
	size_t cap = 4096, len = 0;
	char *buf = malloc(cap);
	int st = 1;
	for (;;) {
		if (!buf) {
			st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
			break;
		}
		if (len + 1 >= cap) {
			char *grown = cap > (64u << 20) ? NULL : realloc(buf, cap * 2);
			if (!grown) {
				st = popc_error_set(err, POPC_ERR_NOMEM, "%s: too large", path);
				break;
			}
			buf = grown;
			cap *= 2;
		}
		ssize_t r = read(fd, buf + len, cap - 1 - len);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			st = popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
			break;
		}
		if (r == 0)
			break;
		len += (size_t)r;
	}
	close(fd);
	if (st != 1) {
		free(buf);
		return st;
	}
	buf[len] = '\0';
	*out = buf;
	*out_len = len;
	return 1;
}
