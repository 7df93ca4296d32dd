/* popc: the experiment runner. Verbs dispatch to cmd_*.c. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static void usage(FILE *f)
{
	fputs("usage: popc VERB [options]\n"
	      "\n"
	      "Runs time-domain passivity controller (PO/PC) experiments on a simulated plant\n"
	      "or a Modbus servo axis and writes CSV logs (Ryu, Hannaford, Kwon, Kim 2005).\n"
	      "\n"
	      "verbs:\n"
	      "  run SCENE       run one experiment\n"
	      "  scene show|keys print a resolved scene, or every scene key\n"
	      "  bench integrators|loop|log  speed against error (docs/BENCHMARKS.md)\n"
	      "  sweep SCENE     run a parameter sweep in parallel (Slurm, GNU parallel)\n"
	      "\n"
	      "'popc VERB --help' describes a verb. popc-analyze reads the logs.\n",
	      f);
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return 2;
	}
	const char *verb = argv[1];
	if (strcmp(verb, "--help") == 0 || strcmp(verb, "-h") == 0 || strcmp(verb, "help") == 0) {
		usage(stdout);
		return 0;
	}
	if (strcmp(verb, "--version") == 0) {
		printf("popc %s (build %s)\n", popc_cli_version(), popc_cli_build_id());
		return 0;
	}
	/* getopt names argv[0] in its messages: "popc run: unrecognized option" */
	static char prog[64] = "popc ";
	strncat(prog, verb, sizeof prog - sizeof "popc ");
	argv[1] = prog;
	if (strcmp(verb, "run") == 0)
		return popc_cmd_run(argc - 1, argv + 1);
	if (strcmp(verb, "scene") == 0)
		return popc_cmd_scene(argc - 1, argv + 1);
	if (strcmp(verb, "bench") == 0)
		return popc_cmd_bench(argc - 1, argv + 1);
	if (strcmp(verb, "sweep") == 0)
		return popc_cmd_sweep(argc - 1, argv + 1);
	fprintf(stderr, "popc: unknown verb '%s'\n", verb);
	usage(stderr);
	return 2;
}
