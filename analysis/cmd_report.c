/* popc-analyze report: gnuplot figures (PNG and PDF) that reproduce the
 * paper's (report_figures.c): per log the contact response (Figs. 3, 10, 14,
 * 16 by variant), the velocity (Fig. 4), zooms at the events of Figs. 5 and
 * 8, force against position (Figs. 6, 7); for all logs an overlay on shared
 * axes, the comparison table and an index page (report_index.c). Whole-log
 * data are min/max decimated and the zooms keep a bounded window of raw rows
 * (report_window.c), so memory is bounded; the gnuplot scripts stay beside the
 * figures so users can restyle and rerun them. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "popc/util/parse.h"
#include "popc/programs/usage_hint.h"
#include "report.h"

#define MAX_LOGS 256
#define FIGS_DEFAULT                                                                               \
	((1u << RF_CONTACT) | (1u << RF_FIG4) | (1u << RF_FIG5) | (1u << RF_FIG6) | (1u << RF_FIG8) | \
	 (1u << RF_FIG11))

static void usage(FILE *f)
{
	fputs("usage: popc-analyze report [options] -o DIR LOG...\n"
	      "\n"
	      "Writes into DIR the figures of each LOG that reproduce the figures of Ryu,\n"
	      "Hannaford, Kwon, Kim (IEEE T-RO 2005), each as NAME<suffix>.png and .pdf with its\n"
	      "gnuplot script (.gp) and data (.dat); every figure names the paper figure, the log\n"
	      "and the scene's parameters:\n"
	      "  NAME        paper Fig. 3, 10, 14 or 16 (by the log's variant): position measured\n"
	      "              and true zoomed to the contact, velocity, W with E_ref (and E_port\n"
	      "              when logged), W - E_ref, f_pc (chatter shaded), f_c\n"
	      "  NAME-fig4   paper Fig. 4: the backward velocity, whole and at +-4 counts\n"
	      "  NAME-fig5   paper Fig. 5: zoom at the velocity sign change (found in the log)\n"
	      "  NAME-fig6   paper Figs. 6 and 7: force against position, the first press and\n"
	      "              the ticks around the Fig. 5 event\n"
	      "  NAME-fig8   paper Fig. 8: zoom where the PC acts and the next tick does not move\n"
	      "  NAME-fig11  paper Fig. 11: true against measured position over the last ticks\n"
	      "  NAME-zoom   with --zoom T: the zoom panels at time T\n"
	      "and for all logs variants.png/.pdf (overlay), compare.csv and compare.md, index.md\n"
	      "and index.html (which figure reproduces which). Force axes are shared by every\n"
	      "figure of a report. Rerun a script in DIR with 'gnuplot NAME.gp'.\n"
	      "\n"
	      "  -o, --output-dir DIR     the report directory (created if missing)\n"
	      "  --figure N               only the panels of paper figure N, one of 3, 4, 5, 6, 8,\n"
	      "                           10, 11, 14, 16 (3, 10, 14, 16: the contact response;\n"
	      "                           repeatable); no overlay or tables. Default: every figure\n"
	      "                           that applies, the overlay and the tables\n"
	      "  --zoom T                 also the zoom panels at time T s (NAME-zoom)\n"
	      "  --points N               at most N buckets per plotted log (default 2000);\n"
	      "                           each bucket keeps its min and max, so chatter stays\n"
	      "                           visible in long logs\n"
	      "  --title TEXT             title of the index page\n"
	      "  --gnuplot PATH           the gnuplot program (default: gnuplot)\n"
	      "  --no-draw                write data, scripts, tables and index only\n",
	      f);
	fputs("  -q, --quiet              print nothing but errors (no notes, no index path)\n"
	      "  -v, --verbose            also show gnuplot's messages when it succeeds (they\n"
	      "                           are shown when it fails)\n"
	      "  --threshold NAME=VALUE   a chatter threshold (see 'chatter --help')\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 1 gnuplot failed, a figure is missing or a --figure asked\n"
	      "for found no event in any log, 2 bad usage or input.\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
}

enum { OPT_POINTS = 256, OPT_TITLE, OPT_GNUPLOT, OPT_NO_DRAW, OPT_THRESHOLD, OPT_FIGURE, OPT_ZOOM };

static const popc_option report_options[] = {
	{"output-dir", 'o', 'o', "DIR"},
	{"points", 0, OPT_POINTS, "N"},
	{"title", 0, OPT_TITLE, "TEXT"},
	{"gnuplot", 0, OPT_GNUPLOT, "FILE"},
	{"no-draw", 0, OPT_NO_DRAW, NULL},
	{"threshold", 0, OPT_THRESHOLD, "NAME=VALUE"},
	{"figure", 0, OPT_FIGURE, "N"},
	{"zoom", 0, OPT_ZOOM, "T"},
	{"quiet", 'q', 'q', NULL},
	{"verbose", 'v', 'v', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_report_opts[] = {report_options, ana_input_option_table, NULL};

/* One log's pass: decimated whole-log data, windows of raw rows, ranges. */
typedef struct report_pass {
	ana_decimator dec;
	ana_decimator adm; /* an admittance log's own columns (report_admittance.c) */
	report_capture cap;
	report_log *lg;
	int k;
} report_pass;

static void on_row(void *ctx, const ana_row *r)
{
	report_pass *p = ctx;
	report_log *lg = p->lg;
	const popc_tick *t = &r->tick;
	report_sample s;
	s.t_s = t->t_s;
	double *v = s.v;
	v[D_X] = t->x_m;
	v[D_X_TRUE] = r->x_true_m;
	v[D_V] = t->v_mps;
	v[D_F_E] = t->f_e_N;
	/* without a PC-force source f_pc, f_c and W are no measurement: NaN, which
	 * the data file carries as a gap and the script does not plot */
	v[D_F_PC] = r->pc_force_known ? t->f_pc_N : (double)NAN;
	v[D_F_C] = r->pc_force_known ? t->f_c_N : (double)NAN;
	v[D_W] = r->w_known ? t->W_J : (double)NAN;
	v[D_E_REF] = t->E_ref_J;
	v[D_WME] = r->w_known ? t->W_J - t->E_ref_J : (double)NAN;
	v[D_E_PORT] = r->extra[0];
	ana_decim_add(&p->dec, t->t_s, v);
	report_admittance_sample(&p->adm, r);
	for (int c = 0; c < D_COLS; c++) { /* fmin and fmax pass over a NaN */
		lg->col_min[c] = fmin(lg->col_min[c], v[c]);
		lg->col_max[c] = fmax(lg->col_max[c], v[c]);
	}
	/* contact: the wall pushes back (f_e != 0 only inside it) */
	const int in_contact = t->f_e_N != 0.0;
	report_capture_add(&p->cap, &s, in_contact);
	if (p->k == 0)
		lg->t_first_s = t->t_s;
	lg->t_last_s = t->t_s;
	if (in_contact && isnan(lg->t_contact_s)) {
		lg->t_contact_s = t->t_s;
		lg->x_contact_min_m = lg->x_contact_max_m = t->x_m;
	}
	if (!isnan(lg->t_contact_s)) {
		lg->x_contact_min_m = fmin(lg->x_contact_min_m, t->x_m);
		lg->x_contact_max_m = fmax(lg->x_contact_max_m, t->x_m);
		if (!isnan(r->x_true_m)) {
			lg->x_contact_min_m = fmin(lg->x_contact_min_m, r->x_true_m);
			lg->x_contact_max_m = fmax(lg->x_contact_max_m, r->x_true_m);
		}
	}
	if (r->pc_force_known) {
		lg->f_c_min_N = fmin(lg->f_c_min_N, fmin(t->f_c_N, t->f_e_N));
		lg->f_c_max_N = fmax(lg->f_c_max_N, fmax(t->f_c_N, t->f_e_N));
	}
	lg->has_x_true |= !isnan(r->x_true_m);
	lg->has_e_port |= !isnan(r->extra[0]);
	p->k++;
}

static const char *const fig_suffixes_reserved[] = {"-fig4", "-fig5", "-fig6",
						    "-fig8", "-fig11", "-zoom"};

static void safe_name(const char *in, char *out, size_t cap)
{
	size_t i = 0;
	for (; in[i] && i + 1 < cap; i++) {
		char c = in[i];
		int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
			 c == '-' || c == '_' || c == '.';
		out[i] = ok ? c : '_';
	}
	out[i] = '\0';
	/* a name a report file has, or that ends like another log's figure
	 * (a log "a-fig4" beside a log "a"), gets "-log" */
	int reserved = i == 0 || strcmp(out, "variants") == 0 || strcmp(out, "compare") == 0 ||
		       strcmp(out, "index") == 0;
	for (size_t k = 0; k < sizeof fig_suffixes_reserved / sizeof *fig_suffixes_reserved; k++) {
		size_t n = strlen(fig_suffixes_reserved[k]);
		reserved |= i >= n && strcmp(out + i - n, fig_suffixes_reserved[k]) == 0;
	}
	if (reserved)
		snprintf(out + i, cap - i, "%s", "-log");
}

/* The variant comes from the log's header, text anyone can write, and goes
 * into gnuplot scripts inside double quotes, where a '"' ends the string and a
 * backquote runs a shell command even inside it (and into Markdown): keep the
 * characters a variant name uses, replace the others with '_'. */
static void script_safe(char *s)
{
	for (; *s; s++) {
		char c = *s;
		int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
			 strchr(" -_.,:;=+()/", c) != NULL;
		if (!ok)
			*s = '_';
	}
}

static int write_tables(const report_out *ro, const report_log *logs, int n)
{
	char path[1400], csv_path[1400];
	FILE *csv = report_open(ro, "compare.csv", csv_path, sizeof csv_path);
	if (!csv)
		return -1;
	FILE *md = report_open(ro, "compare.md", path, sizeof path);
	if (!md) {
		fclose(csv);
		return -1;
	}
	ana_summary_print_header(csv, ANA_CSV);
	ana_summary_print_header(md, ANA_MARKDOWN);
	for (int i = 0; i < n; i++) {
		ana_summary_print_row(csv, ANA_CSV, &logs[i].sum);
		ana_summary_print_row(md, ANA_MARKDOWN, &logs[i].sum);
	}
	int bad = report_close(csv, csv_path, 0) != 0;
	bad |= report_close(md, path, 0) != 0;
	return bad ? -1 : 0;
}

typedef struct report_name {
	char name[256];
} report_name;

static int usable(const report_out *ro, const char *file)
{
	char path[1400];
	snprintf(path, sizeof path, "%s/%s", ro->dir, file);
	return ana_output_file_usable("report", "-o", path);
}

/* Each input's name in the report (a unique, file-name-safe form of its file
 * name, from the paths alone), and a check of every path the report will
 * write: each must be usable as a file (ana_output_file_usable). Returns 0
 * or 2 after saying which. */
static int name_outputs(const report_out *ro, report_name *names, unsigned figs, int tables)
{
	static const char *const fixed[] = {"compare.csv",  "compare.md",   "variants.gp",
					    "variants.png", "variants.pdf", "variants.eps"};
	static const char *const per_fig[] = {"dat", "gp", "png", "pdf", "eps"};
	char file[400];
	if (usable(ro, "index.md") || usable(ro, "index.html"))
		return POPC_EXIT_USAGE;
	for (size_t k = 0; tables && k < sizeof fixed / sizeof fixed[0]; k++)
		if (usable(ro, fixed[k]))
			return POPC_EXIT_USAGE;
	for (int i = 0; i < ro->n_inputs; i++) {
		char log_name[256], base[256];
		ana_log_name(ro->inputs[i], log_name, sizeof log_name);
		safe_name(log_name, base, sizeof base);
		snprintf(names[i].name, sizeof names[i].name, "%s", base);
		for (int k = 2, clash = 1; clash; k++) {
			clash = 0;
			for (int j = 0; j < i; j++)
				clash |= strcmp(names[j].name, names[i].name) == 0;
			if (clash)
				snprintf(names[i].name, sizeof names[i].name, "%.230s-%d", base, k);
		}
		for (int fg = 0; fg < RF_COUNT; fg++) {
			if (!(figs & (1u << fg)))
				continue;
			for (size_t k = 0; k < sizeof per_fig / sizeof per_fig[0]; k++) {
				snprintf(file, sizeof file, "%s%s.%s", names[i].name, report_fig_suffix[fg],
					 per_fig[k]);
				if (usable(ro, file))
					return POPC_EXIT_USAGE;
			}
		}
	}
	return 0;
}

static int make_dir(const char *dir)
{
	if (mkdir(dir, 0777) == 0 || errno == EEXIST) {
		struct stat st;
		if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode))
			return 0;
	}
	fprintf(stderr, "popc-analyze report: %s: cannot create the directory: %s\n", dir,
		strerror(errno));
	return -1;
}

static int file_ok(const char *dir, const char *name, const char *ext)
{
	char path[1400];
	snprintf(path, sizeof path, "%s/%s.%s", dir, name, ext);
	struct stat st;
	return stat(path, &st) == 0 && st.st_size > 0;
}

static int draw(const char *gnuplot, const report_out *ro, const char *name, int verbose)
{
	const char *dir = ro->dir;
	char script[300], why[600];
	snprintf(script, sizeof script, "%s.gp", name);
	/* the figures gnuplot writes: none may be an input; a figure left from an
	 * earlier report is removed, so that a figure found afterwards is this
	 * run's and not a stale one passing the check below */
	static const char *const figure_ext[] = {"png", "pdf", "eps"};
	for (size_t k = 0; k < sizeof figure_ext / sizeof figure_ext[0]; k++) {
		char fig[1400];
		snprintf(fig, sizeof fig, "%s/%s.%s", dir, name, figure_ext[k]);
		if (report_check_not_input(ro, fig) != 0)
			return -2;
		if (remove(fig) != 0 && errno != ENOENT) { /* an output path, not gnuplot: 2 */
			fprintf(stderr, "popc-analyze report: %s: cannot replace: %s\n", fig,
				strerror(errno));
			return -2;
		}
	}
	if (ana_run_gnuplot(gnuplot, dir, script, verbose, why, sizeof why) != 0) {
		fprintf(stderr, "popc-analyze report: %s/%s: %s\n", dir, script, why);
		return -1;
	}
	if (!file_ok(dir, name, "png") || !(file_ok(dir, name, "pdf") || file_ok(dir, name, "eps"))) {
		fprintf(stderr, "popc-analyze report: %s/%s.gp ran but %s.png or its PDF is missing\n",
			dir, name, name);
		return -1;
	}
	return 0;
}

/* --figure N: the report figure of paper figure N (0: not one of them). */
static int figure_option(const char *arg, unsigned *figs, int *fig_asked)
{
	long long n;
	if (popc_parse_ll_text(arg, 0, 100, &n) != 0)
		n = -1;
	switch (n) {
	case 3:
	case 10:
	case 14:
	case 16:
		*figs |= 1u << RF_CONTACT;
		*fig_asked = (int)n;
		return 0;
	case 4: *figs |= 1u << RF_FIG4; return 0;
	case 5: *figs |= 1u << RF_FIG5; return 0;
	case 6:
	case 7: *figs |= 1u << RF_FIG6; return 0;
	case 8: *figs |= 1u << RF_FIG8; return 0;
	case 11: *figs |= 1u << RF_FIG11; return 0;
	default:
		fprintf(stderr,
			"popc-analyze report: --figure '%s': the paper figures a report draws are 3, "
			"4, 5, 6 (or 7), 8, 10, 11, 14, 16 (one figure draws 6 and 7; 3, 10, 14, 16 "
			"are the contact response)\n",
			arg);
		return POPC_EXIT_USAGE;
	}
}

/* Writes a window's rows (NAME-figN.dat; NAME-fig6.dat: the press, two blank
 * lines, the Fig. 7 ticks as gnuplot's index 1). */
static int write_window_data(const report_out *ro, const report_log *lg, report_fig fig,
			     const report_capture *cap)
{
	char path[1400], file[300];
	snprintf(file, sizeof file, "%s%s.dat", lg->name, report_fig_suffix[fig]);
	FILE *f = report_open(ro, file, path, sizeof path);
	if (!f)
		return -1;
	int bad = 0;
	fprintf(f, "# %s: raw rows, " REPORT_DAT_COLUMNS "\n", lg->path);
	if (fig == RF_FIG6) {
		fputs("# index 0: the first press into the wall and its release (Fig. 6)\n", f);
		bad |= report_window_write(&cap->w[RW_PRESS], f) != 0;
		const report_window *w7 =
			lg->has_window[RW_FIG5] ? &cap->w[RW_FIG5] : &cap->w[RW_ZOOM];
		fputs("\n\n# index 1: the ticks around the Fig. 5 event (Fig. 7)\n", f);
		if (w7->n > 0)
			bad |= report_window_write(w7, f) != 0;
	} else {
		report_win w = fig == RF_FIG5	? RW_FIG5
			       : fig == RF_FIG8 ? RW_FIG8
			       : fig == RF_FIG11 ? RW_END
						: RW_ZOOM;
		bad |= report_window_write(&cap->w[w], f) != 0;
	}
	return report_close(f, path, bad);
}

/* Fig. 7's ticks k-3 .. k+3 around the Fig. 5 event (or --zoom), which its
 * script labels: the window's rows from the event's. */
static void fig7_ticks(report_log *lg, const report_capture *cap)
{
	const report_window *w = lg->has_window[RW_FIG5] ? &cap->w[RW_FIG5] : &cap->w[RW_ZOOM];
	lg->fig7_n = 0;
	lg->fig7_event_row = w->event_index;
	if (w->event_index < 0)
		return;
	for (int k = w->event_index - 3; k <= w->event_index + 3; k++) {
		if (k < 0 || k >= w->n)
			continue;
		lg->fig7_x_m[lg->fig7_n] = w->rows[k].v[D_X];
		lg->fig7_f_c_N[lg->fig7_n] = w->rows[k].v[D_F_C];
		lg->fig7_tick[lg->fig7_n++] = k - w->event_index;
	}
}

/* The events of Figs. 4, 5 and 8 (and the settled stretch the contact
 * response's position axis shows), when the report draws them. */
static int find_events(report_log *lg, const ana_input_options *in, unsigned figs, int *rc)
{
	if (!(figs & ~(1u << RF_ZOOM) & ~(1u << RF_FIG11)))
		return 0;
	if (strcmp(lg->path, "-") == 0) {
		fprintf(stderr, "popc-analyze report: note: standard input is read once: no events "
				"(Figs. 4, 5, 8) found in it\n");
		return 0;
	}
	popc_error err;
	int st = report_find_events(lg, in, &err);
	if (st < 0) {
		*rc = ana_fail("report", st, &err);
		return -1;
	}
	return 0;
}

int ana_cmd_report(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_report_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "report";
	/* the true port energy, when the log has it (a column beside popc's table) */
	in.n_extra = 1;
	in.extra_name[0] = "E_port";
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	const char *dir = NULL, *title = "popc report", *gnuplot = "gnuplot";
	long long points = 2000;
	int no_draw = 0, c, rc = 0, n = 0, fig_asked = 0, quiet = 0, verbose = 0;
	unsigned figs = 0;
	double zoom_s = (double)NAN;
	report_log *logs = NULL;
	report_name *names = NULL;
	report_own *own = NULL; /* admittance and teleoperation logs' own figures */
	int n_own = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case 'o': dir = optarg; break;
		case 'q': quiet = in.quiet = 1; break;
		case 'v': verbose = 1; break;
		case OPT_POINTS: {
			if (popc_parse_ll_text(optarg, 10, 1000000, &points) != 0) {
				fprintf(stderr, "popc-analyze report: --points '%s': 10 to 1000000\n", optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		}
		case OPT_FIGURE:
			if ((rc = figure_option(optarg, &figs, &fig_asked)) != 0)
				goto out;
			break;
		case OPT_ZOOM:
			if (popc_parse_double_text(optarg, &zoom_s) != 0 || !isfinite(zoom_s)) {
				fprintf(stderr, "popc-analyze report: --zoom '%s': a time in seconds\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case OPT_TITLE: title = optarg; break;
		case OPT_GNUPLOT: gnuplot = optarg; break;
		case OPT_NO_DRAW: no_draw = 1; break;
		case OPT_THRESHOLD:
			if ((rc = ana_threshold_option(&cc, optarg, "report")) != 0)
				goto out;
			break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "report")) != 0)
				goto out;
			break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (!dir || optind >= argc || argc - optind > MAX_LOGS) {
		fprintf(stderr, "popc-analyze report: %s\n",
			!dir ? "missing -o DIR" : optind >= argc ? "missing LOG" : "at most 256 logs");
		popc_help_hint(argv[0], "options");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	/* the default report: every figure, the overlay and the tables */
	const int tables = figs == 0;
	const unsigned figs_asked = figs;
	if (tables)
		figs = FIGS_DEFAULT;
	if (!isnan(zoom_s))
		figs |= 1u << RF_ZOOM;
	if ((rc = ana_output_dir_usable("report", "-o", dir, 1)) != 0)
		goto out;
	if (make_dir(dir) != 0) {
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	const report_out ro = {dir, argv + optind, argc - optind};
	logs = calloc((size_t)(argc - optind), sizeof *logs);
	names = calloc((size_t)(argc - optind), sizeof *names);
	own = calloc((size_t)(argc - optind), sizeof *own);
	if (!logs || !names || !own) {
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	/* every file the report writes, before any log is read: a path there
	 * that is a directory is bad usage, not a figure that failed (a non-empty
	 * directory named NAME.png could not be replaced: exit 1 after all the
	 * work) */
	if ((rc = name_outputs(&ro, names, figs, tables)) != 0)
		goto out;
	const int whole_log = (figs & ((1u << RF_CONTACT) | (1u << RF_FIG4))) || tables;
	for (int i = optind; i < argc; i++) {
		report_log *lg = &logs[n];
		memset(lg, 0, sizeof *lg);
		snprintf(lg->path, sizeof lg->path, "%s", argv[i]);
		for (int w = 0; w < RW_COUNT; w++)
			lg->t_event_s[w] = (double)NAN;
		lg->t_event_s[RW_ZOOM] = zoom_s;
		lg->t_contact_s = (double)NAN;
		lg->t_settle_s = (double)NAN;
		lg->t_settle_final_s = (double)NAN;
		lg->x_settled_min_m = lg->x_settled_max_m = (double)NAN;
		lg->f_c_min_N = (double)INFINITY;
		lg->f_c_max_N = -(double)INFINITY;
		for (int k = 0; k < D_COLS; k++)
			lg->col_min[k] = lg->col_max[k] = (double)NAN;
		if (find_events(lg, &in, figs, &rc) != 0)
			continue;
		report_pass pass;
		memset(&pass, 0, sizeof pass);
		pass.lg = lg;
		if (ana_decim_init(&pass.dec, D_COLS, (int)points * 2) != 0 ||
		    ana_decim_init(&pass.adm, RA_COLS, (int)points * 2) != 0 ||
		    report_capture_init(&pass.cap, lg->t_event_s) != 0) {
			ana_decim_free(&pass.dec);
			ana_decim_free(&pass.adm);
			fprintf(stderr, "popc-analyze report: out of memory\n");
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		popc_error err;
		int st = ana_summarize(argv[i], &in, &cc, -1.0, &lg->sum, on_row, &pass, &err);
		if (!st && lg->sum.teleop) {
			/* two ports: its own figure (report_teleop.c), listed in the
			 * index with the admittance logs' */
			ana_decim_free(&pass.dec);
			ana_decim_free(&pass.adm);
			report_capture_free(&pass.cap);
			snprintf(lg->name, sizeof lg->name, "%s", names[i - optind].name);
			if (report_teleop_write(&ro, lg, &in, (int)points, &err) != 0) {
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			report_own *o = &own[n_own++];
			snprintf(o->name, sizeof o->name, "%s", lg->name);
			snprintf(o->kind, sizeof o->kind, "teleoperation");
			snprintf(o->file, sizeof o->file, "%s" REPORT_TELE_SUFFIX, lg->name);
			snprintf(o->caption, sizeof o->caption,
				 "%s: master and slave positions, f_c against -fs, energies per port "
				 "(in, out, received), drift x - xs (PCs %s)",
				 o->file, lg->sum.tele.tdpa ? "on" : "off");
			int d = no_draw ? 0 : draw(gnuplot, &ro, o->file, verbose);
			o->drawn = !no_draw && d == 0;
			if (d == -2)
				rc = POPC_EXIT_USAGE;
			else if (d != 0 && rc == 0)
				rc = POPC_EXIT_RUN_FAILED;
			if (!quiet)
				printf("%s/%s.%s\n", dir, o->file, no_draw ? "gp" : "png");
			continue;
		}
		if (!st && lg->sum.admittance) {
			/* the series PC's figures (f_pc in N, the encoder's x) are
			 * not its: its own figure, f_meas, v_ve/v, v_pc and W, drawn
			 * here; the index and tables list the impedance logs */
			snprintf(lg->name, sizeof lg->name, "%s", names[i - optind].name);
			int bad = report_admittance_write(&ro, lg, &pass.adm) != 0;
			ana_decim_free(&pass.dec);
			ana_decim_free(&pass.adm);
			report_capture_free(&pass.cap);
			if (bad) {
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			char file[300];
			snprintf(file, sizeof file, "%s" REPORT_ADM_SUFFIX, lg->name);
			int d = no_draw ? 0 : draw(gnuplot, &ro, file, verbose);
			if (d == -2)
				rc = POPC_EXIT_USAGE;
			else if (d != 0 && rc == 0)
				rc = POPC_EXIT_RUN_FAILED;
			if (!quiet)
				printf("%s/%s.%s\n", dir, file, no_draw ? "gp" : "png");
			report_own *o = &own[n_own++];
			snprintf(o->name, sizeof o->name, "%s", lg->name);
			snprintf(o->kind, sizeof o->kind, "admittance");
			snprintf(o->file, sizeof o->file, "%s", file);
			snprintf(o->caption, sizeof o->caption,
				 "%s: force reading, VE velocity and command, parallel PC's v_pc, W",
				 file);
			o->drawn = !no_draw && d == 0;
			continue;
		}
		if (st) {
			ana_decim_free(&pass.dec);
			ana_decim_free(&pass.adm);
			report_capture_free(&pass.cap);
			rc = ana_fail("report", st, &err);
			continue;
		}
		if (quiet) {
			/* -q: no notes */
		} else if (!lg->sum.has_pc_force) {
			ana_no_pc_force(&err, argv[i]);
			fprintf(stderr, "popc-analyze report: note: %s; no PC force panel, its PC and "
					"chatter columns%s are n/a\n",
				err.msg, lg->sum.has_w ? "" : " and W - E_ref");
		} else if (!ana_chatter_checked(&lg->sum)) {
			ana_chatter_too_short(&err, argv[i], &lg->sum);
			fprintf(stderr, "popc-analyze report: note: %s; its chatter columns are n/a\n",
				err.msg);
		}
		if (!quiet && !ana_lc_checked(&lg->sum)) {
			ana_lc_too_short(&err, argv[i], &lg->sum);
			fprintf(stderr,
				"popc-analyze report: note: %s; its limit-cycle columns are n/a\n",
				err.msg);
		}
		script_safe(lg->sum.variant);
		snprintf(lg->name, sizeof lg->name, "%s", names[i - optind].name);
		report_capture_finish(&pass.cap);
		for (int w = 0; w < RW_COUNT; w++)
			lg->has_window[w] = pass.cap.w[w].event_index >= 0;
		lg->t_event_s[RW_END] = pass.cap.w[RW_END].t_event_s;
		if (lg->has_window[RW_PRESS])
			lg->t_event_s[RW_PRESS] = pass.cap.w[RW_PRESS].t_event_s;
		fig7_ticks(lg, &pass.cap);
		if (!quiet && !isnan(zoom_s) && !lg->has_window[RW_ZOOM])
			fprintf(stderr, "popc-analyze report: note: %s ends before --zoom %g s: no zoom\n",
				argv[i], zoom_s);
		char path[1400], file[300];
		int bad = 0;
		if (whole_log) {
			snprintf(file, sizeof file, "%s.dat", lg->name);
			FILE *f = report_open(&ro, file, path, sizeof path);
			bad = !f; /* report_open said why: an input, or errno */
			if (f) {
				fprintf(f, "# %s decimated: each column's min and max over "
					   "buckets of %lld ticks, at a bucket's first and last t\n"
					   "# " REPORT_ENV_COLUMNS "\n",
					argv[i], pass.dec.width);
				bad = report_close(f, path, ana_decim_write(&pass.dec, f) != 0) != 0;
			}
		}
		for (int fg = RF_FIG5; fg < RF_COUNT && !bad; fg++)
			if (report_log_has(lg, (report_fig)fg, figs))
				bad = write_window_data(&ro, lg, (report_fig)fg, &pass.cap) != 0;
		ana_decim_free(&pass.dec);
		ana_decim_free(&pass.adm);
		report_capture_free(&pass.cap);
		/* each failure has printed its one message (which file, why) */
		if (bad) {
			rc = POPC_EXIT_USAGE;
			goto out;
		}
		n++;
	}
	if (n == 0 && n_own > 0) {
		/* only logs with figures of their own: the index lists them */
		const report_index ix = {title, 0, 0, 0, own, n_own};
		if (report_write_index(&ro, &ix, logs, 0) != 0)
			rc = POPC_EXIT_USAGE;
		else if (!quiet)
			printf("%s/index.html\n", dir);
		goto out;
	}
	if (n == 0)
		goto out;
	/* one scale per force for the whole report: 10 % headroom over the
	 * largest |f_pc| (the bound, when a log reaches it) and f_c of any log */
	report_scales sc = {0.0, (double)INFINITY, -(double)INFINITY};
	for (int i = 0; i < n; i++) {
		if (!logs[i].sum.has_pc_force)
			continue;
		sc.f_pc_N = fmax(sc.f_pc_N, logs[i].sum.pc_max_N);
		sc.f_c_min_N = fmin(sc.f_c_min_N, logs[i].f_c_min_N);
		sc.f_c_max_N = fmax(sc.f_c_max_N, logs[i].f_c_max_N);
	}
	sc.f_pc_N = sc.f_pc_N > 0.0 ? 1.1 * sc.f_pc_N : 1.0; /* never acted: a flat line at 0 */
	if (!(sc.f_c_min_N < sc.f_c_max_N)) {
		sc.f_c_min_N = -1.0;
		sc.f_c_max_N = 1.0;
	} else {
		double pad = 0.05 * (sc.f_c_max_N - sc.f_c_min_N);
		sc.f_c_min_N -= pad;
		sc.f_c_max_N += pad;
	}
	/* the scripts, then the figures */
	for (int i = 0; i < n; i++) {
		for (int fg = 0; fg < RF_COUNT; fg++) {
			if (!report_log_has(&logs[i], (report_fig)fg, figs))
				continue;
			char path[1400], file[300];
			snprintf(file, sizeof file, "%s%s.gp", logs[i].name, report_fig_suffix[fg]);
			FILE *f = report_open(&ro, file, path, sizeof path);
			if (!f || report_close(f, path,
					       report_write_figure(f, (report_fig)fg, &logs[i], &sc,
								   fig_asked) != 0) != 0) {
				rc = POPC_EXIT_USAGE;
				goto out;
			}
		}
	}
	if (tables) {
		char path[1400];
		FILE *f = report_open(&ro, "variants.gp", path, sizeof path);
		if (!f || report_close(f, path, report_write_overlay(f, logs, n, &sc) != 0) != 0 ||
		    write_tables(&ro, logs, n) != 0) {
			rc = POPC_EXIT_USAGE;
			goto out;
		}
	}
	/* a figure asked for by number that no log has (its event not found) */
	for (int fg = RF_FIG5; fg < RF_COUNT; fg++) {
		if (!(figs_asked & (1u << fg)))
			continue;
		int any = 0;
		for (int i = 0; i < n; i++)
			any |= report_log_has(&logs[i], (report_fig)fg, figs);
		if (!any) {
			fprintf(stderr,
				"popc-analyze report: --figure %d: %s in any log, so nothing drawn for it\n",
				fg == RF_FIG5 ? 5 : fg == RF_FIG8 ? 8 : fg == RF_FIG11 ? 11 : 6,
				fg == RF_FIG6 ? "no contact" : "no such event");
			if (rc == 0)
				rc = POPC_EXIT_RUN_FAILED;
		}
	}
	int drawn = 0;
	if (!no_draw) {
		int failed = 0, refused = 0;
		for (int i = 0; i < n; i++) {
			for (int fg = 0; fg < RF_COUNT; fg++) {
				if (!report_log_has(&logs[i], (report_fig)fg, figs))
					continue;
				char file[300];
				snprintf(file, sizeof file, "%s%s", logs[i].name, report_fig_suffix[fg]);
				int d = draw(gnuplot, &ro, file, verbose);
				failed |= d != 0;
				refused |= d == -2;
			}
		}
		if (tables) {
			int d = draw(gnuplot, &ro, "variants", verbose);
			failed |= d != 0;
			refused |= d == -2;
		}
		if (refused)
			rc = POPC_EXIT_USAGE;
		else if (failed && rc == 0)
			rc = POPC_EXIT_RUN_FAILED;
		drawn = !failed;
	}
	const report_index ix = {title, tables, drawn, figs, own, n_own};
	if (report_write_index(&ro, &ix, logs, n) != 0) {
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	if (!quiet)
		printf("%s/index.html\n", dir);
out:
	free(own);
	free(logs);
	free(names);
	ana_input_free(&in);
	return rc;
}
