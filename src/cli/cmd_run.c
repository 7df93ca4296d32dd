/* popc run SCENE [--set k=v]... [--variant NAME] [--log FILE] [--summary FILE]
 *          [--summary-format csv|json] */
#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "popc/axes/axis.h"
#include "popc/log/log.h"
#include "popc/run/run.h"
#include "popc/util/same_file.h"
#include "popc/util/text_builder.h"
#include "popc/programs/usage_hint.h"
#include "progress.h"

static void usage(FILE *f)
{
	fputs("usage: popc run SCENE [options]\n"
	      "\n"
	      "Runs the scene's experiment (the simulated plant, or a servo axis) through the\n"
	      "virtual environment and the PO/PC variant, writes the CSV log and prints a\n"
	      "summary on standard error.\n"
	      "\n"
	      "  --set section.key=value  override a scene key (repeatable, validated)\n"
	      "  --variant NAME           controller.variant: none, po-pc, ref-energy,\n"
	      "                           filtered-velocity, ignore, hold, improved,\n"
	      "                           pc-off-reversals, energy-bounding, windowed-po\n"
	      "  --log FILE               write the CSV log to FILE ('-': standard output)\n"
	      "  --summary FILE           append the summary as a CSV row (header if new;\n"
	      "                           '-': standard output, with its header unless\n"
	      "                           appending to a file that is not empty; not\n"
	      "                           with --log -)\n"
	      "  --summary-format csv|json  the summary as a CSV row (default) or as one JSON\n"
	      "                           object on one line (JSON Lines: appending adds a\n"
	      "                           line; the CSV header's names, numbers as JSON\n"
	      "                           numbers, null for an empty cell; docs/READING.md);\n"
	      "                           a file holding the other format is refused\n"
	      "  --axis sim|modbus        axis.kind: the simulated plant or a servo drive\n"
	      "  --map FILE               axis.map: the drive's register map (docs/MODBUS.md);\n"
	      "                           --map and --connect only with axis.kind = modbus\n"
	      "  --connect URI            axis.connect:\n"
	      "                           " POPC_URI_NOTATION "\n"
	      "                           (" POPC_URI_DEFAULTS ";\n"
	      "                           FORMAT: data bits, parity N/E/O, stop bits)\n"
	      "  --free-run               modbus: no deadlines, each tick as soon as the last\n"
	      "                           is done (lockstep dry runs against popc-servo-sim)\n"
	      "  --rt                     modbus: try SCHED_FIFO and mlockall (notes if denied)\n"
	      "  --channel-log FILE       teleoperation: one row per packet event (sent, lost,\n"
	      "                           delivered, stale) of both channels to FILE\n"
	      "                           (docs/TELEOPERATION.md)\n"	      "  -q, --quiet              no summary and no progress line on standard error\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "A relative path (operator.table, axis.map) is relative to where it is written:\n"
	      "in the scene file, to the file's directory; on the command line (--set, --map),\n"
	      "to the working directory. popc makes it absolute, so the resolved scene in the\n"
	      "log header runs from any directory.\n"
	      "\n"
	      "SCENE and the map (--map, axis.map) may be names of installed files: a name\n"
	      "without a '/' that is no file where a relative path would point is looked up\n"
	      "in the data directories as scenes/NAME then scenes/NAME.ini (drives/ for a\n"
	      "map): 'popc run paper', '--map generic'. A path with a '/' is never looked\n"
	      "up; a local file of that name wins; the path found is recorded absolute.\n"
	      "POPC_DATA_PATH=DIR[:DIR...] sets the data directories ('popc scene list').\n"
	      "\n"
	      "Exit status: 0 done, 1 run failed, 2 bad scene or usage, 3 safety stop,\n"
	      "4 communication lost, 5 interrupted (safe state reached), 6 unstable: a\n"
	      "fixed-step integrator, or the closed loop itself diverged (the log says which).\n",
	      f);
}

enum { OPT_SET = 256, OPT_VARIANT, OPT_LOG, OPT_SUMMARY, OPT_SUMMARY_FORMAT, OPT_AXIS, OPT_MAP,
       OPT_CONNECT, OPT_FREE_RUN, OPT_RT, OPT_CHANNEL_LOG };

static const popc_option run_options[] = {
	{"set", 0, OPT_SET, "KEY=VALUE"},
	{"variant", 0, OPT_VARIANT, "VARIANT"},
	{"log", 0, OPT_LOG, "FILE"},
	{"summary", 0, OPT_SUMMARY, "FILE"},
	{"summary-format", 0, OPT_SUMMARY_FORMAT, "csv|json"},
	{"axis", 0, OPT_AXIS, "sim|modbus"},
	{"map", 0, OPT_MAP, "MAP"},
	{"connect", 0, OPT_CONNECT, "URI"},
	{"free-run", 0, OPT_FREE_RUN, NULL},
	{"rt", 0, OPT_RT, NULL},
	{"channel-log", 0, OPT_CHANNEL_LOG, "FILE"},
	{"quiet", 'q', 'q', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const popc_cli_run_opts[] = {run_options, NULL};

/* The summary as one JSON object on one line: the CSV header's names and the
 * row's cells, typed by the summary table (popc_run_summary_json_kind). */
static int write_summary_json(FILE *f, const char *header, const char *axis_names,
			      const char *row, const char *axis_values)
{
	size_t nl = strlen(header) + strlen(axis_names) + 1, rl = strlen(row) + strlen(axis_values) + 1;
	char *names_line = malloc(nl), *row_line = malloc(rl);
	if (!names_line || !row_line) {
		free(names_line);
		free(row_line);
		return -1;
	}
	snprintf(names_line, nl, "%s%s", header, axis_names);
	snprintf(row_line, rl, "%s%s", row, axis_values);
	const char *names[256];
	popc_json_kind kinds[256];
	int n = popc_json_csv_names(names_line, names, 256);
	for (int i = 0; i < n; i++)
		kinds[i] = strcmp(names[i], "scene") == 0 || strcmp(names[i], "scene_digest") == 0
				   ? POPC_JSON_TEXT /* a digest of digits only is still text */
				   : popc_run_summary_json_kind(names[i]);
	popc_json_csv_object(f, n, names, kinds, row_line, strlen(row_line));
	free(names_line);
	free(row_line);
	return 0;
}

/* The scene's columns of the summary (after the run's, before the axis'):
 * scene, the scene file as found (an installed scene's absolute path; empty
 * for the defaults), and scene_digest, "fnv1a-" and FNV-1a 64 (16 hex digits) of the
 * resolved scene as `popc scene show` prints it below its first line: two
 * rows with one digest ran one scene, whatever the files were called. */
static const char scene_names[] = ",scene,scene_digest";

/* An admittance run's columns (popc_run_summary's adm_ fields): the share of
 * ticks the parallel PC acted, the RMS and largest |v_pc| (m/s), the RMS
 * over the second half. */
static const char adm_names[] = ",v_pc_active,v_pc_rms,v_pc_max,v_pc_rms_late";

static int scene_cells(const popc_scene *s, const char *scene_path, char *out, size_t cap)
{
	char *text = NULL;
	size_t n = 0;
	FILE *m = open_memstream(&text, &n);
	if (!m)
		return -1;
	popc_scene_write(s, m, "");
	if (fclose(m) != 0 || !text) {
		free(text);
		return -1;
	}
	uint64_t h = 0xcbf29ce484222325u; /* FNV-1a 64: offset basis, prime */
	for (size_t i = 0; i < n; i++)
		h = (h ^ (unsigned char)text[i]) * 0x100000001b3u;
	free(text);
	/* the path as a CSV cell: quoted (RFC 4180) where it holds , " or a line break */
	const char *path = scene_path ? s->source : "";
	size_t len = 0;
	out[len++] = ',';
	int quote = strpbrk(path, ",\"\r\n") != NULL;
	if (quote)
		out[len++] = '"';
	for (const char *p = path; *p && len + 4 < cap; p++) {
		if (*p == '"')
			out[len++] = '"';
		out[len++] = *p;
	}
	if (quote)
		out[len++] = '"';
	/* "fnv1a-" first: a digest of 16 decimal digits is still text to every
	 * CSV reader, not a number */
	int w = snprintf(out + len, cap - len, ",fnv1a-%016" PRIx64, h);
	return w < 0 || (size_t)w >= cap - len ? -1 : 0;
}

/* Appends the run's summary row, and the axis' own columns (a real axis:
 * period and latency percentiles) after the run's, to f (opened for
 * appending before the run, so that a summary path that cannot be written
 * stops the run before it starts, not after it is done); an empty file, or a
 * stream without a position (standard output on a pipe or a terminal), gets
 * the header first. Closes f, or flushes it when it is stdout. */
static int write_summary_file(FILE *f, int json, const popc_run_summary *sum,
			      const popc_scene *s, const char *scene_path, const char *axis_names,
			      const char *axis_values)
{
	char *header = NULL, *row = NULL;
	char scene_values[POPC_PATH_MAX * 2 + 64];
	if (scene_cells(s, scene_path, scene_values, sizeof scene_values) != 0)
		return -1;
	/* an admittance run's own columns, after the run's and before the
	 * scene's, only in admittance causality: an impedance summary keeps its
	 * bytes (docs/ADMITTANCE.md, "Downstream") */
	char adm_values[4 * 40] = "";
	if (sum->has_admittance) {
		popc_text_builder t = {.buf = adm_values, .cap = sizeof adm_values, .len = 0};
		const double cells[] = {sum->adm_active, sum->adm_v_pc_rms_mps, sum->adm_v_pc_max_mps,
					sum->adm_v_pc_rms_late_mps};
		for (size_t i = 0; i < sizeof cells / sizeof cells[0]; i++) {
			popc_text_put(&t, ",", 1);
			popc_text_put_double_point(&t, isfinite(cells[i]) ? cells[i] : 0.0);
		}
		adm_values[t.len < sizeof adm_values ? t.len : sizeof adm_values - 1] = '\0';
	}
	char more_names[1200], more_values[sizeof scene_values + sizeof adm_values + 1024];
	snprintf(more_names, sizeof more_names, "%s%s%s", sum->has_admittance ? adm_names : "",
		 scene_names, axis_names);
	snprintf(more_values, sizeof more_values, "%s%s%s", adm_values, scene_values, axis_values);
	axis_names = more_names;
	axis_values = more_values;
	size_t hl = 0, rl = 0;
	FILE *m = open_memstream(&header, &hl);
	if (m) {
		popc_run_summary_csv_header(m);
		fclose(m);
	}
	m = open_memstream(&row, &rl);
	if (m) {
		popc_run_summary_csv_row(sum, s, m);
		fclose(m);
	}
	int st = -1;
	if (header && row && hl && rl) {
		header[hl - 1] = '\0'; /* the '\n': the axis' columns follow */
		row[rl - 1] = '\0';
		if (json) {
			st = write_summary_json(f, header, axis_names, row, axis_values);
		} else {
			/* a pipe cannot seek: ftell fails, and the reader gets a header */
			long at = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
			if (at <= 0)
				fprintf(f, "%s%s\n", header, axis_names);
			fprintf(f, "%s%s\n", row, axis_values);
			st = 0;
		}
	}
	if (f == stdout ? fflush(f) != 0 || ferror(f) : fclose(f) != 0)
		st = -1;
	free(header);
	free(row);
	return st;
}

/* No output may be one of the run's inputs: --log truncates its file before
 * the first tick and --summary appends to its file, so either onto the scene,
 * the operator table or the register map would destroy what the run reads
 * (or what a rerun needs); and --log and --summary onto one file would
 * interleave a log and a summary row. Existing files are compared by
 * st_dev/st_ino (popc_same_file: a link or another spelling counts); a file
 * that does not exist yet is no input. Returns 0, or -1 after saying which
 * option names which file. */
static int refuse_overwriting_inputs(const popc_scene *s, const char *scene_path,
				     const char *log_path, const char *summary_path,
				     const char *channel_log_path)
{
	const int tele = s->tele_arch != POPC_TELEOP_OFF;
	const struct {
		const char *what, *path;
	} inputs[] = {
		{"the scene file", scene_path},
		{"the operator table (operator.table)",
		 s->intent == POPC_INTENT_TABLE ? s->op_table : NULL},
		{"the register map (axis.map)", strcmp(s->axis, "modbus") == 0 ? s->axis_map : NULL},
		{"the forward delay trace (forward.trace)", tele ? s->fwd.trace : NULL},
		{"the backward delay trace (backward.trace)", tele ? s->bwd.trace : NULL},
	};
	const struct {
		const char *option, *path;
	} outputs[] = {{"--log", log_path}, {"--summary", summary_path},
		       {"--channel-log", channel_log_path}};
	for (size_t o = 0; o < sizeof outputs / sizeof outputs[0]; o++)
		for (size_t i = 0; i < sizeof inputs / sizeof inputs[0]; i++)
			if (popc_same_file(outputs[o].path, inputs[i].path)) {
				fprintf(stderr,
					"popc run: %s %s is %s %s: refusing to overwrite an input "
					"(choose another %s)\n",
					outputs[o].option, outputs[o].path, inputs[i].what, inputs[i].path,
					outputs[o].option);
				return -1;
			}
	/* the two outputs, also when neither exists yet ("-" twice is refused
	 * with the usage) */
	if (log_path && summary_path && strcmp(log_path, "-") != 0 &&
	    (strcmp(log_path, summary_path) == 0 || popc_same_file(log_path, summary_path))) {
		fprintf(stderr,
			"popc run: --log %s and --summary %s are the same file: give each its own\n",
			log_path, summary_path);
		return -1;
	}
	/* the channel log beside the other two outputs */
	const char *other[2] = {log_path, summary_path}, *other_opt[2] = {"--log", "--summary"};
	for (int i = 0; channel_log_path && i < 2; i++)
		if (other[i] && (strcmp(other[i], channel_log_path) == 0 ||
				 popc_same_file(other[i], channel_log_path))) {
			fprintf(stderr,
				"popc run: --channel-log %s and %s %s are the same file: give each its "
				"own\n",
				channel_log_path, other_opt[i], other[i]);
			return -1;
		}
	return 0;
}

/* --summary appends: onto a file that holds the other format it would mix
 * them (a JSON object under a CSV header, a headerless CSV row among JSON
 * Lines), and neither reader could take the file afterwards. What a file
 * holds is told by its first byte: a JSON Lines summary starts with '{', a
 * CSV one with its header's first name. An empty or missing file (or "-")
 * holds nothing yet. Returns 0, or -1 after naming the file and its format. */
static int refuse_mixed_summary(const char *summary_path, int json, int admittance)
{
	/* a regular file only: a FIFO or a terminal (/dev/stdout) would block
	 * the read, and holds nothing to mix with */
	struct stat sb;
	if (!summary_path || strcmp(summary_path, "-") == 0 || stat(summary_path, &sb) != 0 ||
	    !S_ISREG(sb.st_mode))
		return 0;
	FILE *f = fopen(summary_path, "r");
	if (!f)
		return 0; /* not there yet, or unreadable: opening it for appending says */
	/* the first line: a CSV header says which causality's columns it has */
	char line[4096];
	int c = fgetc(f);
	if (c != EOF) {
		line[0] = (char)c;
		if (!fgets(line + 1, (int)sizeof line - 1, f))
			line[1] = '\0';
	}
	fclose(f);
	if (c == EOF)
		return 0;
	int holds_json = c == '{';
	if (holds_json == json && !json) {
		/* an admittance row has 4 cells more (adm_names): under the other
		 * causality's header its cells would be misread */
		int holds_adm = strstr(line, ",v_pc_active,") != NULL;
		if (holds_adm == admittance)
			return 0;
		fprintf(stderr,
			"popc run: --summary %s holds %s runs' rows (line 1 %s the columns "
			"v_pc_active...): refusing to append an %s run's row to it (another file)\n",
			summary_path, holds_adm ? "admittance" : "impedance", holds_adm ? "has" : "lacks",
			admittance ? "admittance" : "impedance");
		return -1;
	}
	if (holds_json == json)
		return 0;
	fprintf(stderr,
		"popc run: --summary %s holds %s (line 1 %s): refusing to append %s to it "
		"(give --summary-format %s, or another file)\n",
		summary_path, holds_json ? "JSON Lines" : "CSV",
		holds_json ? "is a JSON object" : "is not a JSON object: a CSV header",
		json ? "a JSON line" : "a CSV row", holds_json ? "json" : "csv");
	return -1;
}

/* popc run's progress line (progress.h): simulated (or run) time against
 * the scene's duration, checked every 1024 ticks so that the clock is read
 * about once a millisecond of simulated time at 1 kHz, not every tick. */
typedef struct run_progress {
	cli_progress line;
	double duration_s, t_s;
	long long ticks;
} run_progress;

static void draw_progress(run_progress *p, int final)
{
	double el = cli_progress_elapsed_s(&p->line);
	double frac = p->duration_s > 0.0 ? p->t_s / p->duration_s : 1.0;
	double eta = frac > 0.0 ? el * (1.0 - frac) / frac : -1.0;
	char eta_text[32], counts[96], rest[64];
	cli_format_duration(eta, eta_text, sizeof eta_text);
	snprintf(counts, sizeof counts, "%.4g/%.4g s", p->t_s, p->duration_s);
	snprintf(rest, sizeof rest, "ETA %s", eta_text);
	cli_progress_bar(&p->line, "popc run: ", frac, counts, rest, final);
}

static void show_progress(void *user, const popc_tick *tick)
{
	run_progress *p = user;
	p->t_s = tick->t_s;
	if ((++p->ticks & 1023) == 0 && cli_progress_due(&p->line, 0))
		draw_progress(p, 0);
}

/* completed: the run reached its duration (the last tick is one period short) */
static void progress_end(run_progress *p, int completed)
{
	if (completed)
		p->t_s = p->duration_s;
	if (cli_progress_due(&p->line, 1))
		draw_progress(p, 1);
}

/* A log of 100 MB or more is announced before the run starts (a mistyped
 * run.duration=5000 wrote 852 MB without a word): its rows and size, at 14
 * bytes a cell as measured (the paper scene's 5 s log: 834160 bytes, 5001
 * rows of 12 cells). */
static void note_log_size(const char *path, const popc_scene *s, unsigned columns)
{
	char names[2048];
	popc_log_column_names(columns, names, sizeof names);
	int cells = 1;
	for (const char *c = names; *c; c++)
		cells += *c == ',';
	double rows = (double)popc_scene_ticks(s) + 1.0;
	double bytes = rows * cells * 14.0;
	if (bytes < 100e6)
		return;
	fprintf(stderr,
		"popc run: note: the log %s will be about %.3g MB (%.0f rows of %d cells, "
		"run.duration = %g s at %g Hz); a signal (Ctrl-C) stops the run with the rows "
		"so far kept\n",
		path, bytes / 1e6, rows, cells, s->duration_s, s->rate_Hz);
}

int popc_cmd_run(int argc, char **argv)
{
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_run_opts, opts, shorts);
	char **sets = NULL;
	int n_sets = 0, quiet = 0, c;
	const char *variant = NULL, *log_path = NULL, *summary_path = NULL, *channel_log_path = NULL;
	int summary_json = 0;
	const char *axis_opt[3] = {NULL, NULL, NULL}; /* --axis, --map, --connect */
	/* a signal ends a real axis' retries and waits too */
	popc_axis_create_options axis_create = {.notes = stderr, .stop_flag = &popc_cli_stop};
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_SET:
			if (popc_arg_push(&sets, &n_sets, optarg) != 0) {
				fprintf(stderr, "popc run: out of memory\n");
				free(sets);
				return POPC_EXIT_RUN_FAILED;
			}
			break;
		case OPT_VARIANT: variant = optarg; break;
		case OPT_LOG: log_path = optarg; break;
		case OPT_SUMMARY: summary_path = optarg; break;
		case OPT_SUMMARY_FORMAT:
			if (strcmp(optarg, "csv") != 0 && strcmp(optarg, "json") != 0) {
				fprintf(stderr, "popc run: --summary-format '%s': csv or json\n", optarg);
				free(sets);
				return POPC_EXIT_USAGE;
			}
			summary_json = strcmp(optarg, "json") == 0;
			break;
		case OPT_AXIS: axis_opt[0] = optarg; break;
		case OPT_MAP: axis_opt[1] = optarg; break;
		case OPT_CONNECT: axis_opt[2] = optarg; break;
		case OPT_FREE_RUN: axis_create.free_run = 1; break;
		case OPT_RT: axis_create.realtime = 1; break;
		case OPT_CHANNEL_LOG: channel_log_path = optarg; break;
		case 'q': quiet = 1; break;
		case 'h': usage(stdout); free(sets); return 0;
		default: popc_option_hint(argv[0], opts, argc, argv); free(sets); return POPC_EXIT_USAGE;
		}
	}
	if (popc_cli_assignment_split("run", "--set", sets, n_sets)) {
		free(sets);
		return POPC_EXIT_USAGE;
	}
	int summary_stdout = summary_path && strcmp(summary_path, "-") == 0;
	if (optind + 1 != argc || (summary_stdout && log_path && strcmp(log_path, "-") == 0)) {
		const char *why = optind >= argc      ? "missing SCENE file"
				  : optind + 1 != argc ? "more than one SCENE file"
						       : "--log - and --summary - both name standard "
							 "output: give one of them a file";
		fprintf(stderr, "popc run: %s\n", why);
		popc_help_hint(argv[0], "options");
		free(sets);
		return POPC_EXIT_USAGE;
	}
	if (popc_cli_stdout_closed("run", "--log", log_path) ||
	    popc_cli_stdout_closed("run", "--summary", summary_path)) {
		free(sets);
		return POPC_EXIT_USAGE;
	}
	popc_scene s;
	popc_error err;
	/* keys with options of their own, applied after --set; their errors
	 * name the option typed ("--variant 'x': ... allowed one of ...") */
	const popc_cli_key_option key_opts[] = {
		{"--variant", "controller", "variant", variant},
		{"--axis", "axis", "kind", axis_opt[0]},
		{"--map", "axis", "map", axis_opt[1]},
		{"--connect", "axis", "connect", axis_opt[2]},
	};
	int st = popc_cli_load_scene_options(&s, argv[optind], sets, n_sets, key_opts,
					     (int)(sizeof key_opts / sizeof key_opts[0]), &err);
	free(sets);
	if (st)
		return popc_cli_fail("run", st, &err);
	if (channel_log_path && (s.tele_arch == POPC_TELEOP_OFF || strcmp(channel_log_path, "-") == 0)) {
		fprintf(stderr,
			"popc run: --channel-log %s: %s\n", channel_log_path,
			s.tele_arch == POPC_TELEOP_OFF
				? "only for a teleoperation scene (teleop.architecture is off: the "
				  "scene has no channel)"
				: "give a file (standard output is for --log - or --summary -)");
		return POPC_EXIT_USAGE;
	}
	if (refuse_overwriting_inputs(&s, argv[optind], log_path, summary_path, channel_log_path) != 0 ||
	    refuse_mixed_summary(summary_path, summary_json,
				 s.causality == POPC_CAUSALITY_ADMITTANCE) != 0)
		return POPC_EXIT_USAGE;
	/* --map and --connect set keys that only a Modbus axis reads: on the
	 * simulated one they would do nothing, silently */
	for (int o = 1; o <= 2; o++)
		if (axis_opt[o] && strcmp(s.axis, "modbus") != 0) {
			fprintf(stderr,
				"popc run: %s %s: only for axis.kind = modbus, and axis.kind is %s "
				"(give --axis modbus, or leave %s out)\n",
				key_opts[o + 1].option, axis_opt[o], s.axis, key_opts[o + 1].option);
			return POPC_EXIT_USAGE;
		}

	/* --free-run and --rt change how a Modbus axis keeps time: the simulated
	 * one has no deadlines and no drive, so they would do nothing, silently */
	if ((axis_create.free_run || axis_create.realtime) && strcmp(s.axis, "modbus") != 0) {
		fprintf(stderr,
			"popc run: %s: only for axis.kind = modbus, and axis.kind is %s (the simulated "
			"axis keeps no deadlines and runs as fast as it can: leave %s out)\n",
			axis_create.free_run ? "--free-run" : "--rt", s.axis,
			axis_create.free_run ? "--free-run" : "--rt");
		return POPC_EXIT_USAGE;
	}

	popc_axis *axis = NULL;
	st = popc_axis_create(&axis, &s, &axis_create, &err);
	if (st)
		return popc_cli_fail("run", st, &err);

	FILE *summary = summary_stdout ? stdout : NULL;
	/* a summary file this run creates is removed again when the run fails
	 * before its first tick (the log cannot be opened): it would be left
	 * empty, a summary of nothing */
	int summary_created = summary_path && !summary_stdout && access(summary_path, F_OK) != 0;
	if (summary_path && !summary_stdout && !(summary = fopen(summary_path, "a"))) {
		st = popc_error_set(&err, POPC_ERR_IO, "%s: cannot open the summary for appending: %s",
				    summary_path, strerror(errno));
		popc_axis_destroy(&axis);
		return popc_cli_fail("run", st, &err);
	}
	popc_log_writer log;
	/* -q without --summary: nobody reads the summary's metrics (run.h) */
	popc_run_options ro = {.log = NULL, .stop_flag = &popc_cli_stop,
			       .summary_unread = quiet && !summary_path};
	if (channel_log_path && !(ro.channel_log = fopen(channel_log_path, "w"))) {
		st = popc_error_set(&err, POPC_ERR_IO, "%s: cannot open the channel log: %s",
				    channel_log_path, strerror(errno));
		if (summary && summary != stdout)
			fclose(summary);
		popc_axis_destroy(&axis);
		return popc_cli_fail("run", st, &err);
	}
	if (log_path) {
		st = popc_log_open(&log, log_path, popc_run_log_columns(&s, axis), &err);
		/* which build, when, what command: the header says how to make
		 * the log again (without them on out of memory: the run goes on) */
		char *provenance = st ? NULL : popc_cli_provenance();
		if (!st && (st = popc_log_write_header(&log, axis->ops->name, &s, provenance, &err)) != 0) {
			popc_error cerr; /* the header did not go out (a full disk): err says so */
			popc_log_close(&log, &cerr);
		}
		free(provenance);
		if (st) {
			if (summary && summary != stdout) {
				fclose(summary);
				if (summary_created)
					remove(summary_path);
			}
			if (ro.channel_log)
				fclose(ro.channel_log);
			popc_axis_destroy(&axis);
			return popc_cli_fail("run", st, &err);
		}
		ro.log = &log;
		if (!quiet)
			note_log_size(log_path, &s, popc_run_log_columns(&s, axis));
	}
	popc_cli_install_signals(!popc_axis_is_simulated(&s));
	/* the progress line: on a terminal, not with -q, once the run has taken
	 * a second (POPC_PROGRESS_AFTER_S); the hook is set only then, so a run
	 * whose stderr is a file or a pipe runs exactly as before */
	run_progress prog = {.duration_s = s.duration_s};
	cli_progress_start(&prog.line, quiet, cli_progress_after_s(1.0));
	if (prog.line.shown) {
		ro.on_tick = show_progress;
		ro.tick_user = &prog;
	}
	popc_run_summary sum;
	int run_st = popc_run(&s, axis, &ro, &sum, &err);
	progress_end(&prog, run_st == 0 && !popc_cli_stop);
	popc_error cerr;
	int close_st = log_path ? popc_log_close(&log, &cerr) : 0;
	if (ro.channel_log && (ferror(ro.channel_log) | fclose(ro.channel_log)) && !close_st)
		close_st = popc_error_set(&cerr, POPC_ERR_IO, "%s: cannot write the channel log",
					  channel_log_path);
	/* a run that failed before its first tick (a drive that could not be
	 * reached) has no statistics: ten lines of zeros would hide the error,
	 * which popc_cli_fail prints below, with what to check */
	int no_tick = run_st != 0 && sum.ticks == 0;
	if (!quiet && !no_tick)
		popc_run_summary_print(&sum, &s, stderr);
	if (!quiet && !log_path) /* the rows are gone: say so, once */
		fprintf(stderr, "popc run: note: no --log given, so the run's log was not kept "
				"(--log FILE keeps it; -q says nothing)\n");
	char axis_names[1024] = "", axis_values[1024] = "";
	if (axis->ops->report) /* period and latency percentiles of a real axis */
		axis->ops->report(axis, quiet || no_tick ? NULL : stderr, axis_names, axis_values,
				  sizeof axis_names);
	popc_axis_destroy(&axis);
	if (summary && write_summary_file(summary, summary_json, &sum, &s, argv[optind], axis_names,
					  axis_values) != 0) {
		fprintf(stderr, "popc run: %s: cannot write the summary: %s\n", summary_path,
			strerror(errno));
		if (!run_st)
			return POPC_EXIT_RUN_FAILED;
	}
	if (run_st) {
		int code = popc_cli_fail("run", run_st, &err);
		if (no_tick && strstr(err.msg, "cannot connect"))
			fprintf(stderr,
				"popc run: hint: is the drive (or popc-servo-sim) on and listening at %s? "
				"Check the host and port (or device and baud) in --connect / axis.connect "
				"(docs/MODBUS.md)\n",
				s.axis_connect);
		return code;
	}
	if (close_st)
		return popc_cli_fail("run", close_st, &cerr);
	return 0;
}
