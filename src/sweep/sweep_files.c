/* File-system helpers of the sweep directory (sweep_files.h). */
#include "popc/sweep/sweep_files.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
