/* popc sweep SCENE --vary KEY=LIST... -o DIR [-j N] [--shard I/N] [--list]
 * popc sweep merge DIR... [-o DIR]
 *
 * The planner, ids, shards and summary rows are in the library (sweep.h).
 * This file runs the plan: a pool of forked worker processes, each running
 * scenes in-process through the library (popc_sweep_run_one), taking run
 * indices from a counter in shared memory ("worker pool" below).
 *
 * Why forked workers and not fork/exec of `popc run` per run: a paper-scene
 * run takes about 1 ms; exec, dynamic loading and re-reading the scene cost
 * about as much again (docs/SWEEPS.md, "Overhead", has the figures). Why
 * processes and not threads: a run that crashes takes down its worker only;
 * the sweep records the run as failed, starts a new worker and goes on. */
#define _XOPEN_SOURCE 700 /* realpath */
#define _DEFAULT_SOURCE   /* MAP_ANONYMOUS: POSIX.1-2024, and Linux, the BSDs, macOS before it */
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <limits.h>
#include <poll.h>
#include <stdatomic.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "popc/sweep/sweep.h"
#include "popc/util/atomic_file.h"
#include "popc/util/clock.h"
#include "popc/util/text.h"

static void usage(FILE *f)
{
	fputs("usage: popc sweep SCENE --vary section.key=LIST [--vary ...] -o DIR [options]\n"
	      "       popc sweep merge DIR... [-o DIR]\n"
	      "\n"
	      "Runs the cartesian product of the --vary lists on the scene, in parallel, and\n"
	      "writes DIR/summary.csv: one row per run with its id, the varied values, its exit\n"
	      "status, the compare metrics and its wall time (last column). Each run has a\n"
	      "directory DIR/runs/<id> with its resolved scene, log and summary. Running the\n"
	      "same sweep into the same DIR again skips finished runs and retries failed ones.\n"
	      "\n"
	      "  --vary section.key=LIST  a scene key and its values (repeatable; the last\n"
	      "                           --vary varies fastest). LIST is a,b,c or a range\n"
	      "                           lo:hi:n (n evenly spaced points, ends included) or\n"
	      "                           lo:hi:n:log (evenly spaced in log); e.g.\n"
	      "                           --vary controller.variant=none,ref-energy,improved\n"
	      "                           --vary encoder.resolution=1e-6:1e-4:5:log\n"
	      "  --set section.key=value  a fixed override of the base scene (repeatable)\n"
	      "                           (a relative operator.table here or in --vary is\n"
	      "                           from the working directory; in the scene file,\n"
	      "                           from the file's directory; each run's scene.ini\n"
	      "                           names it absolute)\n"
	      "  -o, --output DIR         the sweep directory (created if needed)\n"
	      "  -j, --jobs N             parallel runs (default: SLURM_CPUS_PER_TASK, else\n"
	      "                           every online core)\n"
	      "  --no-log                 keep run summaries only (no log.csv, no scene.ini)\n"
	      "  --shard I/N              run only shard I of N (runs with id mod N = I);\n"
	      "                           default from SLURM_ARRAY_TASK_ID/_COUNT when set.\n"
	      "                           A shard writes DIR/summary-shard-I-of-N.csv\n"
	      "  --list                   print one 'popc run' command line per run of the\n"
	      "                           shard (for GNU parallel) instead of running; each\n"
	      "                           runs the run's resolved scene, written now to\n"
	      "                           DIR/runs/<id>/scene.ini (later edits of SCENE do\n"
	      "                           not reach it); then 'popc sweep merge DIR'\n"
	      "                           gathers their results\n"
	      "  --program PATH           the popc that --list lines call (default: this one)\n"
	      "  -q, --quiet              no progress\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "merge: gathers the runs of shard outputs (or of --list runs) into one\n"
	      "summary.csv in DIR (default: the first DIR), equal to a one-machine sweep's but\n"
	      "for the wall_time_s column.\n"
	      "\n"
	      "Exit status: 0 every run succeeded, 1 some run failed (listed) or has no result,\n"
	      "2 bad scene, --vary or usage (nothing ran), 5 interrupted (finished runs kept).\n"
	      "docs/SWEEPS.md: Slurm job arrays, GNU parallel, resuming, merging.\n",
	      f);
}

enum { OPT_VARY = 256, OPT_SET, OPT_NO_LOG, OPT_SHARD, OPT_LIST, OPT_PROGRAM };

/* ---- progress ---------------------------------------------------------------- */

typedef struct progress {
	int quiet, tty;
	long long total, done;         /* done includes runs finished before (resumed) */
	long long done_now, failed_now; /* runs made by this invocation, failed among them */
	double t_start, t_last;
	int last_decile;
	long long last_done;   /* done at the last plain line */
} progress;

static void fmt_duration(double s, char *buf, size_t cap)
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

static void progress_show(progress *p, int final)
{
	if (p->quiet || p->total == 0)
		return;
	double t = popc_now_s();
	if (p->tty && !final && t - p->t_last < 0.1)
		return; /* redraw at most 10 times a second */
	double el = t - p->t_start;
	double rate = el > 0 ? (double)p->done_now / el : 0.0;
	double eta = rate > 0 ? (double)(p->total - p->done) / rate : -1.0;
	char eta_text[32];
	fmt_duration(eta, eta_text, sizeof eta_text);
	int pct = (int)(100 * p->done / p->total);
	if (p->tty) {
		enum { WIDTH = 24 };
		char bar[WIDTH + 1];
		int fill = (int)(WIDTH * p->done / p->total);
		for (int i = 0; i < WIDTH; i++)
			bar[i] = i < fill ? '#' : '.';
		bar[WIDTH] = '\0';
		fprintf(stderr, "\r[%s] %lld/%lld %3d%% %.1f runs/s ETA %s failed %lld\033[K", bar,
			p->done, p->total, pct, rate, eta_text, p->failed_now);
		if (final)
			fputc('\n', stderr);
		p->t_last = t;
		return;
	}
	/* not a terminal: a plain line at every tenth of the way, and at the end */
	int decile = (int)(10 * p->done / p->total);
	if (decile == p->last_decile && (!final || p->done == p->last_done))
		return;
	p->last_decile = decile;
	p->last_done = p->done;
	fprintf(stderr, "popc sweep: %lld/%lld runs (%d%%), %lld failed, %.1f runs/s, ETA %s\n",
		p->done, p->total, pct, p->failed_now, rate, eta_text);
}

/* ---- worker pool ----------------------------------------------------------------- *
 *
 * The runs to make are a list of indices; workers take the next one from a
 * counter in shared memory (no message per run: a pipe round trip and two
 * context switches cost a few percent of a paper-scene run), run it and
 * append its row to their own rows file. The parent only watches: each worker
 * holds the write end of a "life" pipe, whose EOF tells the parent the worker
 * is gone; the worker's slot says which run it had in hand, if any.
 *
 * No run that a worker took may be lost. Taking a run (the fetch-add on the
 * counter) and saying so in the slot are two steps, and a worker can die
 * between them; a worker sent SIGTERM or SIGINT alone drops its run unrecorded
 * (as the whole sweep does on ^C). So each entry of the list also has a
 * "recorded" flag in shared memory, set once its row is written (by the
 * worker, or by the parent for a run whose worker died). When the workers are
 * done, the parent runs the taken-but-unrecorded entries again, in up to
 * RETRY_ROUNDS more rounds, and records what is still left as failed. A worker
 * that ends while runs remain and the sweep is not stopping is replaced. */

#if ATOMIC_LLONG_LOCK_FREE != 2 || ATOMIC_CHAR_LOCK_FREE != 2
#error "the worker pool needs lock-free atomics in shared memory"
#endif

enum { RETRY_ROUNDS = 3 };

typedef struct pool_shared {
	atomic_llong next;            /* next index into the todo list; those below are taken */
	atomic_llong done, failed;    /* runs recorded by workers */
	atomic_int trouble;           /* a row could not be written */
	atomic_int hook_fired;        /* the claim test hook fired (once per sweep) */
	atomic_llong current[];       /* per worker slot: todo index in hand, -1 none */
} pool_shared;

typedef struct worker {
	pid_t pid;                    /* 0: slot empty */
	int life_fd;                  /* read end of the life pipe, -1 closed */
} worker;

typedef struct sweep_ctx {
	const popc_sweep_plan *plan;
	const char *dir;
	int keep_log;
	const long long *todo;
	long long n_todo;
	worker *w;
	int n_workers;
	pool_shared *sh;
	atomic_uchar *recorded;       /* per todo entry: its row is written */
	int crash_fd;                 /* the parent's rows file, for lost runs */
	long rows_pid;                /* the pid in rows file names: 0 the process' own (test hook) */
	long long die_after_claim;    /* test hook: run index, -1 off */
	long long parent_recorded;    /* runs the parent recorded as failed (record_lost) */
	progress prog;
} sweep_ctx;

static void describe(const popc_sweep_plan *p, long long i, char *buf, size_t cap)
{
	int idx[64];
	popc_sweep_run_values(p, i, idx);
	size_t len = 0;
	buf[0] = '\0';
	for (int a = 0; a < p->n_axes && len < cap; a++)
		len += (size_t)snprintf(buf + len, cap - len, "%s%s.%s=%s", a ? " " : "",
					p->axes[a].section, p->axes[a].key, p->axes[a].values[idx[a]]);
}

/* A failed run, as it happens (plain lines only: on a terminal the bar counts
 * failures and the list at the end names them). One write(), so that lines of
 * different workers do not mix. */
static void say_failure(const sweep_ctx *c, long long i, int exit_status, const char *reason)
{
	if (c->prog.quiet || c->prog.tty)
		return;
	char id[POPC_SWEEP_ID_MAX], what[512], line[1400];
	popc_sweep_run_id(c->plan, i, id);
	describe(c->plan, i, what, sizeof what);
	int n = snprintf(line, sizeof line, "popc sweep: run %s (%s) failed, exit %d: %s\n", id, what,
			 exit_status, reason);
	if (n > 0 && write(STDERR_FILENO, line, (size_t)n < sizeof line ? (size_t)n : sizeof line - 1) < 0)
		return;
}

static void worker_main(sweep_ctx *c, int slot)
{
	popc_error err;
	int fd = popc_sweep_rows_open(c->plan, c->dir, c->rows_pid ? c->rows_pid : (long)getpid(), &err);
	if (fd < 0) {
		fprintf(stderr, "popc sweep: %s\n", err.msg);
		atomic_store(&c->sh->trouble, 1);
		_exit(1);
	}
	while (!popc_cli_stop) {
		long long k = atomic_fetch_add(&c->sh->next, 1);
		if (k >= c->n_todo)
			break;
		long long i = c->todo[k];
		/* test hook: die in the window between taking a run and saying so */
		if (i == c->die_after_claim && atomic_exchange(&c->sh->hook_fired, 1) == 0)
			raise(SIGKILL);
		atomic_store(&c->sh->current[slot], k);
		popc_sweep_result res;
		int st = popc_sweep_run_one(c->plan, i, c->dir, c->keep_log, fd, &popc_cli_stop, &res, &err);
		if (st != 0) {
			/* its row could not be written (the sweep exits 1 listing
			 * it as without a result; no retry), or only the run's own
			 * summary.csv (the row counts): said here, and exit 1 */
			fprintf(stderr, "popc sweep: %s\n", err.msg);
			atomic_store(&c->sh->trouble, 1);
		}
		if (st == 0 && res.interrupted) {
			atomic_store(&c->sh->current[slot], -1);
			break; /* not recorded: run again (next round, or a resumed sweep) */
		}
		if ((st == 0 || res.recorded) && res.exit_status != 0) {
			atomic_fetch_add(&c->sh->failed, 1);
			say_failure(c, i, res.exit_status, res.reason);
		}
		atomic_store(&c->recorded[k], 1);
		atomic_fetch_add(&c->sh->done, 1);
		atomic_store(&c->sh->current[slot], -1);
	}
	close(fd);
	/* no atexit handlers, no second flush of the parent's stdio; 5 tells the
	 * parent a signal stopped this worker */
	_exit(popc_cli_stop ? POPC_EXIT_INTERRUPTED : 0);
}

static int spawn_worker(sweep_ctx *c, int slot)
{
	int life[2];
	if (pipe(life) != 0)
		return -1;
	atomic_store(&c->sh->current[slot], -1);
	fflush(stdout);
	fflush(stderr);
	pid_t pid = fork();
	if (pid < 0) {
		close(life[0]);
		close(life[1]);
		return -1;
	}
	if (pid == 0) {
		/* a sibling's life pipe must see EOF when the sibling dies */
		for (int k = 0; k < c->n_workers; k++)
			if (c->w[k].life_fd >= 0)
				close(c->w[k].life_fd);
		close(life[0]);
		if (c->crash_fd >= 0)
			close(c->crash_fd);
		worker_main(c, slot);
	}
	close(life[1]);
	c->w[slot] = (worker){.pid = pid, .life_fd = life[0]};
	return 0;
}

/* Run i has no result of this sweep and will get none: record it as failed
 * in the parent's rows file, with the reason. Returns 1 on trouble. */
static int record_lost(sweep_ctx *c, long long i, const char *reason)
{
	char row[POPC_SWEEP_ROW_MAX];
	popc_error err;
	if (c->crash_fd < 0)
		c->crash_fd = popc_sweep_rows_open(c->plan, c->dir,
						   c->rows_pid ? c->rows_pid : (long)getpid(), &err);
	int n = c->crash_fd < 0 ? c->crash_fd
				: popc_sweep_row(c->plan, i, POPC_EXIT_RUN_FAILED, NULL, NULL, NULL, 0.0, row,
						 sizeof row, &err);
	if (n < 0 || popc_sweep_rows_append(c->plan, c->crash_fd, i, row, POPC_EXIT_RUN_FAILED, reason,
					    &err) != 0) {
		fprintf(stderr, "popc sweep: %s\n", err.msg);
		return 1;
	}
	c->parent_recorded++;
	say_failure(c, i, POPC_EXIT_RUN_FAILED, reason);
	return 0;
}

/* A worker died with run i in hand: the run is what killed it (or it was
 * killed while making it); recorded as failed, not run again. */
static int record_crash(sweep_ctx *c, long long i, int wstatus)
{
	char reason[POPC_ERROR_MSG_MAX];
	if (WIFSIGNALED(wstatus))
		snprintf(reason, sizeof reason, "the worker process died of signal %d (%s)",
			 WTERMSIG(wstatus), strsignal(WTERMSIG(wstatus)));
	else
		snprintf(reason, sizeof reason, "the worker process exited (status %d) during the run",
			 WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1);
	return record_lost(c, i, reason);
}

/* A worker has ended (wstatus from waitpid) while the sweep is not stopping:
 * record the run it had in hand, say what happened, replace it when runs
 * remain. Returns 1 on trouble. */
static int worker_ended(sweep_ctx *c, int slot, int wstatus, int *respawns)
{
	int trouble = 0;
	long long k = atomic_load(&c->sh->current[slot]);
	if (k >= 0 && !atomic_load(&c->recorded[k])) {
		trouble = record_crash(c, c->todo[k], wstatus);
		atomic_store(&c->recorded[k], 1);
	} else if (WIFSIGNALED(wstatus)) {
		fprintf(stderr, "popc sweep: a worker process died of signal %d (%s) between runs; "
				"a new one takes over\n",
			WTERMSIG(wstatus), strsignal(WTERMSIG(wstatus)));
	} else if (WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == POPC_EXIT_INTERRUPTED) {
		fprintf(stderr, "popc sweep: a worker process was stopped by a signal sent to it "
				"alone; a new one takes over\n");
	} else if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0) {
		return 1; /* it could not open its rows file: said, and not replaced */
	}
	/* every replacement follows a death from outside or one that cost a
	 * run: the cap only stops a loop nothing else would */
	if (atomic_load(&c->sh->next) < c->n_todo && (*respawns)++ < c->n_todo + c->n_workers) {
		if (spawn_worker(c, slot) != 0) {
			fprintf(stderr, "popc sweep: cannot start a worker: %s\n", strerror(errno));
			trouble = 1;
		}
	}
	return trouble;
}

/* One round: makes the runs of the todo list. Sets *lost (malloc'd) to the
 * runs taken but not recorded (none when interrupted). Returns 0, or 1 when a
 * row could not be written or a worker could not be started. */
static int run_pool(sweep_ctx *c, int jobs, long long **lost, long long *n_lost)
{
	*lost = NULL;
	*n_lost = 0;
	c->n_workers = (int)(c->n_todo < jobs ? c->n_todo : jobs);
	size_t sh_size = sizeof(pool_shared) + (size_t)c->n_workers * sizeof(atomic_llong);
	size_t rec_size = (size_t)c->n_todo * sizeof(atomic_uchar);
	void *mem = mmap(NULL, sh_size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	void *rec = mmap(NULL, rec_size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	c->w = calloc((size_t)c->n_workers, sizeof *c->w);
	struct pollfd *pfd = calloc((size_t)c->n_workers, sizeof *pfd);
	int *slot_of = calloc((size_t)c->n_workers, sizeof *slot_of);
	if (mem == MAP_FAILED || rec == MAP_FAILED || !c->w || !pfd || !slot_of) {
		fprintf(stderr, "popc sweep: out of memory\n");
		if (mem != MAP_FAILED)
			munmap(mem, sh_size);
		if (rec != MAP_FAILED)
			munmap(rec, rec_size);
		free(c->w);
		free(pfd);
		free(slot_of);
		return 1;
	}
	c->sh = mem;
	c->recorded = rec; /* an anonymous mapping is zero: nothing recorded */
	atomic_init(&c->sh->next, 0);
	atomic_init(&c->sh->done, 0);
	atomic_init(&c->sh->failed, 0);
	atomic_init(&c->sh->trouble, 0);
	atomic_init(&c->sh->hook_fired, c->die_after_claim < 0);
	for (int k = 0; k < c->n_workers; k++)
		c->w[k] = (worker){.pid = 0, .life_fd = -1};
	int trouble = 0, stopping = 0, respawns = 0;
	long long done0 = c->prog.done, done_now0 = c->prog.done_now, failed_now0 = c->prog.failed_now;
	long long parent0 = c->parent_recorded;
	for (int k = 0; k < c->n_workers && !trouble; k++) {
		if (spawn_worker(c, k) != 0) {
			fprintf(stderr, "popc sweep: cannot start a worker: %s\n", strerror(errno));
			trouble = 1;
		}
	}
	for (;;) {
		if (popc_cli_stop && !stopping) {
			/* a terminal's ^C reached the workers too; a signal to the
			 * parent alone is passed on. Running runs stop at their next
			 * tick and are not recorded. */
			stopping = 1;
			for (int k = 0; k < c->n_workers; k++)
				if (c->w[k].pid > 0)
					kill(c->w[k].pid, SIGINT);
		}
		int alive = 0;
		for (int k = 0; k < c->n_workers; k++) {
			if (c->w[k].pid <= 0)
				continue;
			pfd[alive] = (struct pollfd){.fd = c->w[k].life_fd, .events = POLLIN};
			slot_of[alive++] = k;
		}
		long long d = atomic_load(&c->sh->done), pr = c->parent_recorded - parent0;
		c->prog.done = done0 + d + pr;
		c->prog.done_now = done_now0 + d + pr;
		c->prog.failed_now = failed_now0 + atomic_load(&c->sh->failed) + pr;
		if (alive == 0)
			break;
		progress_show(&c->prog, 0);
		int r = poll(pfd, (nfds_t)alive, c->prog.tty ? 100 : 250);
		if (r < 0 && errno != EINTR) {
			fprintf(stderr, "popc sweep: poll: %s\n", strerror(errno));
			trouble = 1;
			stopping = 1;
			popc_cli_stop = 1;
		}
		for (int m = 0; r > 0 && m < alive; m++) {
			if (!pfd[m].revents)
				continue;
			worker *w = &c->w[slot_of[m]];
			char b;
			if (read(w->life_fd, &b, 1) > 0)
				continue; /* workers write nothing; ignore */
			int wstatus = 0;
			while (waitpid(w->pid, &wstatus, 0) < 0 && errno == EINTR)
				;
			close(w->life_fd);
			w->pid = 0;
			w->life_fd = -1;
			if (!stopping && !popc_cli_stop)
				trouble |= worker_ended(c, slot_of[m], wstatus, &respawns);
		}
	}
	trouble |= atomic_load(&c->sh->trouble);
	/* the reconciliation: taken (below next), never recorded */
	long long taken = atomic_load(&c->sh->next);
	if (taken > c->n_todo)
		taken = c->n_todo;
	if (!popc_cli_stop) {
		for (long long k = 0; k < taken; k++)
			*n_lost += !atomic_load(&c->recorded[k]);
		if (*n_lost > 0 && !(*lost = malloc((size_t)*n_lost * sizeof **lost))) {
			fprintf(stderr, "popc sweep: out of memory\n");
			*n_lost = 0;
			trouble = 1;
		}
		for (long long k = 0, m = 0; *lost && k < taken; k++)
			if (!atomic_load(&c->recorded[k]))
				(*lost)[m++] = c->todo[k];
	}
	munmap(mem, sh_size);
	munmap(rec, rec_size);
	c->sh = NULL;
	c->recorded = NULL;
	free(pfd);
	free(slot_of);
	free(c->w);
	c->w = NULL;
	return trouble;
}

/* Makes the runs of c->todo: a round, then rounds for the runs that workers
 * took and dropped (killed in the window, or stopped by a signal of their
 * own), then records what is still left as failed. Returns 0 or 1 (trouble). */
static int run_sweep(sweep_ctx *c, int jobs)
{
	const long long *todo0 = c->todo;
	long long n_todo0 = c->n_todo;
	long long *lost = NULL, n_lost = 0;
	c->crash_fd = -1;
	int trouble = run_pool(c, jobs, &lost, &n_lost);
	c->die_after_claim = -1; /* the test hook fires in the first round only */
	for (int round = 1; round <= RETRY_ROUNDS && n_lost > 0 && !popc_cli_stop; round++) {
		fprintf(stderr, "popc sweep: %lld run%s taken by a worker that stopped before recording "
				"%s: running %s again\n",
			n_lost, n_lost == 1 ? "" : "s", n_lost == 1 ? "it" : "them",
			n_lost == 1 ? "it" : "them");
		c->todo = lost;
		c->n_todo = n_lost;
		long long *again = NULL, n_again = 0;
		trouble |= run_pool(c, jobs, &again, &n_again);
		free(lost);
		lost = again;
		n_lost = n_again;
	}
	if (n_lost > 0 && !popc_cli_stop) {
		char reason[200];
		snprintf(reason, sizeof reason,
			 "no result: each of %d workers that took it stopped before recording it",
			 RETRY_ROUNDS + 1);
		long long before = c->parent_recorded;
		for (long long m = 0; m < n_lost; m++)
			trouble |= record_lost(c, lost[m], reason);
		c->prog.done += c->parent_recorded - before;
		c->prog.done_now += c->parent_recorded - before;
		c->prog.failed_now += c->parent_recorded - before;
	}
	free(lost);
	c->todo = todo0;
	c->n_todo = n_todo0;
	if (c->crash_fd >= 0)
		close(c->crash_fd);
	c->crash_fd = -1;
	progress_show(&c->prog, 1);
	return trouble;
}

/* ---- failures listed at the end ------------------------------------------------- */

typedef struct failure_list {
	const popc_sweep_plan *plan;
	int list_missing;             /* name runs without a result too */
	long long shown, failed, missing;
} failure_list;

enum { FAILURES_SHOWN = 30 };

static void list_failure(void *user, long long i, int exit_status, const char *reason)
{
	failure_list *fl = user;
	if (exit_status < 0)
		fl->missing++;
	else
		fl->failed++;
	if ((exit_status < 0 && !fl->list_missing) || fl->shown >= FAILURES_SHOWN)
		return;
	if (fl->shown == 0)
		fprintf(stderr, "popc sweep: failed runs:\n");
	fl->shown++;
	char id[POPC_SWEEP_ID_MAX], what[512];
	popc_sweep_run_id(fl->plan, i, id);
	describe(fl->plan, i, what, sizeof what);
	if (exit_status < 0)
		fprintf(stderr, "  %s (%s): no result\n", id, what);
	else
		fprintf(stderr, "  %s (%s): exit %d: %s\n", id, what, exit_status,
			reason[0] ? reason : "(no reason recorded)");
}

/* Notes from reading rows files (a header cut by a kill): not errors. */
static void show_notes(const char *verb, const popc_sweep_results *r, int quiet)
{
	if (quiet || r->n_notes == 0)
		return;
	fprintf(stderr, "popc %s: note: %s\n", verb, r->note);
	if (r->n_notes > 1)
		fprintf(stderr, "popc %s: note: and %d more rows files with a note\n", verb,
			r->n_notes - 1);
}

/* Test hooks (docs/SWEEPS.md, "Test hooks"), for tests that must make a rare
 * event happen; unset in normal use:
 *   POPC_SWEEP_TEST_ROWS_PID=N     name rows files after pid N instead of the
 *                                  process' own (a pid used again)
 *   POPC_SWEEP_TEST_DIE_AFTER_CLAIM=I  the worker that takes run I dies by
 *                                  SIGKILL before saying so in its slot
 *                                  (once per invocation) */
static void test_hooks(sweep_ctx *c)
{
	const char *v = getenv("POPC_SWEEP_TEST_ROWS_PID");
	long long n;
	if (v && popc_parse_ll_text(v, 1, LONG_MAX, &n) == 0)
		c->rows_pid = n;
	v = getenv("POPC_SWEEP_TEST_DIE_AFTER_CLAIM");
	if (v && popc_parse_ll_text(v, 0, LONG_MAX, &n) == 0)
		c->die_after_claim = n;
}

/* ---- --list ---------------------------------------------------------------------- */

/* Writes text as one shell word (single quotes unless it is plain). */
static void put_word(FILE *f, const char *text)
{
	if (text[0] && strspn(text, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
				    "_-+=.,/:@%") == strlen(text)) {
		fputs(text, f);
		return;
	}
	fputc('\'', f);
	for (const char *c = text; *c; c++) {
		if (*c == '\'')
			fputs("'\\''", f);
		else
			fputc(*c, f);
	}
	fputc('\'', f);
}

/* One `popc run` line per run of the shard. Each runs the run's resolved
 * scene, written now to DIR/runs/<id>/scene.ini (every key, paths absolute:
 * scene.h), not the sweep's scene file with --set words: the lines run later,
 * maybe on other machines, and an edit of the scene file in between would
 * give results other than the plan's, which merge would take as the plan's. */
static int print_list(const popc_sweep_plan *p, const popc_sweep_shard *sh, const char *program,
		      const char *dir_abs)
{
	char rdir[POPC_PATH_MAX], path[POPC_PATH_MAX + 32];
	for (long long i = 0; i < p->n_runs; i++) {
		if (!popc_sweep_in_shard(sh, i))
			continue;
		/* popc run writes into the run's directory but does not make it */
		if (popc_sweep_run_dir(p, dir_abs, i, rdir, sizeof rdir) != 0 ||
		    (mkdir(rdir, 0777) != 0 && errno != EEXIST)) {
			fprintf(stderr, "popc sweep: %s: %s\n", rdir, strerror(errno));
			return 1;
		}
		popc_scene s;
		popc_error err;
		char *text = NULL;
		size_t len;
		snprintf(path, sizeof path, "%s/scene.ini", rdir);
		int st = popc_sweep_run_scene(p, i, &s, &err);
		if (!st)
			st = popc_scene_to_text(&s, &text, &len, &err);
		if (!st)
			st = popc_write_file_atomic(path, text, len, &err);
		free(text);
		if (st) {
			fprintf(stderr, "popc sweep: %s\n", err.msg);
			return popc_status_exit_code(st);
		}
		put_word(stdout, program);
		fputs(" run ", stdout);
		put_word(stdout, path);
		/* the log always: popc run's summary lacks the chatter detector's
		 * columns, which merge computes from it */
		snprintf(path, sizeof path, "%s/log.csv", rdir);
		fputs(" --log ", stdout);
		put_word(stdout, path);
		snprintf(path, sizeof path, "%s/run.csv", rdir);
		fputs(" --summary ", stdout);
		put_word(stdout, path);
		fputs(" -q\n", stdout);
	}
	return fflush(stdout) != 0 || ferror(stdout) ? 1 : 0;
}

/* ---- the verbs ---------------------------------------------------------------------- */

static int default_jobs(void)
{
	const char *slurm = getenv("SLURM_CPUS_PER_TASK");
	long long n;
	if (slurm && popc_parse_ll_text(slurm, 1, 4096, &n) == 0)
		return (int)n;
	n = sysconf(_SC_NPROCESSORS_ONLN);
	return n > 0 ? (int)(n > 4096 ? 4096 : n) : 1;
}

static void abs_path(const char *path, char *out, size_t cap)
{
	char *r = realpath(path, NULL);
	snprintf(out, cap, "%s", r ? r : path);
	free(r);
}

static int cmd_merge(int argc, char **argv)
{
	static const struct option opts[] = {
		{"output", required_argument, NULL, 'o'},
		{"quiet", no_argument, NULL, 'q'},
		{"help", no_argument, NULL, 'h'},
		{NULL, 0, NULL, 0},
	};
	const char *out = NULL;
	int quiet = 0, c;
	optind = 1;
	while ((c = getopt_long(argc, argv, "o:qh", opts, NULL)) != -1) {
		switch (c) {
		case 'o': out = optarg; break;
		case 'q': quiet = 1; break;
		case 'h': usage(stdout); return 0;
		default: usage(stderr); return 2;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc sweep merge: no sweep directory given\n");
		return 2;
	}
	const char *const *dirs = (const char *const *)argv + optind;
	int n_dirs = argc - optind;
	if (!out)
		out = dirs[0];
	popc_sweep_plan plan;
	popc_error err;
	if (popc_sweep_plan_from_dir(&plan, dirs[0], &err) != 0)
		return popc_cli_fail("sweep merge", POPC_ERR_INVALID, &err);
	for (int d = 1; d < n_dirs; d++) {
		popc_sweep_plan other;
		if (popc_sweep_plan_from_dir(&other, dirs[d], &err) != 0) {
			popc_sweep_plan_free(&plan);
			return popc_cli_fail("sweep merge", POPC_ERR_INVALID, &err);
		}
		uint64_t id = other.plan_id;
		popc_sweep_plan_free(&other);
		if (id != plan.plan_id) {
			fprintf(stderr,
				"popc sweep merge: %s and %s hold different sweeps (plans %016" PRIx64
				" and %016" PRIx64 ")\n",
				dirs[0], dirs[d], plan.plan_id, id);
			popc_sweep_plan_free(&plan);
			return 2;
		}
	}
	/* the output directory gets the plan too, so that it is a sweep
	 * directory itself (merge and resume read it) */
	int is_input = 0;
	for (int d = 0; d < n_dirs; d++)
		is_input |= strcmp(out, dirs[d]) == 0;
	if (!is_input) {
		char src[POPC_PATH_MAX + 32], dst[POPC_PATH_MAX + 32];
		snprintf(dst, sizeof dst, "%s/sweep.plan", out);
		snprintf(src, sizeof src, "%s/sweep.plan", dirs[0]);
		FILE *f = fopen(src, "rb");
		char buf[1 << 16];
		size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
		if (f)
			fclose(f);
		struct stat sb;
		int st = popc_sweep_mkdir_p(out, &err);
		if (!st && stat(dst, &sb) != 0)
			st = popc_write_file_atomic(dst, buf, n, &err);
		if (!st) {
			popc_sweep_plan o;
			st = popc_sweep_plan_from_dir(&o, out, &err);
			if (!st && o.plan_id != plan.plan_id)
				st = popc_error_set(&err, POPC_ERR_INVALID, "%s holds another sweep", out);
			if (!st)
				popc_sweep_plan_free(&o);
		}
		if (st) {
			popc_sweep_plan_free(&plan);
			return popc_cli_fail("sweep merge", st, &err);
		}
	}
	char path[POPC_PATH_MAX + 32];
	snprintf(path, sizeof path, "%s/summary.csv", out);
	popc_sweep_tally t;
	failure_list fl = {.plan = &plan};
	popc_sweep_results res;
	int st = popc_sweep_results_load(&res, &plan, dirs, n_dirs, 1, &err);
	if (!st) {
		show_notes("sweep merge", &res, quiet);
		st = popc_sweep_results_write(&res, &plan, NULL, path, &t, list_failure, &fl, &err);
		popc_sweep_results_free(&res);
	}
	popc_sweep_plan_free(&plan);
	if (st)
		return popc_cli_fail("sweep merge", st, &err);
	if (!quiet || t.failed || t.missing)
		fprintf(stderr, "popc sweep merge: %s: %lld of %lld runs, %lld failed, %lld without a result\n",
			path, t.ok + t.failed, t.planned, t.failed, t.missing);
	return t.failed || t.missing ? 1 : 0;
}

/* Does the --set assignment "section.key=value" name this key? Names are
 * compared without the blanks around them, as popc_scene_set reads them. */
static int set_names_key(const char *set, const char *section, const char *key)
{
	const char *eq = strchr(set, '='), *dot = strchr(set, '.');
	if (!eq || !dot || dot > eq)
		return 0;
	const char *given[2][2] = {{set, dot}, {dot + 1, eq}};
	const char *want[2] = {section, key};
	for (int k = 0; k < 2; k++) {
		const char *gb = given[k][0], *ge = given[k][1];
		const char *wb = want[k], *we = want[k] + strlen(want[k]);
		popc_trim_blanks(&gb, &ge);
		popc_trim_blanks(&wb, &we);
		if (ge - gb != we - wb || memcmp(gb, wb, (size_t)(ge - gb)) != 0)
			return 0;
	}
	return 1;
}

/* The command line of a sweep (not merge), checked. */
typedef struct sweep_args {
	char **vary, **sets;          /* pointers into argv */
	int n_vary, n_sets;
	int quiet, keep_log, list;
	long long jobs;               /* 0: default_jobs() */
	const char *scene_path, *dir, *shard_text, *program;
} sweep_args;

/* Plans, checks and runs (or lists) the sweep of a checked command line. */
static int sweep_main(const sweep_args *a)
{
	/* plan everything, and check every run's scene, before anything runs.
	 * The base scene is not validated alone: it need not be a scene of its
	 * own (--set operator.intent=table --vary operator.table=a.csv,b.csv),
	 * and every run's scene is validated, naming the run. */
	popc_scene base;
	popc_error err;
	popc_scene_defaults(&base);
	int st = popc_scene_load(&base, a->scene_path, &err);
	for (int m = 0; m < a->n_sets && !st; m++)
		st = popc_scene_set_assignment(&base, a->sets[m], &err);
	if (st)
		return popc_cli_fail("sweep", st, &err);
	int n_vary = a->n_vary;
	popc_sweep_axis *axes = calloc((size_t)n_vary, sizeof *axes);
	if (!axes) {
		fprintf(stderr, "popc sweep: out of memory\n");
		return 1;
	}
	for (int k = 0; k < n_vary && !st; k++)
		st = popc_sweep_axis_parse(a->vary[k], &axes[k], &err);
	for (int k = 0; k < n_vary && !st; k++)
		for (int m = 0; m < a->n_sets && !st; m++)
			if (set_names_key(a->sets[m], axes[k].section, axes[k].key))
				st = popc_error_set(&err, POPC_ERR_INVALID,
						    "--set %s and --vary %s.%s=%s: the key is both fixed "
						    "and varied; give it once",
						    a->sets[m], axes[k].section, axes[k].key, axes[k].spec);
	popc_sweep_plan plan;
	if (st) {
		for (int k = 0; k < n_vary; k++)
			popc_sweep_axis_free(&axes[k]);
		free(axes);
		return popc_cli_fail("sweep", st, &err);
	}
	st = popc_sweep_plan_init(&plan, &base, axes, n_vary, 1, &err);
	if (st) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}

	popc_sweep_shard shard = {.index = 0, .count = 1};
	if (a->shard_text)
		st = popc_sweep_shard_parse(a->shard_text, &shard, &err);
	else
		st = popc_sweep_shard_from_slurm(getenv("SLURM_ARRAY_TASK_ID"),
						 getenv("SLURM_ARRAY_TASK_COUNT"),
						 getenv("SLURM_ARRAY_TASK_MIN"),
						 getenv("SLURM_ARRAY_TASK_STEP"), &shard, &err);
	if (st < 0) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	char scene_abs[PATH_MAX], dir_abs[PATH_MAX];
	abs_path(a->scene_path, scene_abs, sizeof scene_abs);
	st = popc_sweep_dir_prepare(&plan, a->dir, scene_abs, &err);
	if (st) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	abs_path(a->dir, dir_abs, sizeof dir_abs);
	if (a->list) {
		char self[PATH_MAX];
		const char *program = a->program;
		if (!program) {
			ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
			self[n > 0 ? n : 0] = '\0';
			program = n > 0 ? self : "popc";
		}
		int r = print_list(&plan, &shard, program, dir_abs);
		popc_sweep_plan_free(&plan);
		return r;
	}

	/* resume: finished runs are skipped, failed ones run again */
	long long n_shard = 0, n_todo = 0;
	for (long long i = 0; i < plan.n_runs; i++)
		n_shard += popc_sweep_in_shard(&shard, i);
	long long *todo = malloc((size_t)(n_shard ? n_shard : 1) * sizeof *todo);
	if (!todo) {
		popc_sweep_plan_free(&plan);
		fprintf(stderr, "popc sweep: out of memory\n");
		return 1;
	}
	const char *dirs[1] = {a->dir};
	popc_sweep_results res;
	st = popc_sweep_results_load(&res, &plan, dirs, 1, 1, &err);
	if (st) {
		free(todo);
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	for (long long i = 0; i < plan.n_runs; i++)
		if (popc_sweep_in_shard(&shard, i) && !(res.run[i].row && res.run[i].exit_status == 0))
			todo[n_todo++] = i;
	popc_sweep_results_free(&res);

	sweep_ctx ctx = {.plan = &plan, .dir = a->dir, .keep_log = a->keep_log, .todo = todo,
			 .n_todo = n_todo, .rows_pid = 0, .die_after_claim = -1};
	test_hooks(&ctx);
	ctx.prog = (progress){.quiet = a->quiet, .tty = isatty(STDERR_FILENO), .total = n_shard,
			      .done = n_shard - n_todo, .t_start = popc_now_s()};
	ctx.prog.last_decile = (int)(10 * ctx.prog.done / (n_shard ? n_shard : 1));
	ctx.prog.last_done = ctx.prog.done;
	if (!a->quiet && n_shard - n_todo > 0)
		fprintf(stderr, "popc sweep: %lld of %lld runs already done in %s\n", n_shard - n_todo,
			n_shard, a->dir);
	popc_cli_install_signals();
	int trouble = n_todo > 0 ? run_sweep(&ctx, a->jobs > 0 ? (int)a->jobs : default_jobs()) : 0;
	free(todo);
	double elapsed = popc_now_s() - ctx.prog.t_start;

	/* summary.csv from the run files, in id order, renamed into place: an
	 * interrupted sweep leaves the last whole one */
	char path[POPC_PATH_MAX + 64];
	if (shard.count > 1)
		snprintf(path, sizeof path, "%s/summary-shard-%lld-of-%lld.csv", a->dir, shard.index,
			 shard.count);
	else
		snprintf(path, sizeof path, "%s/summary.csv", a->dir);
	popc_sweep_tally t;
	/* not interrupted, every run of the shard should have a result: name
	 * any that has none (a row that could not be written, a worker that
	 * could not be started) */
	failure_list fl = {.plan = &plan, .list_missing = !popc_cli_stop};
	st = popc_sweep_results_load(&res, &plan, dirs, 1, 1, &err);
	if (!st) {
		show_notes("sweep", &res, a->quiet);
		st = popc_sweep_results_write(&res, &plan, &shard, path, &t, list_failure, &fl, &err);
		popc_sweep_results_free(&res);
	}
	popc_sweep_plan_free(&plan);
	if (st)
		return popc_cli_fail("sweep", st, &err);
	long long listed = fl.failed + (fl.list_missing ? fl.missing : 0);
	if (fl.shown < listed)
		fprintf(stderr, "  ... and %lld more (exit_status in %s)\n", listed - fl.shown, path);
	if (!a->quiet || t.failed || t.missing)
		fprintf(stderr,
			"popc sweep: %s: %lld runs, %lld succeeded, %lld failed, %lld not run; "
			"%lld run now in %.3g s\n",
			path, t.planned, t.ok, t.failed, t.missing, ctx.prog.done_now, elapsed);
	if (popc_cli_stop) {
		fprintf(stderr, "popc sweep: interrupted; run the same command again to resume\n");
		return POPC_EXIT_INTERRUPTED;
	}
	return trouble || t.failed || t.missing ? POPC_EXIT_RUN_FAILED : 0;
}

int popc_cmd_sweep(int argc, char **argv)
{
	if (argc >= 2 && strcmp(argv[1], "merge") == 0) {
		static char prog[] = "popc sweep merge"; /* getopt's messages name argv[0] */
		argv[1] = prog;
		return cmd_merge(argc - 1, argv + 1);
	}
	static const struct option opts[] = {
		{"vary", required_argument, NULL, OPT_VARY},
		{"set", required_argument, NULL, OPT_SET},
		{"output", required_argument, NULL, 'o'},
		{"jobs", required_argument, NULL, 'j'},
		{"no-log", no_argument, NULL, OPT_NO_LOG},
		{"shard", required_argument, NULL, OPT_SHARD},
		{"list", no_argument, NULL, OPT_LIST},
		{"program", required_argument, NULL, OPT_PROGRAM},
		{"quiet", no_argument, NULL, 'q'},
		{"help", no_argument, NULL, 'h'},
		{NULL, 0, NULL, 0},
	};
	sweep_args a = {.keep_log = 1};
	int c, rc = -1, oom = 0;
	optind = 1;
	while (rc < 0 && (c = getopt_long(argc, argv, "o:j:qh", opts, NULL)) != -1) {
		switch (c) {
		case OPT_VARY: oom |= popc_cli_push(&a.vary, &a.n_vary, optarg); break;
		case OPT_SET: oom |= popc_cli_push(&a.sets, &a.n_sets, optarg); break;
		case 'o': a.dir = optarg; break;
		case 'j':
			if (popc_parse_ll_text(optarg, 1, 4096, &a.jobs) != 0) {
				fprintf(stderr, "popc sweep: -j '%s': a whole number in [1, 4096]\n", optarg);
				rc = 2;
			}
			break;
		case OPT_NO_LOG: a.keep_log = 0; break;
		case OPT_SHARD: a.shard_text = optarg; break;
		case OPT_LIST: a.list = 1; break;
		case OPT_PROGRAM: a.program = optarg; break;
		case 'q': a.quiet = 1; break;
		case 'h': usage(stdout); rc = 0; break;
		default: usage(stderr); rc = 2; break;
		}
	}
	if (rc < 0) {
		/* options that would be silently ignored are refused */
		const char *why = optind >= argc       ? "missing SCENE file"
				  : optind + 1 != argc ? "more than one SCENE file"
				  : !a.dir             ? "missing -o DIR"
				  : !a.dir[0]          ? "-o '': give a directory name"
				  : a.n_vary == 0      ? "nothing to vary: give --vary section.key=LIST"
				  : a.list && !a.keep_log
					  ? "--no-log does not apply to --list: every listed popc run "
					    "keeps its log (merge computes the chatter columns from it)"
				  : a.list && a.jobs
					  ? "-j does not apply to --list: give GNU parallel its own --jobs"
				  : a.program && !a.list
					  ? "--program applies to --list only (the popc the listed lines "
					    "call); a sweep runs in this process"
					  : NULL;
		if (oom) {
			fprintf(stderr, "popc sweep: out of memory\n");
			rc = 1;
		} else if (why) {
			fprintf(stderr, "popc sweep: %s\n", why);
			usage(stderr);
			rc = 2;
		} else {
			a.scene_path = argv[optind];
			rc = sweep_main(&a);
		}
	}
	free(a.vary);
	free(a.sets);
	return rc;
}
