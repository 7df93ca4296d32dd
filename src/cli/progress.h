/* The progress line of popc's long verbs (progress.c): one line on stderr,
 * redrawn in place, only when stderr is a terminal and not with -q, at most
 * ten times a second, and only once the work has taken after_s seconds (a run
 * that ends sooner shows nothing). popc sweep (sweep_progress.c) and popc run
 * draw their bars with it. */
#ifndef POPC_CLI_PROGRESS_H
#define POPC_CLI_PROGRESS_H

#include <stddef.h>

typedef struct cli_progress {
	int shown;                 /* stderr is a terminal and not quiet */
	int drawn;                 /* a line was drawn: the final one ends it */
	double after_s;            /* nothing before this much wall time */
	double t_start, t_last;
} cli_progress;

/* The delay before the first line: default_s, or the environment's
 * POPC_PROGRESS_AFTER_S (seconds, >= 0; for tests, which must not wait on
 * the clock to see the line). */
double cli_progress_after_s(double default_s);

/* Starts the clock; shown when stderr is a terminal and quiet is 0. */
void cli_progress_start(cli_progress *p, int quiet, double after_s);

/* Whether to draw now: shown, past after_s and 0.1 s since the last line;
 * final: whenever a line was drawn (to end it). */
int cli_progress_due(cli_progress *p, int final);

/* Draws "\r<label>[####....] <counts> NN% <rest>" and clears the rest of the
 * line; final ends it with a newline. fraction in [0, 1]. */
void cli_progress_bar(cli_progress *p, const char *label, double fraction, const char *counts,
		      const char *rest, int final);

/* Seconds since cli_progress_start. */
double cli_progress_elapsed_s(const cli_progress *p);

/* "m:ss" or "h:mm:ss"; "--:--" when unknown (negative, NaN, huge). */
void cli_format_duration(double s, char *buf, size_t cap);

#endif
