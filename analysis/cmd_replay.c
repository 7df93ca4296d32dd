/* popc-analyze replay: run controller variants open loop over the recorded
 * position trace of a log and write one popc log per variant (source replay).
 * Open loop: the trace does not react to the replayed force; what changes is
 * what each controller would have commanded and observed on that trace. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "popc/core/admittance.h"
#include "popc/core/encoder.h"
#include "popc/core/port_energy.h"
#include "popc/log/log.h"
#include "popc/util/numfmt.h"
#include "popc/scene/from_scene.h"
#include "popc/util/atomic_file.h" /* popc_mkdir_p */
#include "popc/programs/usage_hint.h"

#define MAX_VARIANTS POPC_VARIANT_COUNT

static void usage(FILE *f)
{
	fputs("usage: popc-analyze replay LOG --variant NAME... [options]\n"
	      "\n"
	      "Runs each controller variant open loop over the recorded position trace of LOG\n"
	      "(its t and count columns, or x quantized to encoder.resolution) and writes one\n"
	      "popc log per variant (source = replay) that the other verbs read. The scene is\n"
	      "the log's header (popc logs) or the defaults, then --set. Replaying a popc log\n"
	      "with its own variant reproduces its rows exactly. An admittance log replays\n"
	      "the parallel PC variants over its recorded force counts (f_count).\n"
	      "\n"
	      "  --variant NAME           none, po-pc, ref-energy, filtered-velocity, ignore,\n"
	      "                           hold, improved, pc-off-reversals, energy-bounding,\n"
	      "                           windowed-po, or 'all' (repeatable); an admittance\n"
	      "                           log: none, parallel-pc, parallel-ignore,\n"
	      "                           parallel-hold, parallel-improved or 'all'; a\n"
	      "                           teleoperation log: tdpa-off, tdpa-on or 'all' (both\n"
	      "                           ports' PCs over the recorded channel; bounds from\n"
	      "                           --set teleop.master_pc_bound=, .slave_pc_bound=)\n"
	      "  -o, --output-dir DIR     write DIR/<log>.<variant>.csv (default: .); makes DIR\n"
	      "  --prefix P               write P<variant>.csv instead\n"
	      "  -q, --quiet              do not list the files written\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 2 bad usage, bad input or a log that could not be written.\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
}

enum { OPT_VARIANT = 256, OPT_PREFIX };

static const popc_option replay_options[] = {
	{"variant", 0, OPT_VARIANT, "VARIANT|all"},
	{"output-dir", 'o', 'o', "DIR"},
	{"prefix", 0, OPT_PREFIX, "PATH"},
	{"quiet", 'q', 'q', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_replay_opts[] = {replay_options, ana_input_option_table, NULL};

typedef struct replay_out {
	popc_scene scene;
	popc_controller *ctl;
	popc_log_writer w;
	char path[1100];
	int open;
} replay_out;

/* An impedance log replays the series PC variants over its positions, an
 * admittance log the parallel PC variants over its force counts
 * (replay_admittance.c); "none" and "all" name either. */
static const char adm_names[] = "none, parallel-pc, parallel-ignore, parallel-hold, "
				"parallel-improved or all";

static int admittance_variant_of(const char *name, popc_admittance_variant *v)
{
	for (int k = 0; popc_admittance_variant_names[k]; k++)
		if (strcmp(name, popc_admittance_variant_names[k]) == 0) {
			*v = (popc_admittance_variant)k;
			return 0;
		}
	return -1;
}

/* The output path of the variant named vn, checked: not the input, not a
 * directory, writable (nothing is opened yet). */
static int output_path(char *out, size_t cap, const char *vn, const char *dir, const char *prefix,
		       const char *log_name, const char *path)
{
	if (prefix)
		snprintf(out, cap, "%s%s.csv", prefix, vn);
	else
		snprintf(out, cap, "%s/%s.%s.csv", dir ? dir : ".", log_name, vn);
	char *self[1] = {(char *)path};
	if (ana_output_is_input(out, self, 1) >= 0) {
		fprintf(stderr,
			"popc-analyze replay: %s is the input log %s: refusing to overwrite it "
			"(choose another -o DIR or --prefix)\n",
			out, path);
		return POPC_EXIT_USAGE;
	}
	return ana_output_file_usable("replay", prefix ? "--prefix" : "-o", out);
}

int ana_cmd_replay(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_replay_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "replay";
	in.uses = ANA_USES_ENVIRONMENT | ANA_USES_CONTROLLER; /* the controllers read them */
	in.ignores = ANA_USES_VARIANT; /* --variant; the log's recomputed W is not used */
	popc_variant variants[MAX_VARIANTS];
	int n_var = 0, c, rc = 0, quiet = 0;
	/* the admittance variants asked for (bit per variant), and the first
	 * name that only one causality has */
	unsigned adm_mask = 0;
	const char *adm_only = NULL, *imp_only = NULL;
	/* teleoperation: bit 0 tdpa-off, bit 1 tdpa-on; the first such name */
	unsigned tele_mask = 0;
	const char *tele_only = NULL;
	const char *dir = NULL, *prefix = NULL;
	replay_out *outs = NULL;
	ana_log l;
	int log_open = 0;
	popc_error err;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_VARIANT: {
			/* a teleoperation log's: both ports' PCs off or on */
			if (strcmp(optarg, "tdpa-off") == 0 || strcmp(optarg, "tdpa-on") == 0) {
				tele_mask |= strcmp(optarg, "tdpa-on") == 0 ? 2u : 1u;
				if (!tele_only)
					tele_only = optarg;
				break;
			}
			if (strcmp(optarg, "all") == 0)
				tele_mask = 3u;
			popc_variant v;
			popc_admittance_variant av;
			int all = strcmp(optarg, "all") == 0;
			int is_imp = all || popc_variant_from_name(optarg, &v) == 0;
			int is_adm = all || admittance_variant_of(optarg, &av) == 0;
			if (!is_imp && !is_adm) {
				fprintf(stderr,
					"popc-analyze replay: --variant '%s': none, po-pc, ref-energy, "
					"filtered-velocity, ignore, hold, improved, pc-off-reversals, "
					"energy-bounding, windowed-po or all (an impedance log); %s (an "
					"admittance log)\n",
					optarg, adm_names);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			if (is_adm)
				adm_mask |= all ? (1u << POPC_ADMITTANCE_VARIANT_COUNT) - 1u : 1u << av;
			if (!is_imp) {
				if (!adm_only)
					adm_only = optarg;
				break;
			}
			if (!is_adm && !imp_only)
				imp_only = optarg;
			for (int k = 0; k < POPC_VARIANT_COUNT; k++) {
				if (!all && k != (int)v)
					continue;
				int dup = 0;
				for (int i = 0; i < n_var; i++)
					dup |= (int)variants[i] == k;
				if (!dup)
					variants[n_var++] = (popc_variant)k;
			}
			break;
		}
		case 'o': dir = optarg; break;
		case OPT_PREFIX: prefix = optarg; break;
		case 'q': quiet = in.quiet = 1; break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "replay")) != 0)
				goto out;
			break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (optind + 1 != argc || (n_var == 0 && adm_mask == 0 && tele_mask == 0) || (dir && prefix)) {
		fprintf(stderr, "popc-analyze replay: %s\n",
			optind >= argc       ? "missing LOG"
			: optind + 1 < argc  ? "exactly one LOG"
			: n_var == 0 && adm_mask == 0 && tele_mask == 0 ? "missing --variant"
					     : "--output-dir and --prefix exclude each other");
		popc_help_hint(argv[0], "options");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	const char *path = argv[optind];
	outs = calloc((size_t)(n_var ? n_var : 1), sizeof *outs);
	if (!outs) {
		fprintf(stderr, "popc-analyze replay: out of memory\n");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	/* every output path first, before the log is read: a directory that is
	 * not there, a path that is a directory, an output that is the input
	 * (nothing is opened, and so nothing truncated, before all are safe) */
	if (dir) {
		/* -o DIR makes DIR (and its parents), as every -o of popc does; a
		 * path that exists as a file is refused just below */
		popc_error merr;
		if (popc_mkdir_p(dir, &merr) != 0) {
			fprintf(stderr, "popc-analyze replay: -o %s: %s\n", dir, merr.msg);
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		if ((rc = ana_output_dir_usable("replay", "-o", dir, 0)) != 0)
			goto out;
	}
	char log_name[256];
	ana_log_name(path, log_name, sizeof log_name);
	/* an admittance variant's paths are checked once the log says its
	 * causality (below) */
	for (int i = 0; !adm_only && !tele_only && i < n_var; i++)
		if ((rc = output_path(outs[i].path, sizeof outs[i].path, popc_variant_name(variants[i]),
				      dir, prefix, log_name, path)) != 0)
			goto out;
	int st = ana_log_open(&l, path, &in, &err);
	if (st) {
		rc = ana_fail("replay", st, &err);
		goto out;
	}
	log_open = 1;
	if (l.scene.tele_arch != POPC_TELEOP_OFF || tele_only) {
		const int tele = l.scene.tele_arch != POPC_TELEOP_OFF;
		const char *other = imp_only ? imp_only : adm_only;
		if (!tele || other) {
			fprintf(stderr,
				tele ? "popc-analyze replay: %s is a teleoperation log (teleop.architecture "
				       "= %s): --variant '%s' is a one-port variant; a teleoperation log "
				       "replays tdpa-off, tdpa-on or all (docs/TELEOPERATION.md)\n"
				     : "popc-analyze replay: %s is a one-port log (teleop.architecture = "
				       "%s): --variant '%s' is a teleoperation variant\n",
				path, popc_teleop_architecture_names[l.scene.tele_arch],
				tele ? other : tele_only);
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		char tele_paths[2][1100];
		static const char *const tele_names[2] = {"tdpa-off", "tdpa-on"};
		for (int on = 0; on < 2; on++)
			if ((tele_mask & (1u << on)) &&
			    (rc = output_path(tele_paths[on], sizeof tele_paths[on], tele_names[on], dir,
					      prefix, log_name, path)) != 0)
				goto out;
		const popc_scene sc = l.scene;
		ana_log_close(&l);
		log_open = 0;
		rc = ana_replay_teleop(path, &sc, tele_mask, tele_paths, quiet);
		goto out;
	}
	if (l.scene.causality == POPC_CAUSALITY_ADMITTANCE || adm_only) {
		int adm = l.scene.causality == POPC_CAUSALITY_ADMITTANCE;
		if (adm && imp_only) {
			/* the series PC over recorded positions would be no replay of
			 * a device that measured force and was commanded a velocity */
			fprintf(stderr,
				"popc-analyze replay: %s is an admittance log (device.causality = "
				"admittance, header line %lld): --variant '%s' is an impedance (series PC) "
				"variant; an admittance log replays %s\n",
				path, popc_log_reader_header_line(&l.r, "device.causality"), imp_only,
				adm_names);
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		if (!adm) {
			fprintf(stderr,
				"popc-analyze replay: %s is an impedance log: --variant '%s' is an "
				"admittance (parallel PC) variant; an impedance log replays the series PC "
				"variants (popc-analyze replay --help)\n",
				path, adm_only);
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		popc_admittance_variant av[POPC_ADMITTANCE_VARIANT_COUNT];
		char adm_paths[POPC_ADMITTANCE_VARIANT_COUNT][1100];
		int n_adm = 0;
		for (int k = 0; k < POPC_ADMITTANCE_VARIANT_COUNT; k++)
			if (adm_mask & (1u << k))
				av[n_adm++] = (popc_admittance_variant)k;
		for (int i = 0; i < n_adm; i++)
			if ((rc = output_path(adm_paths[i], sizeof adm_paths[i],
					      popc_admittance_variant_name(av[i]), dir, prefix, log_name,
					      path)) != 0)
				goto out;
		rc = ana_replay_admittance(&l, path, &l.scene, av, adm_paths, n_adm, quiet);
		goto out;
	}
	popc_scene base = l.scene;
	if (l.period_from_time) {
		/* a foreign log without a rate: its first time step is the period */
		if (!(l.period_s > 0.0)) {
			fprintf(stderr, "popc-analyze replay: %s: cannot tell the period from the time "
					"column; give --set run.rate=HZ\n",
				path);
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		/* the replay logs' header holds the rate, which must read back as a
		 * scene's run.rate: a period outside its range would give logs that
		 * every verb refuses (1/5e-324 s was written as run.rate = inf) */
		char rate[POPC_DOUBLE_TEXT_MAX + 1];
		popc_format_double(1.0 / l.period_s, rate);
		char what[1200];
		snprintf(what, sizeof what, "%s: the period %g s (the first time step) is a rate of",
			 path, l.period_s);
		if ((st = popc_scene_set_option(&base, what, "run", "rate", rate, &err)) != 0) {
			fprintf(stderr, "popc-analyze replay: %s, which the replay logs' header must hold "
					"as run.rate (give --set run.rate=HZ if the time column is not in "
					"seconds)\n",
				err.msg);
			rc = POPC_EXIT_USAGE;
			goto out;
		}
	}
	unsigned columns = (l.c_x_true >= 0 ? POPC_LOG_COL_X_TRUE : 0u) |
			   (l.c_dt >= 0 && l.c_rtt >= 0 ? POPC_LOG_COL_TIMING : 0u);
	char extra[1400];
	snprintf(extra, sizeof extra, "# replay_of = %s\n# replay_of_variant = %s\n", path, l.variant);
	for (int i = 0; i < n_var; i++) {
		replay_out *o = &outs[i];
		o->scene = base;
		o->scene.variant = variants[i];
		popc_controller_config cfg;
		popc_controller_config_from_scene(&cfg, &o->scene);
		st = popc_controller_create(&cfg, &o->ctl, &err);
		if (!st)
			st = popc_log_open(&o->w, o->path, columns, &err);
		if (!st) {
			o->open = 1;
			st = popc_log_write_header(&o->w, "replay", &o->scene, extra, &err);
		}
		if (st) {
			rc = ana_fail("replay", st, &err);
			goto out;
		}
	}
	ana_row row;
	const double delta = base.enc_resolution_m;
	/* E_port goes with x_true: the true port energy of the recorded run (its
	 * f_c over its true trajectory), the same in every replay log and, for a
	 * popc log, equal to the input's E_port bit for bit (port_energy.h) */
	popc_port_energy port;
	popc_port_energy_init(&port);
	while ((st = ana_log_next(&l, &row, &err)) == 1) {
		double E_port_J = 0.0;
		if (columns & POPC_LOG_COL_X_TRUE) {
			E_port_J = popc_port_energy_update(&port, row.x_true_m);
			popc_port_energy_commit(&port, row.tick.f_c_N);
		}
		/* the measured position as the online loop forms it from the count */
		double x = popc_encoder_position(row.tick.count, delta);
		for (int i = 0; i < n_var; i++) {
			popc_log_row lr;
			memset(&lr, 0, sizeof lr);
			popc_controller_step(outs[i].ctl, row.tick.count, x, &lr.tick);
			lr.tick.t_s = row.tick.t_s;
			lr.x_true_m = row.x_true_m;
			lr.E_port_J = E_port_J;
			lr.dt_s = row.dt_s;
			lr.rtt_s = row.rtt_s;
			if ((st = popc_log_write_row(&outs[i].w, &lr, &err)) != 0) {
				rc = ana_fail("replay", st, &err);
				goto out;
			}
		}
	}
	if (st < 0) {
		rc = ana_fail("replay", st, &err);
		/* the rows replayed so far stay, marked as cut short like a run's log */
		for (int i = 0; i < n_var; i++) {
			popc_error cerr;
			if (outs[i].open)
				popc_log_write_comment(&outs[i].w, "stop", "input error", &cerr);
		}
		goto out;
	}
	for (int i = 0; i < n_var; i++) {
		/* an unfinished input gives replays as short as it is, and says so */
		st = popc_log_write_comment(&outs[i].w, "stop",
					    l.unfinished ? "input unfinished" : "completed", &err);
		if (!st)
			st = popc_log_close(&outs[i].w, &err);
		outs[i].open = 0;
		if (st) {
			rc = ana_fail("replay", st, &err);
		} else if (!quiet) {
			printf("%s\n", outs[i].path);
		}
	}
out:
	if (outs) {
		for (int i = 0; i < n_var; i++) {
			if (outs[i].open) {
				popc_error cerr;
				popc_log_close(&outs[i].w, &cerr);
			}
			popc_controller_free(outs[i].ctl);
		}
		free(outs);
	}
	if (log_open)
		ana_log_close(&l);
	ana_input_free(&in);
	return rc;
}
