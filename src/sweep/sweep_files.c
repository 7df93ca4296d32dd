/* File-system helpers of the sweep directory (sweep_files.h). */
#include "popc/sweep/sweep_files.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

/* The buffer grows no further than 128 MB (a sweep's rows file of 10,000
 * runs is some 3.4 MB) */
#define READ_FILE_MAX ((size_t)128 << 20)

/* Files from this size on are mapped by popc_sweep_view_file: read into
 * fresh memory, a 3.4 MB rows file (10,000 runs) costs a page fault per
 * 4 kB and a copy, dear on a VM (a third of a sweep's own CPU per run,
 * docs/BENCHMARKS.md section 6); mapped, its page cache pages are used as
 * they are. Below this size a read costs little either way. */
#define VIEW_MAP_MIN ((size_t)64 << 10)

/* Opens path: 1 and *fd, 0 if it does not exist, or a negative popc_status. */
static int open_file(const char *path, int *fd, popc_error *err)
{
	*fd = open(path, O_RDONLY);
	if (*fd >= 0)
		return 1;
	if (errno == ENOENT || errno == ENOTDIR)
		return 0;
	return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
}

/* The whole of fd (sb: its fstat, zeroed if none), NUL-terminated. The
 * buffer is sized by the file's size and the file read in one read() while
 * it has not grown: growing a 4 kB buffer by doubling copied the text up to
 * ten times and faulted in each new buffer's pages. A file that grows while
 * read (or has no size: a pipe) is read on with the buffer doubled. */
static int read_fd(int fd, const struct stat *sb, const char *path, char **out, size_t *out_len,
		   popc_error *err)
{
	size_t cap = 4096, len = 0;
	if (sb->st_size > 0 && (size_t)sb->st_size < READ_FILE_MAX)
		cap = (size_t)sb->st_size + 2; /* + the NUL, + a byte to see the end in one read */
	char *buf = malloc(cap);
	for (;;) {
		if (!buf)
			return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
		if (len + 1 >= cap) {
			char *grown = cap * 2 > READ_FILE_MAX ? NULL : realloc(buf, cap * 2);
			if (!grown) {
				free(buf);
				return popc_error_set(err, POPC_ERR_NOMEM, "%s: too large", path);
			}
			buf = grown;
			cap *= 2;
		}
		ssize_t r = read(fd, buf + len, cap - 1 - len);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0) {
			free(buf);
			return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(errno));
		}
		if (r == 0)
			break;
		len += (size_t)r;
		/* a regular file read to its size and short of the buffer: its
		 * end, without a second read() to hear it */
		if (S_ISREG(sb->st_mode) && len == (size_t)sb->st_size && len + 1 < cap)
			break;
	}
	buf[len] = '\0';
	*out = buf;
	*out_len = len;
	return 1;
}

/* open_file, and the file's fstat in *sb (zeros when it cannot be had: the
 * file is then read to its end, whatever its size). */
static int open_stat(const char *path, int *fd, struct stat *sb, popc_error *err)
{
	int st = open_file(path, fd, err);
	if (st > 0 && fstat(*fd, sb) != 0)
		memset(sb, 0, sizeof *sb);
	return st;
}

/* Reads a whole (small) file, NUL-terminated. Returns 1, 0 if it does not
 * exist, or a negative popc_status. */
int popc_sweep_read_file(const char *path, char **out, size_t *out_len, popc_error *err)
{
	*out = NULL;
	int fd;
	struct stat sb;
	int st = open_stat(path, &fd, &sb, err);
	if (st <= 0)
		return st;
	st = read_fd(fd, &sb, path, out, out_len, err);
	close(fd);
	return st;
}

int popc_sweep_view_file(const char *path, popc_sweep_file_view *v, popc_error *err)
{
	*v = (popc_sweep_file_view){0};
	int fd;
	struct stat sb;
	int st = open_stat(path, &fd, &sb, err);
	if (st <= 0)
		return st;
	size_t size = (size_t)sb.st_size;
	if (S_ISREG(sb.st_mode) && size >= VIEW_MAP_MIN && size < READ_FILE_MAX) {
		/* (MAP_POPULATE, every page mapped in one call, measured no
		 * faster: the faults on page cache pages allocate nothing) */
		void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
		if (map != MAP_FAILED) {
			close(fd);
			*v = (popc_sweep_file_view){.text = map, .len = size, .map = map, .map_len = size};
			return 1;
		}
		/* a file system that maps no files: read it */
	}
	char *text;
	size_t len;
	st = read_fd(fd, &sb, path, &text, &len, err);
	close(fd);
	if (st == 1)
		*v = (popc_sweep_file_view){.text = text, .len = len, .buf = text};
	return st;
}

void popc_sweep_file_view_free(popc_sweep_file_view *v)
{
	if (v->map)
		munmap(v->map, v->map_len);
	free(v->buf);
	*v = (popc_sweep_file_view){0};
}
