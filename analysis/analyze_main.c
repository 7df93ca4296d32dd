/* popc-analyze: the offline analyser of popc and device logs. Verbs dispatch
 * to cmd_*.c. */
#include "analyze.h"
#include "popc/programs/verb.h"
#include "popc/programs/stdfds.h"
#include "popc_config.h"

int main(int argc, char **argv)
{
	if (popc_stdfds_make_safe() != 0) /* a closed 0-2 on /dev/null, before any open (stdfds.h) */
		return POPC_EXIT_RUN_FAILED;
	static const popc_verb verbs[] = {
		{"energy", ana_cmd_energy, "LOG...", "recompute W and E_ref with each observer definition", ana_energy_opts, NULL, 0},
		{"chatter", ana_cmd_chatter, "LOG...", "flag PC chattering intervals and limit cycles", ana_chatter_opts, NULL, 0},
		{"compare", ana_cmd_compare, "LOG...", "one row of metrics per log (text, CSV, Markdown)", ana_compare_opts, NULL, 0},
		{"replay", ana_cmd_replay, "LOG --variant V",
		 "run controller variants over a recorded position trace", ana_replay_opts, NULL, 0},
		{"events", ana_cmd_events, "LOG...",
		 "the paper's timeline: velocity settling, Fig. 5 and Fig. 8 events", ana_events_opts, NULL, 0},
		{"teleop", ana_cmd_teleop, "LOG...",
		 "teleoperation logs: position drift, force tracking, each port's PC", ana_teleop_opts, NULL, 0},
		{"report", ana_cmd_report, "LOG... -o DIR", "gnuplot figures (PNG, PDF), table and index page", ana_report_opts, NULL, 0},
	};
	static const popc_program analyze = {
		.name = "popc-analyze",
		.version = POPC_VERSION,
		.synopsis = "VERB [options] LOG...",
		.about = "Analyses CSV logs of popc (and recorded device logs, with --column) after the\n"
			 "fact: energies, chatter, comparison of controller variants, replay, reports.\n",
		.footer = "'popc-analyze VERB --help' describes a verb. Exit status: 0 ok, 1 something\n"
			  "found (chatter flagged, energy --check failed, report drawing failed),\n"
			  "2 bad usage or input.\n",
		.verbs = verbs,
		.n_verbs = sizeof verbs / sizeof verbs[0],
	};
	return popc_verb_dispatch(&analyze, argc, argv);
}
