/* Line reader for ini_parse_stream (ini_lines.h). */
#include "popc/scene/ini_lines.h"

#include <string.h>

char *popc_ini_read_line(char *str, int num, FILE *f, int *line, int *too_long)
{
	/* fgets, but seeing a NUL byte: past one strlen would see a line cut
	 * short, take it for one too long, and count the rest as another line */
	int n = 0, c, nul = 0;
	while (n < num - 1 && (c = getc(f)) != EOF) {
		str[n++] = (char)c;
		nul |= c == '\0';
		if (c == '\n')
			break;
	}
	if (n == 0)
		return NULL; /* the end of the file, or a read error (ferror) */
	str[n] = '\0';
	char *r = str;
	(*line)++;
	if (nul) { /* libinih would read the line up to the NUL only */
		*too_long = 2;
		return NULL;
	}
	if (r[n - 1] != '\n') {
		/* num - 1 characters without their newline: the line either ends
		 * here (the newline, or CR LF, is consumed, or it is the last line
		 * of the file) or goes on */
		int next = getc(f);
		if (next == '\r') {
			int after = getc(f);
			if (after != '\n' && after != EOF) {
				*too_long = 1;
				return NULL;
			}
		} else if (next != EOF && next != '\n') {
			*too_long = 1;
			return NULL;
		}
	}
	/* Blanks before a key are indentation, not a continuation: libinih
	 * (INI_ALLOW_MULTILINE in Debian's build) would read an indented
	 * "rate = 500" after "duration = 2" as a second value of duration. */
	size_t lead = strspn(r, " \t");
	if (lead > 0)
		memmove(r, r + lead, (size_t)n - lead + 1);
	return r;
}

int popc_ini_line_has_bare_cr(const char *line)
{
	for (const char *p = strchr(line, '\r'); p; p = strchr(p + 1, '\r'))
		if (p[1] != '\n' && p[1] != '\0')
			return 1;
	return 0;
}
