/* Runs gnuplot as a child process (fork/exec) with its exit status checked.
 * Its messages (stderr: warnings such as "empty y range", errors) go to a
 * temporary file, shown after the run only when it failed or when asked
 * (-v): a report that drew every figure prints nothing of gnuplot's. */
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "analyze.h"

/* Copies what gnuplot said to our stderr, each line after "gnuplot: ". */
static void show_messages(FILE *msg, const char *script)
{
	char line[1024];
	rewind(msg);
	while (fgets(line, sizeof line, msg)) {
		size_t n = strlen(line);
		fprintf(stderr, "gnuplot %s: %s%s", script, line, n && line[n - 1] == '\n' ? "" : "\n");
	}
}

static int run(const char *gnuplot, const char *dir, const char *script, FILE *msg, char *why,
	       size_t why_cap)
{
	fflush(stdout); /* nothing buffered is written twice by the child */
	fflush(stderr);
	pid_t pid = fork();
	if (pid < 0) {
		snprintf(why, why_cap, "fork: %s", strerror(errno));
		return -1;
	}
	if (pid == 0) {
		/* the child: run in the report directory so the scripts' relative
		 * paths work, and a user can rerun them there the same way */
		if (chdir(dir) != 0)
			_exit(126);
		int devnull = open("/dev/null", O_RDONLY);
		if (devnull >= 0) {
			dup2(devnull, STDIN_FILENO);
			close(devnull);
		}
		if (msg)
			dup2(fileno(msg), STDERR_FILENO);
		execlp(gnuplot, gnuplot, script, (char *)NULL);
		_exit(127);
	}
	int status;
	while (waitpid(pid, &status, 0) < 0) {
		if (errno != EINTR) {
			snprintf(why, why_cap, "waitpid: %s", strerror(errno));
			return -1;
		}
	}
	if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
		return 0;
	if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
		snprintf(why, why_cap, "cannot run '%s' (not installed? use --gnuplot PATH)", gnuplot);
	else if (WIFEXITED(status) && WEXITSTATUS(status) == 126)
		snprintf(why, why_cap, "cannot enter %s", dir);
	else if (WIFEXITED(status))
		snprintf(why, why_cap, "%s %s exited with status %d", gnuplot, script,
			 WEXITSTATUS(status));
	else
		snprintf(why, why_cap, "%s %s killed by signal %d", gnuplot, script,
			 WIFSIGNALED(status) ? WTERMSIG(status) : 0);
	return -1;
}

int ana_run_gnuplot(const char *gnuplot, const char *dir, const char *script, int verbose,
		    char *why, size_t why_cap)
{
	/* no temporary file (no space, no /tmp): gnuplot's messages go where ours do */
	FILE *msg = tmpfile();
	int rc = run(gnuplot, dir, script, msg, why, why_cap);
	if (msg) {
		if (rc != 0 || verbose)
			show_messages(msg, script);
		fclose(msg);
	}
	return rc;
}
