#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "popc/programs/env.h"
#include "popc/util/atomic_file.h"
#include "popc/programs/stdfds.h"
#include "popc/util/text.h"

volatile sig_atomic_t popc_cli_stop = 0;
char **popc_cli_argv;

void popc_cli_keep_argv(int argc, char **argv)
{
	/* a copy of the pointers: getopt permutes argv's, and verbs name
	 * argv[0] "popc VERB" for getopt's messages */
	char **copy = malloc((size_t)(argc + 1) * sizeof *copy);
	if (!copy)
		return; /* no copy: a crash in -j 1's sweep is not survived (sweep_crash.h) */
	for (int k = 0; k < argc; k++)
		copy[k] = argv[k];
	copy[argc] = NULL;
	popc_cli_argv = copy;
}

static void on_signal(int sig)
{
	(void)sig;
	popc_cli_stop = 1;
}

/* Every signal whose default action ends the process (or, SIGTSTP, stops
 * it) would leave a drive enabled at its last force, with nothing in popc
 * running to zero it. Each is handled or ignored, none left at its default:
 *
 * - the stop flag, and so the safe stop (zero force, disable, the log's stop
 *   line, exit 5): SIGINT, SIGTERM, SIGQUIT (its default would dump core with
 *   the drive enabled), SIGHUP (the terminal or the ssh session went away),
 *   SIGALRM, SIGUSR1, SIGUSR2, SIGVTALRM, SIGPROF (nothing in popc sets a
 *   timer or uses them: they come from outside, as a request to end),
 *   SIGXCPU (the soft CPU time limit: the hard one follows with SIGKILL, so
 *   stop while we still can), SIGIO/SIGPOLL, SIGPWR (a UPS: the power is
 *   going), SIGSTKFLT, SIGTRAP and SIGSYS sent by kill, the real-time
 *   signals SIGRTMIN..SIGRTMAX, and with a drive (drive != 0) SIGTSTP: ^Z
 *   would suspend popc with the drive holding its last force, so a drive run
 *   is ended, not paused (a simulated run or a sweep is suspended as usual);
 * - ignored: SIGPIPE (a --log pipe whose reader left is a write error,
 *   EPIPE) and SIGXFSZ (a file size limit reached: the write fails with
 *   EFBIG, the log is cut back to its last whole row, exit 1).
 *
 * A SIGHUP ignored when popc starts (nohup) stays ignored: nohup asks the
 * run to outlive the terminal. Not covered, and said in docs/MODBUS.md:
 * SIGKILL and SIGSTOP cannot be caught or ignored; SIGSEGV, SIGBUS, SIGFPE,
 * SIGILL and SIGABRT are a crash (a handler cannot return into the code that
 * faulted), SIGTTIN and SIGTTOU stop a background popc that uses the
 * terminal, and SIGCONT, SIGCHLD, SIGURG and SIGWINCH do nothing by default;
 * for these only the drive's own watchdog brings the axis to a safe state. */
static const int stop_signals[] = {
	SIGINT, SIGTERM, SIGQUIT, SIGALRM, SIGUSR1, SIGUSR2, SIGVTALRM, SIGPROF,
	SIGXCPU, SIGTRAP, SIGSYS,
#ifdef SIGIO
	SIGIO,
#endif
#ifdef SIGPWR
	SIGPWR,
#endif
#ifdef SIGSTKFLT
	SIGSTKFLT,
#endif
};

void popc_cli_install_signals(int drive)
{
	struct sigaction sa, old;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	for (size_t i = 0; i < sizeof stop_signals / sizeof stop_signals[0]; i++)
		sigaction(stop_signals[i], &sa, NULL);
#ifdef SIGRTMIN
	for (int sig = SIGRTMIN; sig <= SIGRTMAX; sig++)
		sigaction(sig, &sa, NULL);
#endif
	if (drive)
		sigaction(SIGTSTP, &sa, NULL);
	if (sigaction(SIGHUP, NULL, &old) != 0 || old.sa_handler != SIG_IGN)
		sigaction(SIGHUP, &sa, NULL);
	signal(SIGPIPE, SIG_IGN);
	signal(SIGXFSZ, SIG_IGN);
}

void popc_cli_getopt_tables(const popc_option *const *tables,
			    struct option opts[POPC_CLI_MAX_OPTIONS], char shorts[2 * POPC_CLI_MAX_OPTIONS])
{
	/* the sizes hold every verb's tables: a table that outgrows them is a
	 * programming error, which the first run of that verb shows */
	if (popc_options_getopt(tables, opts, POPC_CLI_MAX_OPTIONS, shorts, 2 * POPC_CLI_MAX_OPTIONS) != 0)
		abort();
}

int popc_cli_fail(const char *verb, int status, const popc_error *err)
{
	fprintf(stderr, "popc %s: %s\n", verb, err->msg);
	return popc_status_exit_code(status);
}

int popc_cli_load_scene_options(popc_scene *s, const char *path, char **sets, int n_sets,
				const popc_cli_key_option *opts, int n_opts, popc_error *err)
{
	int st = popc_env_scene_defaults(s, err);
	if (!st && path)
		st = popc_scene_load(s, path, err);
	for (int i = 0; !st && i < n_sets; i++)
		st = popc_scene_set_assignment(s, sets[i], err);
	for (int i = 0; !st && i < n_opts; i++)
		if (opts[i].value)
			st = popc_scene_set_option(s, opts[i].option, opts[i].section, opts[i].key,
						   opts[i].value, err);
	if (!st)
		st = popc_scene_validate(s, err);
	return st;
}

int popc_cli_load_scene(popc_scene *s, const char *path, char **sets, int n_sets, popc_error *err)
{
	return popc_cli_load_scene_options(s, path, sets, n_sets, NULL, 0, err);
}

int popc_cli_assignment_split(const char *verb, const char *option, char *const *values, int n)
{
	for (int i = 0; i < n; i++) {
		if (strchr(values[i], '='))
			continue;
		/* the word after "OPTION KEY" as started (getopt has moved the
		 * operands since) */
		const char *next = NULL;
		for (int k = 0; popc_cli_argv && popc_cli_argv[k] && popc_cli_argv[k + 1]; k++)
			if (strcmp(popc_cli_argv[k], option) == 0 && popc_cli_argv[k + 1] == values[i]) {
				next = popc_cli_argv[k + 2];
				break;
			}
		if (next && next[0] && next[0] != '-')
			fprintf(stderr,
				"popc %s: %s %s %s: give %s KEY=VALUE as one word, with '=': %s %s=%s\n",
				verb, option, values[i], next, option, option, values[i], next);
		else
			fprintf(stderr, "popc %s: %s '%s' has no '=': give %s KEY=VALUE, e.g. %s "
					"run.duration=10\n",
				verb, option, values[i], option, option);
		return 1;
	}
	return 0;
}

int popc_cli_set_names_key(const char *set, const char *section, const char *key)
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

int popc_cli_commit_memstream(FILE *f, char **buf, size_t *n, const char *dir, const char *name,
			      popc_error *err)
{
	if (fclose(f) != 0) {
		free(*buf);
		*buf = NULL;
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	char path[POPC_PATH_MAX + 64];
	snprintf(path, sizeof path, "%s/%s", dir, name);
	int st = popc_write_file_atomic(path, *buf, *n, err);
	free(*buf);
	*buf = NULL;
	return st;
}

int popc_cli_stdout_closed(const char *verb, const char *option, const char *path)
{
	if (!path || strcmp(path, "-") != 0 || !popc_stdfds_was_closed(1))
		return 0;
	/* stdout is /dev/null now (stdfds.h): the output would vanish with exit 0 */
	fprintf(stderr,
		"popc %s: %s -: standard output is closed (popc was started with descriptor 1 "
		"closed, e.g. '>&-'): give %s a file\n",
		verb, option, option);
	return 1;
}
