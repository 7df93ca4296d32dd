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
	/* sub-verbs: listed for --complete (verb.h); their verb dispatches them */
	static const popc_verb scene_subs[] = {
		{"show", NULL, "SCENE", "", popc_cli_scene_show_opts, NULL, 0},
		{"keys", NULL, "", "", popc_cli_scene_keys_opts, NULL, 0},
		{"list", NULL, "", "", popc_cli_scene_list_opts, NULL, 0},
	};
	static const popc_verb bench_subs[] = {
		{"integrators", NULL, "", "", popc_cli_bench_opts, NULL, 0},
		{"loop", NULL, "", "", popc_cli_bench_opts, NULL, 0},
		{"log", NULL, "", "", popc_cli_bench_opts, NULL, 0},
	};
	static const popc_verb sweep_subs[] = {
		{"merge", NULL, "DIR...", "", popc_cli_sweep_merge_opts, NULL, 0},
		{"stats", NULL, "DIR", "", popc_cli_sweep_stats_opts, NULL, 0},
	};
#define SUBS(a) a, sizeof a / sizeof a[0]
	static const popc_verb verbs[] = {
		{"run", popc_cmd_run, "SCENE", "run one experiment", popc_cli_run_opts, NULL, 0},
		{"scene", popc_cmd_scene, "show|keys|list", "print a resolved scene, every scene key, or the installed scenes",
		 popc_cli_scene_opts, SUBS(scene_subs)},
		{"bench", popc_cmd_bench, "integrators|loop|log",
		 "speed against error (docs/BENCHMARKS.md)", popc_cli_bench_opts, SUBS(bench_subs)},
		{"sweep", popc_cmd_sweep, "SCENE",
		 "run a parameter sweep in parallel (Slurm, GNU parallel); sweep merge, sweep stats",
		 popc_cli_sweep_opts, SUBS(sweep_subs)},
		{"map", popc_cmd_map, "SCENE", "stability map: the largest acceptable wall stiffness (Z-width)",
		 popc_cli_map_opts, NULL, 0},
	};
#undef SUBS
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
