#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

volatile sig_atomic_t popc_cli_stop = 0;

static void on_signal(int sig)
{
	(void)sig;
	popc_cli_stop = 1;
}

void popc_cli_install_signals(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
}

int popc_cli_fail(const char *verb, int status, const popc_error *err)
{
	fprintf(stderr, "popc %s: %s\n", verb, err->msg);
	return popc_status_exit_code(status);
}

int popc_cli_load_scene(popc_scene *s, const char *path, char **sets, int n_sets, popc_error *err)
{
	popc_scene_defaults(s);
	int st = 0;
	if (path)
		st = popc_scene_load(s, path, err);
	for (int i = 0; !st && i < n_sets; i++)
		st = popc_scene_set_assignment(s, sets[i], err);
	if (!st)
		st = popc_scene_validate(s, err);
	return st;
}

int popc_cli_push(char ***list, int *n, char *value)
{
	char **grown = realloc(*list, (size_t)(*n + 1) * sizeof **list);
	if (!grown)
		return -1;
	grown[(*n)++] = value;
	*list = grown;
	return 0;
}

int popc_cli_parse_long(const char *text, long lo, long hi, long *out)
{
	char *end;
	errno = 0;
	long v = strtol(text, &end, 10);
	if (end == text || *end || errno || v < lo || v > hi)
		return -1;
	*out = v;
	return 0;
}
