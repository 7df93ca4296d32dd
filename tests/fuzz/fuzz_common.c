/* Helpers shared by the fuzz harnesses (fuzz.h). */
#define _GNU_SOURCE /* memfd_create */
#include "fuzz.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

void popc_fuzz_fail(const uint8_t *data, size_t size, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	fputs("popc fuzz: property broken: ", stderr);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, "\ninput (%zu bytes): ", size);
	for (size_t i = 0; i < size && i < 400; i++) {
		unsigned char c = data[i];
		if (c >= 0x20 && c < 0x7f && c != '\\')
			fputc(c, stderr);
		else
			fprintf(stderr, "\\x%02x", c);
	}
	fputs(size > 400 ? "...\n" : "\n", stderr);
	abort();
}

int popc_fuzz_file(const uint8_t *data, size_t size, char *path, size_t cap)
{
	int fd = memfd_create("popc-fuzz", 0);
	if (fd < 0)
		return -1;
	size_t done = 0;
	while (done < size) {
		ssize_t n = write(fd, data + done, size - done);
		if (n <= 0) {
			close(fd);
			return -1;
		}
		done += (size_t)n;
	}
	snprintf(path, cap, "/proc/self/fd/%d", fd);
	return fd;
}

void popc_fuzz_file_close(int fd)
{
	if (fd >= 0)
		close(fd);
}

int popc_fuzz_names_line(const char *msg, const char *path, long long max_line, long long *line)
{
	size_t n = strlen(path);
	if (strncmp(msg, path, n) != 0 || msg[n] != ':')
		return 0;
	const char *p = msg + n + 1;
	if (*p < '0' || *p > '9')
		return 0;
	char *end;
	long long v = strtoll(p, &end, 10);
	if (*end != ':' || v < 1 || v > max_line)
		return 0;
	if (line)
		*line = v;
	return 1;
}

long long popc_fuzz_count_lines(const uint8_t *data, size_t size)
{
	long long n = 0;
	for (size_t i = 0; i < size; i++)
		n += data[i] == '\n';
	if (size > 0 && data[size - 1] != '\n')
		n++;
	return n;
}
