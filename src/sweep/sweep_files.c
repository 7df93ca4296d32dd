/* File-system helpers of the sweep directory (sweep_files.h). */
#include "popc/sweep/sweep_files.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The buffer grows no further than 128 MB (a sweep's rows file of 10,000
 * runs is some 10 MB) */
#define READ_FILE_MAX ((size_t)128 << 20)

/* Reads a whole (small) file, NUL-terminated. Returns 1, 0 if it does not
 * exist, or a negative popc_status. The buffer is sized by fstat and the
 * file read in one read() where it has not grown since: growing a 4 kB
 * buffer by doubling copied the text up to ten times and faulted in each
 * new buffer's pages, a fifth of a sweep's own CPU on a VM where page faults
 * are dear (docs/BENCHMARKS.md section 6). A file that grows while read
 * (or has no size: a pipe) is read on with the buffer doubled. */
int popc_sweep_read_file(const char *path, char **out, size_t *out_len, popc_error *err)
{
	*out = NULL;
	int fd = open(path, O_RDONLY);
	if (fd < 0) {
		if (errno == ENOENT || errno == ENOTDIR)
			return 0;
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
	}
	struct stat sb = {0};
	size_t cap = 4096, len = 0;
	if (fstat(fd, &sb) == 0 && sb.st_size > 0 && (size_t)sb.st_size < READ_FILE_MAX)
		cap = (size_t)sb.st_size + 2; /* + the NUL, + one byte to see the end in one read */
	char *buf = malloc(cap);
	int st = 1;
	for (;;) {
		if (!buf) {
			st = popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
			break;
		}
		if (len + 1 >= cap) {
			char *grown = cap * 2 > READ_FILE_MAX ? NULL : realloc(buf, cap * 2);
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
		/* a short read of a regular file at its size: the end, without a
		 * second read() to hear it */
		if (S_ISREG(sb.st_mode) && len == (size_t)sb.st_size && len + 1 < cap)
			break;
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
