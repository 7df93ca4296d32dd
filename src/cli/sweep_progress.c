/* popc sweep's progress display (sweep_progress.h). */
#include "sweep_progress.h"

#include <stdio.h>
#include <unistd.h>

#include "popc/util/clock.h"
#include "popc/util/error.h"
#include "progress.h"

void sweep_progress_show(sweep_progress *p, int final)
{
	if (p->quiet || p->total == 0)
		return;
	if (p->tty && !final && !cli_progress_due(&p->line, 0))
		return; /* redraw at most 10 times a second */
	double el = popc_now_s() - p->t_start;
	double rate = el > 0 ? (double)p->done_now / el : 0.0;
	double eta = rate > 0 ? (double)(p->total - p->done) / rate : -1.0;
	char eta_text[32];
	cli_format_duration(eta, eta_text, sizeof eta_text);
	int pct = (int)(100 * p->done / p->total);
	if (p->tty) {
		/* the bar of every long verb (progress.c) */
		char counts[64], rest[128];
		snprintf(counts, sizeof counts, "%lld/%lld", p->done, p->total);
		snprintf(rest, sizeof rest, "%.1f runs/s ETA %s %s %lld", rate, eta_text,
			 p->map ? "diverged/failed" : "failed", p->failed_now);
		cli_progress_bar(&p->line, "", (double)p->done / (double)p->total, counts, rest, final);
		return;
	}
	/* not a terminal: a plain line at every tenth of the way, and at the end */
	int decile = (int)(10 * p->done / p->total);
	if (decile == p->last_decile && (!final || p->done == p->last_done))
		return;
	p->last_decile = decile;
	p->last_done = p->done;
	if (p->map)
		fprintf(stderr, "popc map: %lld/%lld runs (%d%%), %lld diverged (verdicts) or failed, "
				"%.1f runs/s, ETA %s\n",
			p->done, p->total, pct, p->failed_now, rate, eta_text);
	else
		fprintf(stderr, "popc sweep: %lld/%lld runs (%d%%), %lld failed, %.1f runs/s, ETA %s\n",
			p->done, p->total, pct, p->failed_now, rate, eta_text);
}

void sweep_progress_start(sweep_progress *p, int quiet, long long total, long long done_before)
{
	*p = (sweep_progress){.quiet = quiet, .tty = isatty(STDERR_FILENO), .total = total,
			      .done = done_before, .t_start = popc_now_s()};
	/* a sweep draws its bar from the start (after 0 s): it takes long */
	cli_progress_start(&p->line, quiet, 0.0);
	p->last_decile = (int)(10 * p->done / (total ? total : 1));
	p->last_done = p->done;
}

double sweep_progress_elapsed_s(const sweep_progress *p)
{
	return popc_now_s() - p->t_start;
}

void sweep_progress_failure(const sweep_progress *p, const popc_sweep_plan *plan, long long i,
			    int exit_status, const char *reason)
{
	if (p->quiet || p->tty)
		return;
	char id[POPC_SWEEP_ID_MAX], what[512], line[1400];
	popc_sweep_run_id(plan, i, id);
	popc_sweep_run_describe(plan, i, what, sizeof what);
	int n = p->map && exit_status == POPC_EXIT_UNSTABLE
			? snprintf(line, sizeof line,
				   "popc map: run %s (%s) diverged, as a probe past the edge is expected "
				   "to: a verdict, not a failure\n",
				   id, what)
		: p->map ? snprintf(line, sizeof line, "popc map: run %s (%s) failed, exit %d: %s\n",
				    id, what, exit_status, reason)
			 : snprintf(line, sizeof line, "popc sweep: run %s (%s) failed, exit %d: %s\n",
				    id, what, exit_status, reason);
	if (n > 0 && write(STDERR_FILENO, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1) < 0)
		return;
}
