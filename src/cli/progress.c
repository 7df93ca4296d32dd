/* The progress line of popc's long verbs (progress.h). */
#include "progress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "popc/util/clock.h"
#include "popc/util/parse.h"

double cli_progress_after_s(double default_s)
{
	const char *e = getenv("POPC_PROGRESS_AFTER_S");
	double v;
	if (e && *e && popc_parse_double_text(e, &v) == 0 && v >= 0.0 && isfinite(v))
		return v;
	return default_s;
}

void cli_progress_start(cli_progress *p, int quiet, double after_s)
{
	*p = (cli_progress){.shown = !quiet && isatty(STDERR_FILENO), .after_s = after_s,
			    .t_start = popc_now_s(), .t_last = -(double)INFINITY};
}

int cli_progress_due(cli_progress *p, int final)
{
	if (!p->shown)
		return 0;
	if (final)
		return p->drawn;
	double t = popc_now_s();
	/* redraw at most 10 times a second */
	return t - p->t_start >= p->after_s && t - p->t_last >= 0.1;
}

void cli_progress_bar(cli_progress *p, const char *label, double fraction, const char *counts,
		      const char *rest, int final)
{
	enum { WIDTH = 24 };
	if (!(fraction >= 0.0))
		fraction = 0.0;
	if (fraction > 1.0)
		fraction = 1.0;
	char bar[WIDTH + 1];
	int fill = (int)(WIDTH * fraction);
	for (int i = 0; i < WIDTH; i++)
		bar[i] = i < fill ? '#' : '.';
	bar[WIDTH] = '\0';
	fprintf(stderr, "\r%s[%s] %s %3d%% %s\033[K", label, bar, counts, (int)(100.0 * fraction),
		rest);
	if (final)
		fputc('\n', stderr);
	p->drawn = 1;
	p->t_last = popc_now_s();
}

double cli_progress_elapsed_s(const cli_progress *p)
{
	return popc_now_s() - p->t_start;
}

void cli_format_duration(double s, char *buf, size_t cap)
{
	if (!(s >= 0) || s > 1e8) {
		snprintf(buf, cap, "--:--");
		return;
	}
	long t = (long)(s + 0.5);
	if (t >= 3600)
		snprintf(buf, cap, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
	else
		snprintf(buf, cap, "%ld:%02ld", t / 60, t % 60);
}
