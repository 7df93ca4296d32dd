/* popc sweep's worker pool (sweep_pool.h).
 *
 * Why forked workers and not fork/exec of `popc run` per run: a paper-scene
 * run takes about 1 ms; exec, dynamic loading and re-reading the scene cost
 * about as much again (docs/SWEEPS.md, "Overhead", has the figures). Why
 * processes and not threads: a run that crashes takes down its worker only;
 * the sweep records the run as failed, starts a new worker and goes on.
 *
 * The runs to make are a list of indices; workers take the next one from a
 * counter in shared memory (no message per run: a pipe round trip and two
 * context switches cost a few percent of a paper-scene run), run it and
 * append its row to their own rows file (summaries only: 32 rows a write(),
 * ROWS_HELD_MAX below). The parent only watches: each worker
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
 * that ends while runs remain and the sweep is not stopping is replaced.
 *
 * -j 1 has no worker: the sweep's own process runs the worker's loop
 * (make_runs, c->here), and a crash among its runs starts popc again as
 * --isolate (sweep_crash.h says why and how). -j N makes runs in the
 * sweep's own process too, beside N - 1 workers (slot 0 is its own): at -j 2
 * on 300 paper-scene runs of about 0.25 ms each, a parent that only watched
 * paid a second worker's fork, copy-on-write faults and exit and left one of
 * the two cores to its poll loop (docs/BENCHMARKS.md, "-j 2 against -j 1").
 * It watches its workers once its own loop has found no run left; a worker
 * that died before then is found there, its run recorded as failed, as
 * before (only later: the runs it would have made were the parent's). A
 * crash in the parent kills and reaps its workers before popc starts again
 * (sweep_crash.h). */
#define _DEFAULT_SOURCE   /* MAP_ANONYMOUS: POSIX.1-2024, and Linux, the BSDs, macOS before it */
#include "sweep_pool.h"

#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "sweep_crash.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_row.h"
#include "popc/sweep/sweep_run.h"
#include "popc/util/parse.h"

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

typedef struct pool_ctx {
	const popc_sweep_plan *plan;
	const char *dir;
	int keep_log;
	const long long *todo;
	long long n_todo;
	worker *w;
	volatile pid_t *pids;         /* per slot: the worker's pid, 0 none (read by the crash handler) */
	int n_workers;                /* slots; with c->here slot 0 is this process' */
	pool_shared *sh;
	atomic_uchar *recorded;       /* per todo entry: its row is written */
	int crash_fd;                 /* the parent's rows file, for lost runs */
	long rows_pid;                /* the pid in rows file names: 0 the process' own (test hook) */
	long long die_after_claim;    /* test hook: run index, -1 off */
	long long crash_at;           /* test hook: run index, -1 off */
	long long interrupt_after;    /* test hook: runs taken before ^C, -1 off */
	int here;                     /* this process makes runs too: slot 0, beside the workers */
	long long parent_recorded;    /* runs the parent recorded as failed (record_lost) */
	/* the counts of prog when this round began */
	long long done0, done_now0, failed_now0, parent0;
	sweep_progress *prog;
} pool_ctx;

/* prog from the round's counts (workers', and the parent's own records). */
static void count_progress(pool_ctx *c)
{
	long long d = atomic_load(&c->sh->done), pr = c->parent_recorded - c->parent0;
	c->prog->done = c->done0 + d + pr;
	c->prog->done_now = c->done_now0 + d + pr;
	c->prog->failed_now = c->failed_now0 + atomic_load(&c->sh->failed) + pr;
}

static void show_progress(pool_ctx *c, int final)
{
	if (c->prog->quiet)
		return;
	count_progress(c);
	sweep_progress_show(c->prog, final);
}

/* Rows a summaries-only worker holds before one write(): a write() per row
 * cost about 3 us of system time a run on the 2-core VM of
 * docs/BENCHMARKS.md section 6, a third of the sweep's own cost per run. A
 * held row is not recorded: a worker that dies loses at most these, whose
 * runs the parent makes again (the reconciliation below), as it does a run
 * taken in the window. So that such a loss stays small for long runs too,
 * the rows are also written once the held runs took HELD_S_MAX of wall time.
 * With logs each row is written at once (a run's summary.csv follows its
 * row). */
enum { ROWS_HELD_MAX = 32 };
#define HELD_S_MAX 1.0

/* The runs whose rows the worker holds, recorded when the rows are written. */
typedef struct held_runs {
	long long k[ROWS_HELD_MAX];   /* todo indices */
	popc_sweep_result res[ROWS_HELD_MAX];
	int n;
	double wall_s;                /* the held runs' wall time */
} held_runs;

/* Writes the held rows and records their runs: a run is counted done (and a
 * failed one shown) once its row is in the rows file, so that a run made
 * again after a worker died is shown once. Rows that cannot be written are
 * said, and their runs end without a result (no retry), as before. */
static void record_held(pool_ctx *c, popc_sweep_rows_batch *rows, held_runs *h)
{
	popc_error err;
	if (popc_sweep_rows_flush(rows, &err) != 0) {
		fprintf(stderr, "popc sweep: %s\n", err.msg);
		atomic_store(&c->sh->trouble, 1);
	}
	for (int m = 0; m < h->n; m++) {
		const popc_sweep_result *res = &h->res[m];
		long long k = h->k[m];
		if (res->exit_status != 0) {
			atomic_fetch_add(&c->sh->failed, 1);
			sweep_progress_failure(c->prog, c->plan, c->todo[k], res->exit_status, res->reason);
		}
		atomic_store(&c->recorded[k], 1);
		atomic_fetch_add(&c->sh->done, 1);
	}
	h->n = 0;
	h->wall_s = 0.0;
}

/* -j 1's rows file: one per process, kept open across a map's rounds (a
 * file per round would take the names HOST.PID.1.csv, .2, ... one after
 * the other, as the same pid's). Closed at exit. */
static struct {
	int fd;
	char dir[POPC_PATH_MAX];
} here_rows = {.fd = -1};

static int open_rows(pool_ctx *c, popc_error *err)
{
	if (c->here && here_rows.fd >= 0 && strcmp(here_rows.dir, c->dir) == 0)
		return here_rows.fd;
	int fd = popc_sweep_rows_open(c->plan, c->dir, c->rows_pid ? c->rows_pid : (long)getpid(), err);
	if (c->here && fd >= 0 && strlen(c->dir) < sizeof here_rows.dir) {
		if (here_rows.fd >= 0)
			close(here_rows.fd);
		here_rows.fd = fd;
		strcpy(here_rows.dir, c->dir);
	}
	return fd;
}

static void close_rows(int fd)
{
	if (fd != here_rows.fd)
		close(fd);
}

/* The loop of a worker, or of the sweep itself at -j 1 (c->here): takes
 * runs until none is left or the sweep stops. Returns the worker's exit
 * status: 0, 1 (its rows file could not be opened; said), or 5 (stopped by
 * a signal). */
static int make_runs(pool_ctx *c, int slot)
{
	popc_error err;
	int fd = open_rows(c, &err);
	popc_sweep_rows_batch rows;
	held_runs *held = malloc(sizeof *held);
	if (fd < 0 || !held ||
	    popc_sweep_rows_batch_init(&rows, fd, c->keep_log ? 1 : ROWS_HELD_MAX, &err) != 0) {
		fprintf(stderr, "popc sweep: %s\n", fd < 0 || held ? err.msg : "out of memory");
		atomic_store(&c->sh->trouble, 1);
		if (fd >= 0)
			close_rows(fd);
		free(held);
		return POPC_EXIT_RUN_FAILED;
	}
	held->n = 0;
	held->wall_s = 0.0;
	if (c->here)
		sweep_crash_hold(&rows);
	while (!popc_cli_stop) {
		long long k = atomic_fetch_add(&c->sh->next, 1);
		if (k >= c->n_todo)
			break;
		long long i = c->todo[k];
		/* test hook: die in the window between taking a run and saying
		 * so (the held rows written first: the hook's run is the one lost) */
		if (i == c->die_after_claim && atomic_exchange(&c->sh->hook_fired, 1) == 0) {
			record_held(c, &rows, held);
			raise(SIGKILL);
		}
		atomic_store(&c->sh->current[slot], k);
		popc_sweep_result *res = &held->res[held->n];
		if (c->here)
			sweep_crash_in_hand(i);
		/* test hooks: the run ends the process that makes it, as a
		 * crash; the sweep is sent SIGINT (as by ^C) once this process
		 * has taken that many runs (counted across a map's rounds) */
		if (i == c->crash_at)
			abort();
		static long long taken_here;
		if (c->interrupt_after >= 0 && taken_here++ == c->interrupt_after)
			kill(c->here ? getpid() : getppid(), SIGINT);
		int st = popc_sweep_run_one(c->plan, i, c->dir, c->keep_log, &rows, &popc_cli_stop, res, &err);
		if (c->here)
			sweep_crash_in_hand(-1);
		if (st != 0) {
			/* its row could not be written (the sweep exits 1 listing
			 * it as without a result; no retry), or only the run's own
			 * summary.csv (the row counts): said here, and exit 1 */
			fprintf(stderr, "popc sweep: %s\n", err.msg);
			atomic_store(&c->sh->trouble, 1);
		}
		if (st == 0 && res->interrupted) {
			atomic_store(&c->sh->current[slot], -1);
			break; /* not recorded: run again (next round, or a resumed sweep) */
		}
		if (!(st == 0 || res->recorded))
			res->exit_status = 0; /* no result: not shown as failed */
		held->k[held->n++] = k;
		held->wall_s += res->wall_time_s;
		/* written now (the batch is full, or a log's row was written at
		 * once) or held for the next write */
		if (rows.n_rows == 0 || held->n == ROWS_HELD_MAX || held->wall_s >= HELD_S_MAX)
			record_held(c, &rows, held);
		atomic_store(&c->sh->current[slot], -1);
		if (c->here)
			show_progress(c, 0);
	}
	record_held(c, &rows, held);
	if (c->here)
		sweep_crash_hold(NULL);
	popc_sweep_rows_batch_free(&rows);
	free(held);
	close_rows(fd);
	return popc_cli_stop ? POPC_EXIT_INTERRUPTED : 0;
}

static void worker_main(pool_ctx *c, int slot)
{
	/* no atexit handlers, no second flush of the parent's stdio; 5 tells the
	 * parent a signal stopped this worker */
	_exit(make_runs(c, slot));
}

static int spawn_worker(pool_ctx *c, int slot)
{
	int life[2];
	if (pipe(life) != 0)
		return -1;
	atomic_store(&c->sh->current[slot], -1);
	fflush(stdout);
	fflush(stderr);
	pid_t parent = getpid();
	pid_t pid = fork();
	if (pid < 0) {
		close(life[0]);
		close(life[1]);
		return -1;
	}
	if (pid == 0) {
		/* a worker ends with the sweep: killed (SIGKILL cannot be
		 * caught), the sweep would leave its workers making runs and
		 * holding the directory's lock. SIGTERM, as a signal to the
		 * worker alone: the run in hand stops at its next tick,
		 * unrecorded, the rows held are written. The parent may have
		 * died before the prctl: then this worker is already an orphan */
		if (prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || getppid() != parent)
			_exit(POPC_EXIT_INTERRUPTED);
		/* a worker beside the parent's runs: a crash here is this
		 * worker's, recorded by the parent; the rows file is its own */
		if (c->here) {
			c->here = 0;
			sweep_crash_disarm();
			if (here_rows.fd >= 0)
				close(here_rows.fd);
			here_rows.fd = -1;
		}
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
	c->pids[slot] = pid;
	return 0;
}

/* Run i has no result of this sweep and will get none: record it as failed
 * in the parent's rows file, with the reason. Returns 1 on trouble. */
static int record_lost(pool_ctx *c, long long i, const char *reason)
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
	sweep_progress_failure(c->prog, c->plan, i, POPC_EXIT_RUN_FAILED, reason);
	return 0;
}

/* A worker died with run i in hand: the run is what killed it (or it was
 * killed while making it); recorded as failed, not run again. */
static int record_crash(pool_ctx *c, long long i, int wstatus)
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
static int worker_ended(pool_ctx *c, int slot, int wstatus, int *respawns)
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
static int run_pool(pool_ctx *c, int jobs, long long **lost, long long *n_lost)
{
	*lost = NULL;
	*n_lost = 0;
	c->n_workers = (int)(c->n_todo < jobs ? c->n_todo : jobs);
	size_t sh_size = sizeof(pool_shared) + (size_t)c->n_workers * sizeof(atomic_llong);
	size_t rec_size = (size_t)c->n_todo * sizeof(atomic_uchar);
	void *mem = mmap(NULL, sh_size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	void *rec = mmap(NULL, rec_size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
	c->w = calloc((size_t)c->n_workers, sizeof *c->w);
	c->pids = calloc((size_t)c->n_workers, sizeof *c->pids);
	struct pollfd *pfd = calloc((size_t)c->n_workers, sizeof *pfd);
	int *slot_of = calloc((size_t)c->n_workers, sizeof *slot_of);
	if (mem == MAP_FAILED || rec == MAP_FAILED || !c->w || !c->pids || !pfd || !slot_of) {
		fprintf(stderr, "popc sweep: out of memory\n");
		if (mem != MAP_FAILED)
			munmap(mem, sh_size);
		if (rec != MAP_FAILED)
			munmap(rec, rec_size);
		free(c->w);
		free((void *)c->pids);
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
	c->done0 = c->prog->done;
	c->done_now0 = c->prog->done_now;
	c->failed_now0 = c->prog->failed_now;
	c->parent0 = c->parent_recorded;
	/* with c->here, slot 0 is this process': workers in the others (none
	 * at -j 1), started first so that they make runs while it does */
	if (c->here && c->n_workers > 1)
		sweep_crash_workers(c->pids, c->n_workers);
	for (int k = c->here ? 1 : 0; k < c->n_workers && !trouble; k++) {
		if (spawn_worker(c, k) != 0) {
			fprintf(stderr, "popc sweep: cannot start a worker: %s\n", strerror(errno));
			trouble = 1;
		}
	}
	if (c->here && !trouble) {
		atomic_store(&c->sh->current[0], -1);
		int status = make_runs(c, 0);
		trouble = status != 0 && status != POPC_EXIT_INTERRUPTED;
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
		count_progress(c);
		if (alive == 0)
			break;
		sweep_progress_show(c->prog, 0);
		int r = poll(pfd, (nfds_t)alive, c->prog->tty ? 100 : 250);
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
			c->pids[slot_of[m]] = 0;
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
	if (c->here)
		sweep_crash_workers(NULL, 0);
	munmap(mem, sh_size);
	munmap(rec, rec_size);
	c->sh = NULL;
	c->recorded = NULL;
	free((void *)c->pids);
	c->pids = NULL;
	free(pfd);
	free(slot_of);
	free(c->w);
	c->w = NULL;
	return trouble;
}

/* Makes the runs of c->todo: a round, then rounds for the runs that workers
 * took and dropped (killed in the window, or stopped by a signal of their
 * own), then records what is still left as failed. Returns 0 or 1 (trouble). */
static int run_sweep(pool_ctx *c, int jobs)
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
		c->prog->done += c->parent_recorded - before;
		c->prog->done_now += c->parent_recorded - before;
		c->prog->failed_now += c->parent_recorded - before;
	}
	free(lost);
	c->todo = todo0;
	c->n_todo = n_todo0;
	if (c->crash_fd >= 0)
		close(c->crash_fd);
	c->crash_fd = -1;
	sweep_progress_show(c->prog, 1);
	return trouble;
}

int sweep_pool_run(const sweep_pool_config *cfg, const long long *todo, long long n_todo,
		   sweep_progress *prog)
{
	pool_ctx c = {.plan = cfg->plan, .dir = cfg->dir, .keep_log = cfg->keep_log, .todo = todo,
		       .n_todo = n_todo, .rows_pid = cfg->rows_pid,
		       .die_after_claim = cfg->die_after_claim, .crash_at = cfg->crash_at,
		       .interrupt_after = cfg->interrupt_after,
		       .prog = prog};
	/* the sweep's own process makes runs (all of them at -j 1, beside N -
	 * 1 workers at -j N) unless asked not to (--isolate, or the popc that a
	 * crash here started: sweep_crash.h), or when a crash here could not
	 * be survived (no program to start again) */
	const char *isolate = getenv("POPC_SWEEP_ISOLATE");
	c.here = cfg->jobs >= 1 && !cfg->isolate && !(isolate && isolate[0] == '1') &&
		 cfg->die_after_claim < 0 && sweep_crash_arm(cfg->plan) == 0;
	int trouble = run_sweep(&c, cfg->jobs);
	if (c.here)
		sweep_crash_disarm();
	return trouble;
}

void sweep_pool_test_hooks(sweep_pool_config *cfg)
{
	const char *v = getenv("POPC_SWEEP_TEST_ROWS_PID");
	long long n;
	if (v && popc_parse_ll_text(v, 1, LONG_MAX, &n) == 0)
		cfg->rows_pid = n;
	v = getenv("POPC_SWEEP_TEST_DIE_AFTER_CLAIM");
	if (v && popc_parse_ll_text(v, 0, LONG_MAX, &n) == 0)
		cfg->die_after_claim = n;
	v = getenv("POPC_SWEEP_TEST_CRASH_AT");
	if (v && popc_parse_ll_text(v, 0, LONG_MAX, &n) == 0)
		cfg->crash_at = n;
	v = getenv("POPC_SWEEP_TEST_INTERRUPT_AFTER");
	if (v && popc_parse_ll_text(v, 0, LONG_MAX, &n) == 0)
		cfg->interrupt_after = n;
}

int sweep_pool_default_jobs(void)
{
	const char *slurm = getenv("SLURM_CPUS_PER_TASK");
	long long n;
	if (slurm && popc_parse_ll_text(slurm, 1, 4096, &n) == 0)
		return (int)n;
	n = sysconf(_SC_NPROCESSORS_ONLN);
	return n > 0 ? (int)(n > 4096 ? 4096 : n) : 1;
}

int sweep_pool_shard(const char *shard_text, popc_sweep_shard *shard, popc_error *err)
{
	*shard = (popc_sweep_shard){.index = 0, .count = 1};
	if (shard_text)
		return popc_sweep_shard_parse(shard_text, shard, err);
	return popc_sweep_shard_from_slurm(getenv("SLURM_ARRAY_TASK_ID"),
					   getenv("SLURM_ARRAY_TASK_COUNT"),
					   getenv("SLURM_ARRAY_TASK_MIN"),
					   getenv("SLURM_ARRAY_TASK_STEP"), shard, err);
}
