/* popc-analyze teleop: transparency of teleoperation logs (docs/
 * TELEOPERATION.md, "Analysing a log"): position drift between master and
 * slave, force tracking between the master's command and the slave's
 * sensor, each port's PC activity, energies and chatter (teleop_log.h). */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "popc/programs/usage_hint.h"

static void usage(FILE *f)
{
	fputs("usage: popc-analyze teleop [options] LOG...\n"
	      "\n"
	      "Transparency of a teleoperation log (teleop.architecture not off): position\n"
	      "drift x - xs (end, largest, RMS) as measured, and delayed: x(k - fwd_age(k))\n"
	      "- xs(k), the master position the slave's held packet carries; force tracking\n"
	      "f_c + fs (RMS, largest |.|; f_c = -fs when rendered exactly) as measured, and\n"
	      "delayed: f_c(k) + fs(k - bwd_age(k)), what the master's PC and losses add to\n"
	      "the force received; each port's PC activity, energies and smallest two-port\n"
	      "margin. Definitions: docs/TELEOPERATION.md, \"Analysing a log\".\n"
	      "\n"
	      "  --format text|csv|markdown|json  text (default): a paragraph per log; the\n"
	      "                           others: compare's teleoperation table\n"
	      "  --threshold NAME=VALUE   a chatter threshold (see 'chatter --help')\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 2 bad usage or input (a one-port log is refused).\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
}

enum { OPT_FORMAT = 256, OPT_THRESHOLD };

static const popc_option teleop_options[] = {
	{"format", 0, OPT_FORMAT, "text|csv|markdown|json"},
	{"threshold", 0, OPT_THRESHOLD, "NAME=VALUE"},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_teleop_opts[] = {teleop_options, ana_input_option_table, NULL};

static void print_port(const char *name, const char *unit, const ana_tele_port *p, long long ticks)
{
	printf("  %s port: PC active %.4g %% (%lld ticks), |d| RMS %.4g %s, max %.4g %s, clamped "
	       "%lld; E_in %.4g J, E_out %.4g J, received %.4g J, smallest margin %.3g J\n",
	       name, ticks > 0 ? 100.0 * (double)p->active / (double)ticks : 0.0, p->active,
	       p->pc_rms, unit, p->pc_max, unit, p->clamped, p->in_J, p->out_J, p->rx_J,
	       p->margin_min_J);
}

static void print_text(const char *log, const popc_scene *sc, const ana_tele_summary *s)
{
	printf("%s: teleop %s, PCs %s, delay %.4g s forward, %.4g s backward, %lld ticks "
	       "(%.4g s)\n",
	       log, popc_teleop_architecture_names[sc->tele_arch], s->tdpa ? "on" : "off",
	       s->fwd_delay_s, s->bwd_delay_s, s->ticks, s->duration_s);
	printf("  drift x - xs: end %.4g m, largest %.4g m, RMS %.4g m", s->drift_end_m,
	       s->drift_max_m, s->drift_rms_m);
	if (s->drift_al_n > 0)
		printf("; delayed: end %.4g m, largest %.4g m, RMS %.4g m\n", s->drift_al_end_m,
		       s->drift_al_max_m, s->drift_al_rms_m);
	else
		printf("; delayed: n/a (no packet held)\n");
	printf("  force tracking f_c + fs: RMS %.4g N, largest %.4g N", s->track_rms_N,
	       s->track_max_N);
	if (s->track_al_n > 0)
		printf("; delayed: RMS %.4g N, largest %.4g N\n", s->track_al_rms_N,
		       s->track_al_max_N);
	else
		printf("; delayed: n/a (no packet held)\n");
	print_port("master", "N", &s->m, s->ticks);
	print_port("slave", "m/s", &s->s, s->ticks);
}

int ana_cmd_teleop(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_teleop_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "teleop";
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	ana_format fmt = ANA_TEXT;
	int c, rc = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_FORMAT:
			if (ana_format_from_name(optarg, &fmt) != 0) {
				fprintf(stderr, "popc-analyze teleop: --format '%s': text, csv, markdown or "
						"json\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case OPT_THRESHOLD:
			if ((rc = ana_threshold_option(&cc, optarg, "teleop")) != 0)
				goto out;
			break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "teleop")) != 0)
				goto out;
			break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc-analyze teleop: missing LOG\n");
		popc_help_hint(argv[0], "options");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	const int n = argc - optind;
	char (*names)[ANA_LOG_NAME_MAX] = malloc((size_t)n * sizeof *names);
	ana_summary *all = calloc((size_t)n, sizeof *all);
	char **lognames = calloc((size_t)n, sizeof *lognames);
	const ana_tele_summary **ts = calloc((size_t)n, sizeof *ts);
	if (!names || !all || !lognames || !ts || ana_log_names(argv + optind, n, names) != 0) {
		fprintf(stderr, "popc-analyze teleop: out of memory\n");
		rc = POPC_EXIT_RUN_FAILED;
		goto done;
	}
	for (int i = 0; i < n; i++) {
		popc_error err;
		lognames[i] = names[i];
		int st = ana_summarize(argv[optind + i], &in, &cc, -1.0, &all[i], NULL, NULL, &err);
		if (st) {
			rc = ana_fail("teleop", st, &err);
			continue;
		}
		if (!all[i].teleop) {
			fprintf(stderr,
				"popc-analyze teleop: %s is not a teleoperation log (teleop.architecture "
				"= off: no slave or network columns); 'popc-analyze compare' summarizes a "
				"one-port log\n",
				argv[optind + i]);
			rc = POPC_EXIT_USAGE;
			continue;
		}
		ts[i] = &all[i].tele;
		if (fmt == ANA_TEXT)
			print_text(names[i], &all[i].tele_scene, &all[i].tele);
	}
	if (fmt != ANA_TEXT && ana_tele_table(stdout, (int)fmt, lognames, ts, n) != 0) {
		fprintf(stderr, "popc-analyze teleop: out of memory\n");
		rc = POPC_EXIT_RUN_FAILED;
	}
	if (fflush(stdout) != 0)
		rc = POPC_EXIT_USAGE;
done:
	free(names);
	free(all);
	free(lognames);
	free(ts);
out:
	ana_input_free(&in);
	return rc;
}
