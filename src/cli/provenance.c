/* The log header's provenance lines: which build made the log, when, and from
 * which command line (cli.h, popc_cli_provenance). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"

/* One argument as a POSIX shell reads it back: bare when it holds only
 * characters no shell treats specially, else in single quotes (a ' as '\'').
 * A control character (a newline would end the header line) is written as
 * bash's $'\NNN' outside the quotes, so the line stays one line. */
static void put_arg(FILE *m, const char *a)
{
	static const char safe[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
				   "0123456789_./=:,+@%-";
	if (a[0] && strspn(a, safe) == strlen(a)) {
		fputs(a, m);
		return;
	}
	int quoted = 0;
	if (!a[0])
		fputs("''", m);
	for (const unsigned char *p = (const unsigned char *)a; *p; p++) {
		int ctl = *p < 0x20 || *p == 0x7f;
		if (ctl || *p == '\'') {
			if (quoted)
				fputc('\'', m);
			quoted = 0;
			if (ctl)
				fprintf(m, "$'\\%03o'", *p);
			else
				fputs("\\'", m);
			continue;
		}
		if (!quoted)
			fputc('\'', m);
		quoted = 1;
		fputc(*p, m);
	}
	if (quoted)
		fputc('\'', m);
}

char *popc_cli_provenance(void)
{
	char *text = NULL;
	size_t n = 0;
	FILE *m = open_memstream(&text, &n);
	if (!m)
		return NULL;
	/* the date in UTC, ISO 8601: the same text wherever the log is read */
	char date[32] = "unknown";
	time_t now = time(NULL);
	struct tm tm;
	if (now != (time_t)-1 && gmtime_r(&now, &tm))
		strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &tm);
	fprintf(m, "# popc_build = %s\n# date = %s\n# command =", popc_cli_build_id(), date);
	for (char **a = popc_cli_argv; a && *a; a++) {
		fputc(' ', m);
		put_arg(m, *a);
	}
	fputc('\n', m);
	if (fclose(m) != 0) {
		free(text);
		return NULL;
	}
	return text;
}
