/* popc: the experiment runner. Verbs dispatch to cmd_*.c. */
#include <stdio.h>

#include "cli.h"
#include "popc/programs/verb.h"
#include "popc/programs/stdfds.h"
#include "popc_config.h"

int main(int argc, char **argv)
{
	if (popc_stdfds_make_safe() != 0) /* a closed 0-2 on /dev/null, before any open (stdfds.h) */
		return POPC_EXIT_RUN_FAILED;
	popc_cli_keep_argv(argc, argv);
	static const popc_verb verbs[] = {
		{"run", popc_cmd_run, "SCENE", "run one experiment"},
		{"scene", popc_cmd_scene, "show|keys", "print a resolved scene, or every scene key"},
		{"bench", popc_cmd_bench, "integrators|loop|log",
		 "speed against error (docs/BENCHMARKS.md)"},
		{"sweep", popc_cmd_sweep, "SCENE", "run a parameter sweep in parallel (Slurm, GNU parallel)"},
		{"map", popc_cmd_map, "SCENE", "stability map: the largest acceptable wall stiffness (Z-width)"},
	};
	/* --version names the build too (sweep plans record it: docs/SWEEPS.md) */
	static char version[256];
	snprintf(version, sizeof version, "%s (build %s)", popc_cli_version(), popc_cli_build_id());
	const popc_program popc = {
		.name = "popc",
		.version = version,
		.synopsis = "VERB [options]",
		.about = "Runs time-domain passivity controller (PO/PC) experiments on a simulated plant\n"
			 "or a Modbus servo axis and writes CSV logs (Ryu, Hannaford, Kwon, Kim 2005).\n",
		.footer = "'popc VERB --help' describes a verb. popc-analyze reads the logs.\n",
		.verbs = verbs,
		.n_verbs = sizeof verbs / sizeof verbs[0],
	};
	return popc_verb_dispatch(&popc, argc, argv);
}
