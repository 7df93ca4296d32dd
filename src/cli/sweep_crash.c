/* A crash among -j 1's runs (sweep_crash.h).
 *
 * The handler calls only what is async-signal-safe: write, sigprocmask,
 * fcntl, kill, waitpid, execve, sigaction, raise, and this file's own copying of bytes. Everything
 * it needs (the program's path, the environment with POPC_SWEEP_ISOLATE=1,
 * the prefix of its message) is made when it is armed. */
#define _DEFAULT_SOURCE /* readlink, sigaltstack, environ */
#include "sweep_crash.h"

#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "popc/sweep/sweep_lock.h"

extern char **environ;

static const int fatal_signals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
enum { N_FATAL = sizeof fatal_signals / sizeof fatal_signals[0] };

static struct {
	int armed;
	const popc_sweep_plan *plan;
	popc_sweep_rows_batch *volatile rows;
	volatile long long in_hand;
	volatile pid_t *volatile workers; /* beside this process' runs (-j N > 1) */
	volatile int n_workers;
	volatile int beside;          /* workers were registered: -j N > 1 */
	char exe[PATH_MAX];
	char **env;                   /* environ, POPC_SWEEP_ISOLATE=1 and the
				       * lock's descriptors last */
	char lock_fds[64];            /* POPC_SWEEP_LOCK_FDS=..., "" none */
	char who[32];                 /* "popc sweep" or "popc map" */
	struct sigaction old[N_FATAL];
	stack_t old_stack;
} crash = {.in_hand = -1};

/* The handler's stack. SIGSTKSZ is not a constant in glibc 2.34 and later;
 * 64 kB is more than the handler's frame and a few bytes of text. Static:
 * its pages are faulted in by a crash only (a malloc'd one cost a page
 * fault or two a sweep, 10 to 20 us each on the VM of
 * docs/BENCHMARKS.md). */
static _Alignas(16) char crash_stack[1 << 16];

/* strsignal's words, which strsignal itself (locale) may not give here */
static const char *signal_words(int sig)
{
	switch (sig) {
	case SIGSEGV: return "Segmentation fault";
	case SIGBUS: return "Bus error";
	case SIGFPE: return "Floating point exception";
	case SIGILL: return "Illegal instruction";
	case SIGABRT: return "Aborted";
	}
	return "?";
}

typedef struct text {
	char buf[600];
	size_t len;
} text;

static void add(text *t, const char *s)
{
	while (*s && t->len < sizeof t->buf)
		t->buf[t->len++] = *s++;
}

static void add_int(text *t, int v)
{
	char digits[12];
	int k = (int)sizeof digits - 1;
	digits[k] = '\0';
	unsigned m = v < 0 ? 0u - (unsigned)v : (unsigned)v;
	do
		digits[--k] = (char)('0' + m % 10);
	while ((m /= 10) != 0 && k > 1);
	if (v < 0)
		digits[--k] = '-';
	add(t, digits + k);
}

static void write_all(int fd, const char *buf, size_t len)
{
	while (len > 0) {
		ssize_t w = write(fd, buf, len);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0)
			return;
		buf += w;
		len -= (size_t)w;
	}
}

static int signal_slot(int sig)
{
	for (int k = 0; k < N_FATAL; k++)
		if (fatal_signals[k] == sig)
			return k;
	return -1;
}

static void on_crash(int sig, siginfo_t *si, void *context)
{
	(void)context;
	int saved_errno = errno;
	long long i = crash.in_hand;
	/* the held rows: whole rows, one write (a cut one is the file's last
	 * line, which readers skip, as after a kill) */
	popc_sweep_rows_batch *rows = crash.rows;
	crash.rows = NULL;
	if (rows && rows->len > 0)
		write_all(rows->fd, rows->buf, rows->len);
	text t = {.len = 0};
	add(&t, crash.who);
	add(&t, ": ");
	if (i >= 0) {
		char id[POPC_SWEEP_ID_MAX];
		popc_sweep_run_id(crash.plan, i, id);
		add(&t, "run ");
		add(&t, id);
	} else {
		add(&t, "between runs, the process");
	}
	add(&t, " crashed (signal ");
	add_int(&t, sig);
	add(&t, ", ");
	add(&t, signal_words(sig));
	if (crash.beside)
		add(&t, ") in the sweep's own process, beside its workers (now stopped); the rows "
			"so far are written; going on with worker processes only (as --isolate)\n");
	else
		add(&t, ") in the sweep's own process (-j 1); the rows so far are written; going on "
			"with a worker process (as --isolate)\n");
	write_all(STDERR_FILENO, t.buf, t.len);
	/* the workers end before popc starts again: they would outlive the
	 * execve, making runs into the directory it resumes */
	volatile pid_t *w = crash.workers;
	for (int k = 0; w && k < crash.n_workers; k++) {
		pid_t pid = w[k];
		if (pid <= 0)
			continue;
		kill(pid, SIGKILL);
		while (waitpid(pid, NULL, 0) < 0 && errno == EINTR)
			;
		w[k] = 0;
	}
	/* exec keeps the signal mask: this signal is blocked while handled */
	sigset_t set;
	sigemptyset(&set);
	sigaddset(&set, sig);
	sigprocmask(SIG_UNBLOCK, &set, NULL);
	/* the sweep directory's lock goes on with the popc started: it is
	 * never free between the two, so no other sweep can start there */
	popc_sweep_lock_keep_across_exec();
	execve(crash.exe, popc_cli_argv, crash.env);
	/* not started: end as the signal would have ended us */
	t.len = 0;
	add(&t, crash.who);
	add(&t, ": cannot start popc again (");
	add(&t, crash.exe);
	add(&t, "); run the same command with --isolate to go on\n");
	write_all(STDERR_FILENO, t.buf, t.len);
	sigprocmask(SIG_BLOCK, &set, NULL);
	int k = signal_slot(sig);
	if (k >= 0)
		sigaction(sig, &crash.old[k], NULL);
	errno = saved_errno;
	/* sent (kill, raise, abort): sent again, delivered when this returns;
	 * a fault happens again when this returns */
	if (si->si_code <= 0)
		raise(sig);
}

int sweep_crash_arm(const popc_sweep_plan *p)
{
	if (crash.armed)
		return 0;
	if (!popc_cli_argv || !popc_cli_argv[0])
		return -1;
	ssize_t n = readlink("/proc/self/exe", crash.exe, sizeof crash.exe - 1);
	if (n <= 0)
		return -1;
	crash.exe[n] = '\0';
	size_t n_env = 0;
	while (environ && environ[n_env])
		n_env++;
	crash.env = malloc((n_env + 3) * sizeof *crash.env);
	if (!crash.env)
		return -1;
	size_t m = 0;
	static char isolate[] = "POPC_SWEEP_ISOLATE=1";
	size_t lock_len = strlen(POPC_SWEEP_LOCK_FDS_ENV "=");
	for (size_t k = 0; k < n_env; k++)
		if (strncmp(environ[k], "POPC_SWEEP_ISOLATE=", 19) != 0 &&
		    strncmp(environ[k], POPC_SWEEP_LOCK_FDS_ENV "=", lock_len) != 0)
			crash.env[m++] = environ[k];
	crash.env[m++] = isolate;
	popc_sweep_lock_exec_entry(crash.lock_fds, sizeof crash.lock_fds);
	if (crash.lock_fds[0])
		crash.env[m++] = crash.lock_fds;
	crash.env[m] = NULL;
	const char *verb = popc_cli_argv[1] && strcmp(popc_cli_argv[1], "map") == 0 ? "map" : "sweep";
	strcpy(crash.who, "popc ");
	strcat(crash.who, verb);
	crash.plan = p;
	crash.in_hand = -1;
	crash.rows = NULL;
	stack_t ss = {.ss_sp = crash_stack, .ss_size = sizeof crash_stack, .ss_flags = 0};
	sigaltstack(&ss, &crash.old_stack);
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_sigaction = on_crash;
	sa.sa_flags = SA_SIGINFO | SA_ONSTACK;
	sigemptyset(&sa.sa_mask);
	for (int k = 0; k < N_FATAL; k++)
		sigaction(fatal_signals[k], &sa, &crash.old[k]);
	crash.armed = 1;
	return 0;
}

void sweep_crash_hold(popc_sweep_rows_batch *rows)
{
	crash.rows = rows;
}

void sweep_crash_in_hand(long long i)
{
	crash.in_hand = i;
}

void sweep_crash_workers(volatile pid_t *pids, int n)
{
	crash.workers = NULL; /* never a stale array with a new count */
	crash.n_workers = n;
	crash.workers = pids;
	if (pids)
		crash.beside = 1;
}

void sweep_crash_disarm(void)
{
	if (!crash.armed)
		return;
	for (int k = 0; k < N_FATAL; k++)
		sigaction(fatal_signals[k], &crash.old[k], NULL);
	sigaltstack(&crash.old_stack, NULL);
	free(crash.env);
	crash.env = NULL;
	crash.rows = NULL;
	crash.in_hand = -1;
	crash.workers = NULL;
	crash.n_workers = 0;
	crash.beside = 0;
	crash.armed = 0;
}
