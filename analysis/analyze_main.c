/* popc-analyze: the offline analyser of popc and device logs. Verbs dispatch
 * to cmd_*.c. */
#include <stdio.h>
#include <string.h>

#include "analyze.h"
#include "popc/util/stdfds.h"
#include "popc_config.h"

static void usage(FILE *f)
{
	fputs("usage: popc-analyze VERB [options] LOG...\n"
	      "\n"
	      "Analyses CSV logs of popc (and recorded device logs, with --column) after the\n"
	      "fact: energies, chatter, comparison of controller variants, replay, reports.\n"
	      "\n"
	      "verbs:\n"
	      "  energy LOG...           recompute W and E_ref with each observer definition\n"
	      "  chatter LOG...          flag PC chattering intervals and limit cycles\n"
	      "  compare LOG...          one row of metrics per log (text, CSV, Markdown)\n"
	      "  replay LOG --variant V  run controller variants over a recorded position trace\n"
	      "  report LOG... -o DIR    gnuplot figures (PNG, PDF), table and index page\n"
	      "\n"
	      "'popc-analyze VERB --help' describes a verb. Exit status: 0 ok, 1 something\n"
	      "found (chatter flagged, energy --check failed, report drawing failed),\n"
	      "2 bad usage or input.\n",
	      f);
}

int main(int argc, char **argv)
{
	if (popc_stdfds_make_safe() != 0) /* a closed 0-2 on /dev/null, before any open (stdfds.h) */
		return 1;
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
		printf("popc-analyze %s\n", POPC_VERSION);
		return 0;
	}
	static const struct {
		const char *name;
		int (*run)(int, char **);
	} verbs[] = {
		{"energy", ana_cmd_energy},   {"chatter", ana_cmd_chatter},
		{"compare", ana_cmd_compare}, {"replay", ana_cmd_replay},
		{"report", ana_cmd_report},
	};
	for (size_t i = 0; i < sizeof verbs / sizeof verbs[0]; i++)
		if (strcmp(verb, verbs[i].name) == 0)
			return verbs[i].run(argc - 1, argv + 1);
	fprintf(stderr, "popc-analyze: unknown verb '%s'\n", verb);
	usage(stderr);
	return 2;
}
