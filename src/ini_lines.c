/* Line reader for ini_parse_stream (ini_lines.h). */
#include "ini_lines.h"

#include <string.h>

char *popc_ini_read_line(char *str, int num, FILE *f, int *line, int *too_long)
{
	char *r = fgets(str, num, f);
	if (!r)
		return NULL;
	(*line)++;
	size_t n = strlen(r);
	if (n > 0 && r[n - 1] == '\n')
		return r;
	/* num - 1 characters without their newline: the line either ends here
	 * (the newline is consumed, or it is the last line of the file) or goes on */
	int next = getc(f);
	if (next == EOF || next == '\n')
		return r;
	*too_long = 1;
	return NULL;
}
