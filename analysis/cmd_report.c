/* popc-analyze report: gnuplot figures (PNG and PDF) of each log in the
 * seed's form (Fig. 3: position, velocity, W against E_ref, PC force), a
 * figure overlaying the logs (variants), the comparison table and an index
 * page. The data files are min/max decimated (bounded memory); the gnuplot
 * scripts stay beside the figures so users can restyle and rerun them. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "analyze.h"
#include "popc/util/parse.h"

/* data file columns after t */
enum { D_X, D_X_TRUE, D_V, D_F_E, D_F_PC, D_F_C, D_W, D_E_REF, D_WME, D_COLS };

#define MAX_LOGS 256

static void usage(FILE *f)
{
	fputs("usage: popc-analyze report [options] -o DIR LOG...\n"
	      "\n"
	      "Writes into DIR, for each LOG: NAME.dat (min/max decimated data), NAME.gp (the\n"
	      "gnuplot script), NAME.png and NAME.pdf (position measured and true, velocity,\n"
	      "W against E_ref, PC force with chatter intervals shaded: the seed's Fig. 3 form);\n"
	      "for all logs: variants.gp/.png/.pdf overlaying position, W - E_ref and PC force,\n"
	      "compare.csv and compare.md (the 'compare' table), index.md and index.html.\n"
	      "Rerun a script in DIR with 'gnuplot NAME.gp'.\n"
	      "\n"
	      "  -o, --output-dir DIR     the report directory (created if missing)\n"
	      "  --points N               at most N buckets per plotted log (default 2000);\n"
	      "                           each bucket keeps its min and max, so chatter stays\n"
	      "                           visible in long logs\n"
	      "  --title TEXT             title of the index page\n"
	      "  --gnuplot PATH           the gnuplot program (default: gnuplot)\n"
	      "  --no-draw                write data, scripts, tables and index only\n"
	      "  --threshold NAME=VALUE   a chatter threshold (see 'chatter --help')\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 1 gnuplot failed or a figure is missing, 2 bad usage or\n"
	      "input.\n",
	      f);
}

enum { OPT_POINTS = 256, OPT_TITLE, OPT_GNUPLOT, OPT_NO_DRAW, OPT_THRESHOLD };

typedef struct report_log {
	char name[256];             /* file-name safe, unique in the report */
	int has_x_true;
	ana_summary sum;
} report_log;

static void on_row(void *ctx, const ana_row *r)
{
	ana_decimator *d = ctx;
	const popc_tick *t = &r->tick;
	double v[D_COLS];
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
	ana_decim_add(d, t->t_s, v);
}

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
	if (i == 0 || strcmp(out, "variants") == 0 || strcmp(out, "compare") == 0 ||
	    strcmp(out, "index") == 0)
		snprintf(out + i, cap - i, "%s", "-log");
}

/* Where the report goes, and the logs it reads: no output may replace one. */
typedef struct report_out {
	const char *dir;
	char *const *inputs;
	int n_inputs;
} report_out;

/* 0 when DIR/file is not one of the input logs; else says so. */
static int check_not_input(const report_out *ro, const char *path)
{
	int i = ana_output_is_input(path, ro->inputs, ro->n_inputs);
	if (i < 0)
		return 0;
	fprintf(stderr,
		"popc-analyze report: %s is the input log %s: refusing to overwrite it (choose "
		"another -o DIR)\n",
		path, ro->inputs[i]);
	return -1;
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

static FILE *open_in(const report_out *ro, const char *file, char *path, size_t cap)
{
	snprintf(path, cap, "%s/%s", ro->dir, file);
	if (check_not_input(ro, path) != 0)
		return NULL;
	FILE *f = fopen(path, "w");
	if (!f)
		fprintf(stderr, "popc-analyze report: %s: cannot open for writing: %s\n", path,
			strerror(errno));
	return f;
}

/* Closes a file open_in opened: 0, or -1 after saying which file failed and
 * why (failed: an earlier write to it already failed). Every failure prints
 * one message, where it happens, so the caller adds none. */
static int close_out(FILE *f, const char *path, int failed)
{
	failed |= ferror(f) != 0;
	/* errno tells only for fclose: an earlier failed write's errno may be
	 * overwritten by now */
	int close_failed = fclose(f) != 0;
	int saved = errno;
	if (!failed && !close_failed)
		return 0;
	fprintf(stderr, "popc-analyze report: %s: write failed%s%s\n", path,
		close_failed ? ": " : "", close_failed ? strerror(saved) : "");
	return -1;
}

/* The terminal lines shared by every script: pngcairo/pdfcairo when this
 * gnuplot has them (Debian's gnuplot-nox does), else png and EPS. */
static void write_terminal_block(FILE *f, const char *name, const char *png_size,
				 const char *pdf_size)
{
	fprintf(f,
		"  if (out eq \"png\") {\n"
		"    if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
		"      set terminal pngcairo size %s noenhanced font \"sans,9\"\n"
		"    } else {\n"
		"      set terminal png size %s noenhanced\n"
		"    }\n"
		"    set output \"%s.png\"\n"
		"  } else {\n"
		"    if (strstrt(GPVAL_TERMINALS, \"pdfcairo\") > 0) {\n"
		"      set terminal pdfcairo size %s noenhanced font \"sans,8\"\n"
		"      set output \"%s.pdf\"\n"
		"    } else {\n"
		"      set terminal postscript eps color noenhanced\n"
		"      set output \"%s.eps\"\n"
		"    }\n"
		"  }\n",
		png_size, png_size, name, pdf_size, name, name);
}

static int write_log_script(const report_out *ro, const report_log *lg)
{
	char path[1400], file[300];
	snprintf(file, sizeof file, "%s.gp", lg->name);
	FILE *f = open_in(ro, file, path, sizeof path);
	if (!f)
		return -1;
	const popc_chatter_result *c = &lg->sum.chatter;
	fprintf(f,
		"# popc-analyze report: %s (variant %s). Rerun here: gnuplot %s.gp\n"
		"# %s.dat columns: t x x_true v f_e f_pc f_c W E_ref W-E_ref; two rows per\n"
		"# bucket hold its min and max (min/max decimation), so chatter stays visible.\n"
		"data = \"%s.dat\"\n"
		"do for [out in \"png pdf\"] {\n",
		lg->name, lg->sum.variant, lg->name, lg->name, lg->name);
	write_terminal_block(f, lg->name, "1000,1100", "7in,8in");
	fprintf(f,
		"  set multiplot layout %d,1 title \"%s: variant %s\"\n"
		"  set grid\n"
		"  set key top right\n"
		"  set lmargin 12\n"
		"  set xlabel \"\"\n"
		"  set ylabel \"position (m)\"\n"
		"  plot data using 1:2 with lines lw 1 title \"measured x\"%s\n"
		"  set ylabel \"velocity (m/s)\"\n"
		"  plot data using 1:4 with lines lw 1 title \"v (controller)\"\n"
		"  set ylabel \"energy (J)\"\n"
		"  plot %sdata using 1:9 with lines lw 1 dt 2 title \"E_ref%s\"\n",
		lg->sum.has_pc_force ? 4 : 3, lg->name, lg->sum.variant,
		lg->has_x_true ? ", data using 1:3 with lines lw 1 dt 2 title \"true x_true\"" : "",
		lg->sum.has_w ? "data using 1:8 with lines lw 1 title \"W (PO)\", " : "",
		lg->sum.has_w ? "" : " (W n/a: no PC force in the log)");
	if (!lg->sum.has_pc_force) {
		/* no PC force in the log: no panel for it, rather than a flat 0 */
		fputs("  unset multiplot\n"
		      "  set output\n"
		      "}\n",
		      f);
		return close_out(f, path, 0);
	}
	fputs("  set ylabel \"PC force (N)\"\n"
	      "  set xlabel \"t (s)\"\n",
	      f);
	for (int i = 0; i < c->n_stored; i++)
		fprintf(f,
			"  set object %d rect from first %.9g, graph 0 to first %.9g, graph 1 "
			"fillcolor rgb \"#ffd8d8\" fillstyle solid 1.0 noborder behind\n",
			i + 1, c->intervals[i].start_s, c->intervals[i].end_s);
	if (lg->sum.pc_max_N == 0.0) /* the PC never acted: a flat line, not gnuplot's warning */
		fputs("  set yrange [-1:1]\n", f);
	fprintf(f, "  plot data using 1:6 with lines lw 1 title \"f_pc%s\"\n"
		   "  set autoscale y\n"
		   "  unset object\n"
		   "  unset multiplot\n"
		   "  set output\n"
		   "}\n",
		c->n_intervals ? " (shaded: chatter flagged)" : "");
	return close_out(f, path, 0);
}

/* Panel p of variants.gp: 0 position, 1 W - E_ref, 2 PC force. */
static int has_panel(const report_log *lg, int p)
{
	return p == 0 || (p == 1 ? lg->sum.has_w : lg->sum.has_pc_force);
}

static int write_variants_script(const report_out *ro, const report_log *logs, int n)
{
	char path[1400];
	FILE *f = open_in(ro, "variants.gp", path, sizeof path);
	if (!f)
		return -1;
	fputs("# popc-analyze report: the logs overlaid. Rerun here: gnuplot variants.gp\n"
	      "do for [out in \"png pdf\"] {\n",
	      f);
	write_terminal_block(f, "variants", "1000,1000", "7in,7.5in");
	fputs("  set multiplot layout 3,1 title \"variants overlaid\"\n"
	      "  set grid\n"
	      "  set key top right\n"
	      "  set lmargin 12\n",
	      f);
	static const struct {
		int col;
		const char *label;
	} panels[3] = {{2, "position x (m)"}, {10, "W - E_ref (J)"}, {6, "PC force (N)"}};
	for (int p = 0; p < 3; p++) {
		/* a log without a PC force has no W - E_ref (unless logged) and no PC
		 * force: it is left out of those panels; a panel nobody has is empty */
		int any = 0;
		for (int i = 0; i < n; i++)
			any |= has_panel(&logs[i], p);
		fprintf(f, "  set ylabel \"%s\"\n  set xlabel \"%s\"\n", panels[p].label,
			p == 2 ? "t (s)" : "");
		if (!any) {
			fputs("  set yrange [-1:1]\n"
			      "  set label 1 \"n/a: no log has a PC force\" at graph 0.5, 0.5 center\n"
			      "  plot 0 with lines lc rgb \"gray\" notitle\n"
			      "  unset label 1\n"
			      "  set autoscale y\n",
			      f);
			continue;
		}
		fputs("  plot ", f);
		for (int i = 0, k = 0; i < n; i++) {
			if (!has_panel(&logs[i], p))
				continue;
			fprintf(f, "%s\"%s.dat\" using 1:%d with lines lw 1 title \"%s\"",
				k++ ? ", \\\n       " : "", logs[i].name, panels[p].col, logs[i].name);
		}
		fputc('\n', f);
	}
	fputs("  unset multiplot\n  set output\n}\n", f);
	return close_out(f, path, 0);
}

static void html_escape(FILE *f, const char *s)
{
	for (; *s; s++) {
		switch (*s) {
		case '<': fputs("&lt;", f); break;
		case '>': fputs("&gt;", f); break;
		case '&': fputs("&amp;", f); break;
		case '"': fputs("&quot;", f); break;
		default: fputc(*s, f);
		}
	}
}

static int file_ok(const char *dir, const char *name, const char *ext)
{
	char path[1400];
	snprintf(path, sizeof path, "%s/%s.%s", dir, name, ext);
	struct stat st;
	return stat(path, &st) == 0 && st.st_size > 0;
}

static const char *pdf_ext(const char *dir, const char *name)
{
	return file_ok(dir, name, "pdf") ? "pdf" : "eps";
}

static int write_index(const report_out *ro, const char *title, const report_log *logs, int n,
		       int drawn)
{
	char path[1400];
	const char *dir = ro->dir;
	char md_path[1400];
	FILE *md = open_in(ro, "index.md", md_path, sizeof md_path);
	if (!md)
		return -1;
	FILE *html = open_in(ro, "index.html", path, sizeof path);
	if (!html) {
		fclose(md);
		return -1;
	}
	fprintf(md, "# %s\n\n"
		    "Written by `popc-analyze report`. Each figure has its gnuplot script (`.gp`)\n"
		    "and decimated data (`.dat`) beside it; rerun with `gnuplot NAME.gp` here.\n"
		    "Metrics and chatter thresholds: docs/ANALYSIS.md.\n\n"
		    "## Comparison\n\n",
		title);
	ana_summary_print_header(md, ANA_MARKDOWN);
	for (int i = 0; i < n; i++)
		ana_summary_print_row(md, ANA_MARKDOWN, &logs[i].sum);
	fputs("\nAlso as CSV: [compare.csv](compare.csv).\n\n## Variants overlaid\n\n", md);
	if (drawn)
		fprintf(md, "![variants](variants.png)\n\n[PDF](variants.%s) · [script](variants.gp)\n\n",
			pdf_ext(dir, "variants"));
	else
		fputs("[script](variants.gp) (not drawn: --no-draw)\n\n", md);
	fputs("## Logs\n\n", md);

	fputs("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>", html);
	html_escape(html, title);
	fputs("</title>\n<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
	      "td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
	      "img{max-width:100%}</style></head><body>\n<h1>",
	      html);
	html_escape(html, title);
	fputs("</h1>\n<p>Written by <code>popc-analyze report</code>; each figure's gnuplot script "
	      "(<code>.gp</code>) and decimated data (<code>.dat</code>) are beside it.</p>\n"
	      "<h2>Comparison</h2>\n<table>\n<tr><th>log</th><th>variant</th><th>pc_rms (N)</th>"
	      "<th>pc_rms_late (N)</th><th>pc_max (N)</th><th>pc_active</th><th>W-E_ref end (J)</th>"
	      "<th>vsign/s</th><th>chatter (s)</th><th>limit cycle</th></tr>\n",
	      html);
	for (int i = 0; i < n; i++) {
		const ana_summary *s = &logs[i].sum;
		fprintf(html, "<tr><td><a href=\"#%s\">%s</a></td><td>", logs[i].name, logs[i].name);
		html_escape(html, s->variant);
		fputs("</td>", html);
		/* as compare.md: a cell without data behind it is n/a, never a 0 */
		const struct {
			double v;
			int known;
		} cell[] = {
			{s->pc_rms_N, s->has_pc_force},     {s->pc_rms_late_N, s->has_pc_force},
			{s->pc_max_N, s->has_pc_force},     {s->pc_active, s->has_pc_force},
			{s->w_minus_eref_end_J, s->has_w},  {s->vsign_rate_Hz, 1},
			{s->chatter.chatter_s, ana_chatter_checked(s)},
		};
		for (size_t k = 0; k < sizeof cell / sizeof cell[0]; k++) {
			if (cell[k].known)
				fprintf(html, "<td>%.4g</td>", cell[k].v);
			else
				fputs("<td>n/a</td>", html);
		}
		fprintf(html, "<td>%s</td></tr>\n",
			!ana_lc_checked(s) ? "n/a" : s->chatter.limit_cycle ? "yes" : "no");
	}
	fputs("</table>\n<p><a href=\"compare.csv\">compare.csv</a> · "
	      "<a href=\"compare.md\">compare.md</a></p>\n<h2>Variants overlaid</h2>\n",
	      html);
	if (drawn)
		fprintf(html, "<p><img src=\"variants.png\" alt=\"variants\"><br><a href=\"variants.%s\">PDF</a> · "
			      "<a href=\"variants.gp\">script</a></p>\n",
			pdf_ext(dir, "variants"));
	fputs("<h2>Logs</h2>\n", html);
	for (int i = 0; i < n; i++) {
		const char *nm = logs[i].name;
		const popc_chatter_result *c = &logs[i].sum.chatter;
		fprintf(md, "### %s (variant %s)\n\n", nm, logs[i].sum.variant);
		fprintf(html, "<h3 id=\"%s\">%s (variant ", nm, nm);
		html_escape(html, logs[i].sum.variant);
		fputs(")</h3>\n<p>", html);
		if (!ana_chatter_checked(&logs[i].sum)) {
			const char *why = logs[i].sum.has_pc_force ? "shorter than one chatter window"
								   : "no PC force";
			fprintf(md, "Chatter not checked (%s).", why);
			fprintf(html, "Chatter not checked (%s).", why);
		} else if (c->n_intervals) {
			fprintf(md, "Chatter flagged: %.3f s in %d interval(s).", c->chatter_s, c->n_intervals);
			fprintf(html, "Chatter flagged: %.3f s in %d interval(s).", c->chatter_s,
				c->n_intervals);
		} else {
			fputs("No chatter flagged.", md);
			fputs("No chatter flagged.", html);
		}
		if (!ana_lc_checked(&logs[i].sum)) {
			fputs(" Limit cycle not checked (shorter than half a limit-cycle window).\n\n",
			      md);
			fputs(" Limit cycle not checked (shorter than half a limit-cycle window).\n\n",
			      html);
		} else {
			const char *lc = c->limit_cycle ? "Limit cycle" : "No limit cycle";
			fprintf(md, " %s: amplitude %.3g m at %.3g Hz over the last %.3g s.\n\n", lc,
				c->lc_amplitude_m, c->lc_frequency_Hz, c->lc_span_s);
			fprintf(html, " %s: amplitude %.3g m at %.3g Hz over the last %.3g s.\n\n",
				lc, c->lc_amplitude_m, c->lc_frequency_Hz, c->lc_span_s);
		}
		if (drawn) {
			fprintf(md, "![%s](%s.png)\n\n[PDF](%s.%s) · [script](%s.gp) · [data](%s.dat)\n\n", nm,
				nm, nm, pdf_ext(dir, nm), nm, nm);
			fprintf(html, "</p><p><img src=\"%s.png\" alt=\"%s\"><br><a href=\"%s.%s\">PDF</a> · "
				      "<a href=\"%s.gp\">script</a> · <a href=\"%s.dat\">data</a></p>\n",
				nm, nm, nm, pdf_ext(dir, nm), nm, nm);
		} else {
			fprintf(md, "[script](%s.gp) · [data](%s.dat)\n\n", nm, nm);
			fprintf(html, "</p><p><a href=\"%s.gp\">script</a> · <a href=\"%s.dat\">data</a></p>\n",
				nm, nm);
		}
	}
	fputs("</body></html>\n", html);
	int bad = close_out(md, md_path, 0) != 0;
	bad |= close_out(html, path, 0) != 0;
	return bad ? -1 : 0;
}

static int write_tables(const report_out *ro, const report_log *logs, int n)
{
	char path[1400], csv_path[1400];
	FILE *csv = open_in(ro, "compare.csv", csv_path, sizeof csv_path);
	if (!csv)
		return -1;
	FILE *md = open_in(ro, "compare.md", path, sizeof path);
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
	int bad = close_out(csv, csv_path, 0) != 0;
	bad |= close_out(md, path, 0) != 0;
	return bad ? -1 : 0;
}

typedef struct report_name {
	char name[256];
} report_name;

/* Each input's name in the report (a unique, file-name-safe form of its file
 * name, from the paths alone), and a check of every path the report will
 * write: each must be usable as a file (ana_output_file_usable). Returns 0
 * or 2 after saying which. */
static int name_outputs(const report_out *ro, report_name *names)
{
	static const char *const fixed[] = {"compare.csv", "compare.md",   "index.md",
					    "index.html",  "variants.gp",  "variants.png",
					    "variants.pdf", "variants.eps"};
	static const char *const per_log[] = {"dat", "gp", "png", "pdf", "eps"};
	char path[1400];
	for (size_t k = 0; k < sizeof fixed / sizeof fixed[0]; k++) {
		snprintf(path, sizeof path, "%s/%s", ro->dir, fixed[k]);
		if (ana_output_file_usable("report", "-o", path) != 0)
			return 2;
	}
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
				snprintf(names[i].name, sizeof names[i].name, "%.240s-%d", base, k);
		}
		for (size_t k = 0; k < sizeof per_log / sizeof per_log[0]; k++) {
			snprintf(path, sizeof path, "%s/%s.%s", ro->dir, names[i].name, per_log[k]);
			if (ana_output_file_usable("report", "-o", path) != 0)
				return 2;
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

static int draw(const char *gnuplot, const report_out *ro, const char *name)
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
		if (check_not_input(ro, fig) != 0)
			return -2;
		if (remove(fig) != 0 && errno != ENOENT) { /* an output path, not gnuplot: 2 */
			fprintf(stderr, "popc-analyze report: %s: cannot replace: %s\n", fig,
				strerror(errno));
			return -2;
		}
	}
	if (ana_run_gnuplot(gnuplot, dir, script, why, sizeof why) != 0) {
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

int ana_cmd_report(int argc, char **argv)
{
	static const struct option opts[] = {
		{"output-dir", required_argument, NULL, 'o'},
		{"points", required_argument, NULL, OPT_POINTS},
		{"title", required_argument, NULL, OPT_TITLE},
		{"gnuplot", required_argument, NULL, OPT_GNUPLOT},
		{"no-draw", no_argument, NULL, OPT_NO_DRAW},
		{"threshold", required_argument, NULL, OPT_THRESHOLD},
		{"help", no_argument, NULL, 'h'},
		ANA_INPUT_LONG_OPTIONS,
		{NULL, 0, NULL, 0},
	};
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "report";
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	const char *dir = NULL, *title = "popc report", *gnuplot = "gnuplot";
	long long points = 2000;
	int no_draw = 0, c, rc = 0, n = 0;
	report_log *logs = NULL;
	report_name *names = NULL;
	optind = 1;
	while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
		switch (c) {
		case 'o': dir = optarg; break;
		case OPT_POINTS: {
			if (popc_parse_ll_text(optarg, 10, 1000000, &points) != 0) {
				fprintf(stderr, "popc-analyze report: --points '%s': 10 to 1000000\n", optarg);
				rc = 2;
				goto out;
			}
			break;
		}
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
		default: usage(stderr); rc = 2; goto out;
		}
	}
	if (!dir || optind >= argc || argc - optind > MAX_LOGS) {
		fprintf(stderr, "popc-analyze report: %s\n",
			!dir ? "missing -o DIR" : optind >= argc ? "missing LOG" : "at most 256 logs");
		usage(stderr);
		rc = 2;
		goto out;
	}
	if ((rc = ana_output_dir_usable("report", "-o", dir, 1)) != 0)
		goto out;
	if (make_dir(dir) != 0) {
		rc = 2;
		goto out;
	}
	const report_out ro = {dir, argv + optind, argc - optind};
	logs = calloc((size_t)(argc - optind), sizeof *logs);
	names = calloc((size_t)(argc - optind), sizeof *names);
	if (!logs || !names) {
		rc = 2;
		goto out;
	}
	/* every file the report writes, before any log is read: a path there
	 * that is a directory is bad usage, not a figure that failed (a non-empty
	 * directory named NAME.png could not be replaced: exit 1 after all the
	 * work) */
	if ((rc = name_outputs(&ro, names)) != 0)
		goto out;
	for (int i = optind; i < argc; i++) {
		report_log *lg = &logs[n];
		ana_decimator dec;
		if (ana_decim_init(&dec, D_COLS, (int)points * 2) != 0) {
			fprintf(stderr, "popc-analyze report: out of memory\n");
			rc = 2;
			goto out;
		}
		popc_error err;
		int st = ana_summarize(argv[i], &in, &cc, -1.0, &lg->sum, on_row, &dec, &err);
		if (st) {
			ana_decim_free(&dec);
			rc = ana_fail("report", st, &err);
			continue;
		}
		if (!lg->sum.has_pc_force) {
			ana_no_pc_force(&err, argv[i]);
			fprintf(stderr, "popc-analyze report: note: %s; no PC force panel, its PC and "
					"chatter columns%s are n/a\n",
				err.msg, lg->sum.has_w ? "" : " and W - E_ref");
		} else if (!ana_chatter_checked(&lg->sum)) {
			ana_chatter_too_short(&err, argv[i], &lg->sum);
			fprintf(stderr, "popc-analyze report: note: %s; its chatter columns are n/a\n",
				err.msg);
		}
		if (!ana_lc_checked(&lg->sum)) {
			ana_lc_too_short(&err, argv[i], &lg->sum);
			fprintf(stderr,
				"popc-analyze report: note: %s; its limit-cycle columns are n/a\n",
				err.msg);
		}
		script_safe(lg->sum.variant);
		snprintf(lg->name, sizeof lg->name, "%s", names[i - optind].name);
		lg->has_x_true = 0;
		for (int b = 0; b < dec.n; b++)
			lg->has_x_true |= !isnan(dec.b[b].mn[D_X_TRUE]);
		char path[1400], file[300];
		snprintf(file, sizeof file, "%s.dat", lg->name);
		FILE *f = open_in(&ro, file, path, sizeof path);
		int bad = !f; /* open_in said why: a refusal to overwrite an input, or errno */
		if (f) {
			fprintf(f, "# %s decimated (min/max per bucket of %lld ticks)\n"
				   "# t x x_true v f_e f_pc f_c W E_ref W-E_ref\n",
				argv[i], dec.width);
			bad = close_out(f, path, ana_decim_write(&dec, f) != 0) != 0;
		}
		ana_decim_free(&dec);
		/* each failure has printed its one message (which file, why) */
		if (bad || write_log_script(&ro, lg) != 0) {
			rc = 2;
			goto out;
		}
		n++;
	}
	if (n == 0)
		goto out;
	if (write_variants_script(&ro, logs, n) != 0 || write_tables(&ro, logs, n) != 0) {
		rc = 2;
		goto out;
	}
	int drawn = 0;
	if (!no_draw) {
		int failed = 0, refused = 0;
		for (int i = 0; i < n; i++) {
			int d = draw(gnuplot, &ro, logs[i].name);
			failed |= d != 0;
			refused |= d == -2;
		}
		int d = draw(gnuplot, &ro, "variants");
		failed |= d != 0;
		refused |= d == -2;
		if (refused)
			rc = 2;
		else if (failed && rc == 0)
			rc = 1;
		drawn = !failed;
	}
	if (write_index(&ro, title, logs, n, drawn) != 0) {
		rc = 2;
		goto out;
	}
	printf("%s/index.html\n", dir);
out:
	free(logs);
	free(names);
	ana_input_free(&in);
	return rc;
}
