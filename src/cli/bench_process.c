/* `popc run` as a whole process, timed for `popc bench loop` (bench.h): the
 * loop's figure beside what a user's `popc run SCENE -q` costs (issue 23). */
#include "bench.h"

#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>

extern char **environ;

int bench_process_cpu_s(const bench_opts *o, double duration_s, double *cpu_s, popc_error *err)
{
	*cpu_s = (double)NAN;
	/* popc run SCENE [--set k=v]... --set run.duration=D -q: this program,
	 * with the scene and the sets bench was given, the duration last */
	int n = 0;
	char **argv = calloc((size_t)(2 * o->n_sets + 8), sizeof *argv);
	char dur[64];
	if (!argv)
		return popc_error_set(err, POPC_ERR_NOMEM, "bench: out of memory");
	snprintf(dur, sizeof dur, "run.duration=%.17g", duration_s);
	argv[n++] = (char *)"popc";
	argv[n++] = (char *)"run";
	argv[n++] = (char *)o->scene_path;
	for (int i = 0; i < o->n_sets; i++) {
		argv[n++] = (char *)"--set";
		argv[n++] = o->sets[i];
	}
	argv[n++] = (char *)"--set";
	argv[n++] = dur;
	argv[n++] = (char *)"-q";
	argv[n] = NULL;
	/* the children's CPU before and after: wait4 is no POSIX function */
	struct rusage before, ru;
	getrusage(RUSAGE_CHILDREN, &before);
	pid_t pid;
	int rc = posix_spawn(&pid, "/proc/self/exe", NULL, NULL, argv, environ);
	free(argv);
	if (rc != 0)
		return popc_error_set(err, POPC_ERR_IO, "bench: cannot start popc run (/proc/self/exe): %s",
				      strerror(rc));
	int status;
	pid_t w;
	while ((w = waitpid(pid, &status, 0)) < 0 && errno == EINTR)
		;
	if (w < 0)
		return popc_error_set(err, POPC_ERR_IO, "bench: waiting for popc run: %s",
				      strerror(errno));
	if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
		return popc_error_set(err, POPC_ERR_IO,
				      "bench: popc run %s (duration %g s) as a process failed (%s %d)",
				      o->scene_path, duration_s,
				      WIFEXITED(status) ? "exit" : "signal",
				      WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
	getrusage(RUSAGE_CHILDREN, &ru);
	*cpu_s = (double)(ru.ru_utime.tv_sec - before.ru_utime.tv_sec) +
		 1e-6 * (double)(ru.ru_utime.tv_usec - before.ru_utime.tv_usec) +
		 (double)(ru.ru_stime.tv_sec - before.ru_stime.tv_sec) +
		 1e-6 * (double)(ru.ru_stime.tv_usec - before.ru_stime.tv_usec);
	return 0;
}
