/* popc bench integrators|loop|log: speed against error (docs/BENCHMARKS.md).
 *
 * integrators  work-precision: for each integrator and substep count, the
 *              maximum position error over the logged samples against the
 *              exact discretization, and the time per control step.
 * loop         the control loop without logging, exact against the paper's
 *              scheme (trapezoid at 100 substeps), side by side.
 * log          log writing against printf("%.17g"), log reading + energy
 *              recompute against strtod, and the reader's memory.
 *
 * This file reads the options and runs one of them: bench_integrators.c,
 * bench_loop.c (with bench_floor.c), bench_log.c; bench_common.c holds what
 * they share. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"
#include "cli.h"
#include "popc/util/atomic_file.h" /* popc_mkdir_p */
#include "popc/programs/table_out.h"
#include "popc/programs/usage_hint.h"

static void usage(FILE *f)
{
	fputs("usage: popc bench integrators|loop|log [options]\n"
	      "\n"
	      "Measures popc's speed against its error (docs/BENCHMARKS.md).\n"
	      "  integrators  work-precision table: per integrator and substep count, the max\n"
	      "               position error against the exact discretization (same force\n"
	      "               sequence for all: the exact run's f_c, replayed open loop) and\n"
	      "               the closed-loop time per control step; measured orders\n"
	      "  loop         control loop without logging: exact vs trapezoid at 100 substeps,\n"
	      "               and the tick's dependency chain alone (the floor any\n"
	      "               implementation of the tick meets); an admittance scene\n"
	      "               (device.causality = admittance): its loop against the same\n"
	      "               scene in impedance causality, alternated\n"
	      "  log          log writing vs printf(\"%.17g\"), reading + energy recompute vs\n"
	      "               strtod, reader memory for two log lengths\n"
	      "\n"
	      "  --scene FILE             scene (default: the built-in paper scene)\n"
	      "  --set section.key=value  override a scene key (repeatable)\n"
	      "  --format text|csv|json   output format (default text); json: the csv's rows\n"
	      "                           as one object each on one line, the same digits\n"
	      "  --plot DIR               integrators: write DIR/integrators.{dat,gp,png}\n"
	      "                           (DIR and its parents are made if missing)\n"
	      "  --min-time S             wall time per timing (default 0.2 s)\n"
	      "  --repeat N               timing repeats, fastest kept (default 3)\n"
	      "  --rows N                 log: rows per log (default 200000)\n"
	      "  --dir DIR                log: scratch directory (default $TMPDIR or /tmp)\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 1 failed, 2 usage. Figures and how to read them:\n"
	      "docs/BENCHMARKS.md.\n",
	      f);
}

enum { OPT_SCENE = 256, OPT_SET, OPT_FORMAT, OPT_PLOT, OPT_MIN_TIME, OPT_REPEAT, OPT_ROWS, OPT_DIR };

static int bench_what(const popc_scene *s0, const bench_opts *op, const char *what, int json);

static const popc_option bench_options[] = {
	{"scene", 0, OPT_SCENE, "SCENE"},
	{"set", 0, OPT_SET, "KEY=VALUE"},
	{"format", 0, OPT_FORMAT, "text|csv|json"},
	{"plot", 0, OPT_PLOT, "DIR"},
	{"min-time", 0, OPT_MIN_TIME, "S"},
	{"repeat", 0, OPT_REPEAT, "N"},
	{"rows", 0, OPT_ROWS, "N"},
	{"dir", 0, OPT_DIR, "DIR"},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const popc_cli_bench_opts[] = {bench_options, NULL};

/* The CSV text a benchmark wrote into the buffer (its header line, then its
 * rows) as JSON Lines on stdout; rc: the benchmark's exit status, kept
 * unless out of memory. Closes f and frees the buffer. */
static int json_from_csv(FILE *f, char **buf, size_t *len, int rc)
{
	int st = fclose(f) == 0 && *buf ? 0 : -1;
	if (!st && *len) {
		char *nl = strchr(*buf, '\n');
		if (nl)
			*nl = '\0';
		/* the first column names the row ("what", "integrator"); "status" is a word */
		static const char *const text_columns[] = {"what", "integrator", "status", NULL};
		popc_table_out t;
		st = popc_table_out_begin(&t, stdout, 1, *buf, text_columns);
		if (!st && nl) {
			fputs(nl + 1, popc_table_out_row(&t));
			st = popc_table_out_end(&t);
		} else if (!st) {
			st = popc_table_out_end(&t);
		}
	}
	free(*buf);
	*buf = NULL;
	if (st) {
		fprintf(stderr, "popc bench: out of memory\n");
		return POPC_EXIT_RUN_FAILED;
	}
	return rc;
}

int popc_cmd_bench(int argc, char **argv)
{
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_bench_opts, opts, shorts);
	bench_opts o = {.min_time_s = 0.2, .repeats = 3, .rows = 200000};
	int c, json = 0;
	long long lv;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_SCENE: o.scene_path = optarg; break;
		case OPT_SET:
			if (popc_arg_push(&o.sets, &o.n_sets, optarg) != 0) {
				fprintf(stderr, "popc bench: out of memory\n");
				free(o.sets);
				return POPC_EXIT_RUN_FAILED;
			}
			break;
		case OPT_FORMAT:
			json = strcmp(optarg, "json") == 0;
			if (strcmp(optarg, "csv") == 0 || json)
				o.csv = 1;
			else if (strcmp(optarg, "text") != 0) {
				fprintf(stderr, "popc bench: --format %s: expected text, csv or json\n", optarg);
				free(o.sets);
				return POPC_EXIT_USAGE;
			}
			break;
		case OPT_PLOT: o.plot_dir = optarg; break;
		case OPT_MIN_TIME:
			if (popc_parse_double_text(optarg, &o.min_time_s) != 0 ||
			    !(o.min_time_s >= 0 && o.min_time_s <= 60)) {
				fprintf(stderr, "popc bench: --min-time %s: expected seconds in [0, 60]\n",
					optarg);
				free(o.sets);
				return POPC_EXIT_USAGE;
			}
			break;
		case OPT_REPEAT:
			if (popc_parse_ll_text(optarg, 1, 100, &lv) != 0) {
				fprintf(stderr, "popc bench: --repeat %s: expected an integer in [1, 100]\n",
					optarg);
				free(o.sets);
				return POPC_EXIT_USAGE;
			}
			o.repeats = (int)lv;
			break;
		case OPT_ROWS:
			if (popc_parse_ll_text(optarg, 1000, 100000000, &lv) != 0) {
				fprintf(stderr, "popc bench: --rows %s: expected an integer in [1000, 1e8]\n",
					optarg);
				free(o.sets);
				return POPC_EXIT_USAGE;
			}
			o.rows = lv;
			break;
		case OPT_DIR: o.dir = optarg; break;
		case 'h': usage(stdout); free(o.sets); return 0;
		default: popc_option_hint(argv[0], opts, argc, argv); free(o.sets); return POPC_EXIT_USAGE;
		}
	}
	if (optind + 1 != argc) {
		fprintf(stderr, "popc bench: %s\n",
			optind >= argc ? "missing what to measure (integrators, loop or log)"
				       : "one thing to measure at a time");
		popc_help_hint(argv[0], "options");
		free(o.sets);
		return POPC_EXIT_USAGE;
	}
	const char *what = argv[optind];
	if (strcmp(what, "integrators") != 0 && strcmp(what, "loop") != 0 && strcmp(what, "log") != 0) {
		fprintf(stderr, "popc bench: unknown benchmark '%s' (integrators, loop or log)\n", what);
		free(o.sets);
		return POPC_EXIT_USAGE;
	}
	popc_scene s;
	popc_error err;
	int st = popc_cli_load_scene(&s, o.scene_path, o.sets, o.n_sets, &err);
	if (st) {
		free(o.sets);
		return popc_cli_fail("bench", st, &err);
	}
	/* o.sets lives on: bench loop runs `popc run` with them (bench_process.c) */
	int rc = bench_what(&s, &o, what, json);
	free(o.sets);
	return rc;
}

/* The benchmark WHAT of the loaded scene s (json: its CSV rows as JSON
 * Lines): an exit code. */
static int bench_what(const popc_scene *s0, const bench_opts *op, const char *what, int json)
{
	popc_scene s = *s0;
	bench_opts o = *op;
	popc_error err;
	int st;
	if (!popc_axis_is_simulated(&s)) {
		fprintf(stderr, "popc bench: the benchmarks run the simulated axis (axis = %s)\n", s.axis);
		return POPC_EXIT_USAGE;
	}
	/* the figure's directory is made (or refused) before half a minute of
	 * measuring, as report -o and sweep -o make theirs */
	if (o.plot_dir && (st = popc_mkdir_p(o.plot_dir, &err)) != 0) {
		fprintf(stderr, "popc bench: --plot %s: %s\n", o.plot_dir, err.msg);
		return POPC_EXIT_USAGE; /* an unusable output named on the command line: nothing ran */
	}
	/* a name that is already a file passes mkdir (EEXIST): the figure's
	 * files would fail to open after the measurement */
	struct stat sb;
	if (o.plot_dir && (stat(o.plot_dir, &sb) != 0 || !S_ISDIR(sb.st_mode) ||
			   access(o.plot_dir, W_OK | X_OK) != 0)) {
		fprintf(stderr, "popc bench: --plot %s: %s (the figure's files go into a directory)\n",
			o.plot_dir, stat(o.plot_dir, &sb) == 0 && !S_ISDIR(sb.st_mode) ? "not a directory"
												  : "cannot write into it");
		return POPC_EXIT_USAGE;
	}
	/* json: the CSV rows into a buffer, then each as one object with the
	 * header's names and the same cells (popc_table_out) */
	char *buf = NULL;
	size_t len = 0;
	o.out = json ? open_memstream(&buf, &len) : stdout;
	if (!o.out) {
		fprintf(stderr, "popc bench: out of memory\n");
		return POPC_EXIT_RUN_FAILED;
	}
	int rc = strcmp(what, "integrators") == 0 ? bench_integrators(&s, &o)
		 : strcmp(what, "loop") == 0	   ? bench_loop(&s, &o)
						   : bench_log(&s, &o);
	if (json)
		rc = json_from_csv(o.out, &buf, &len, rc);
	return rc;
}

