/* The gnuplot scripts of the report's figures (report.h): each names the
 * paper figure it reproduces (a "# paper_figure = N" line and its title), the
 * log it came from and the scene's parameters (a box); force axes take the
 * report's shared scales so variants compare by eye. */
#include <math.h>
#include <string.h>

#include "report.h"

const char *const report_fig_suffix[RF_COUNT] = {"",      "-fig4",  "-fig5", "-fig6",
						 "-fig8", "-fig11", "-zoom"};

int report_contact_paper_fig(const char *variant)
{
	/* Fig. 3: energy-following PO/PC [18]; Fig. 10: its filtered velocity;
	 * Fig. 14: ignoring the sign-change energy; Fig. 16: holding and ignoring */
	static const struct {
		const char *variant;
		int fig;
	} map[] = {{"ref-energy", 3}, {"filtered-velocity", 10}, {"ignore", 14}, {"improved", 16}};
	for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
		if (strcmp(variant, map[i].variant) == 0)
			return map[i].fig;
	return 0;
}

static const char *paper_variant(int fig)
{
	switch (fig) {
	case 3: return "ref-energy";
	case 10: return "filtered-velocity";
	case 14: return "ignore";
	case 16: return "improved";
	default: return "?";
	}
}

/* The terminal lines shared by every script: pngcairo/pdfcairo when this
 * gnuplot has them (Debian's gnuplot-nox does), else png and EPS. */
void report_terminal_block(FILE *f, const char *file, const char *png_size, const char *pdf_size)
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
		png_size, png_size, file, pdf_size, file, file);
}

/* Text from a log (its path, its header's variant) goes into double-quoted
 * gnuplot strings, where '"' ends the string and a backquote runs a shell
 * command: keep the characters such names use, '_' for the others. */
static void safe_text(const char *in, char *out, size_t cap)
{
	size_t i = 0;
	for (; in[i] && i + 1 < cap; i++) {
		char c = in[i];
		int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
			 strchr(" -_.,:;=+()/", c) != NULL;
		out[i] = ok ? c : '_';
	}
	out[i] = '\0';
}

void report_safe_text(const char *in, char *out, size_t cap)
{
	safe_text(in, out, cap);
}

/* The scene's parameters, boxed at the figure's top right corner. */
static void parameter_box(FILE *f, const report_log *lg)
{
	const ana_summary *s = &lg->sum;
	fprintf(f,
		"  set label 99 \"variant %s\\nK_e = %g N/m, delta = %g m\\nT = %g s, pc_bound = %g N\\n"
		"ignore_mode = %s\" at screen 0.99, 0.99 right front boxed\n"
		"  set key outside right bottom # the first panel's: the box is above it\n",
		s->variant, s->env_stiffness_Npm, s->enc_resolution_m, s->period_s, s->pc_bound_N,
		s->ignore_mode);
}

/* Everything before the first panel: the header comments, the terminal, the
 * multiplot with its two-line title (paper figure, then log), margins that
 * align the panels and leave the keys room outside them on the right. */
static void begin(FILE *f, const report_log *lg, report_fig fig, int paper_fig, const char *what,
		  int rows, int cols, const char *png_size, const char *pdf_size)
{
	char file[300], path[1024];
	snprintf(file, sizeof file, "%s%s", lg->name, report_fig_suffix[fig]);
	safe_text(lg->path, path, sizeof path);
	fprintf(f,
		"# popc-analyze report: %s.png and .pdf. Rerun here: gnuplot %s.gp\n"
		"# paper_figure = %d (Ryu, Hannaford, Kwon, Kim, IEEE T-RO 2005; 0: none)\n"
		"# log = %s, variant %s\n"
		"# data columns: %s\n"
		"do for [out in \"png pdf\"] {\n",
		file, file, paper_fig, path, lg->sum.variant,
		fig == RF_CONTACT || fig == RF_FIG4 ? REPORT_ENV_COLUMNS : REPORT_DAT_COLUMNS);
	report_terminal_block(f, file, png_size, pdf_size);
	fprintf(f,
		"  set multiplot layout %d,%d title \"%s\\nlog %s (variant %s)\"\n"
		"  set grid\n"
		"  set key outside right top vertical\n"
		"  set lmargin at screen %s\n"
		"  set rmargin at screen %s\n",
		rows, cols, what, path, lg->sum.variant, cols > 1 ? "0.08" : "0.1",
		cols > 1 ? "0.78" : "0.76");
	if (cols > 1) /* side by side: each panel sets its own margins */
		fputs("  unset lmargin\n  unset rmargin\n  set key inside top left\n", f);
	parameter_box(f, lg);
}

static void end(FILE *f)
{
	fputs("  unset multiplot\n"
	      "  set output\n"
	      "}\n",
	      f);
}

/* After a panel: back to the defaults the next panel expects. */
/* After a panel: back to the defaults the next panel expects. */
static void reset(FILE *f)
{
	fputs("  unset label 99\n  unset arrow\n  unset object\n  set autoscale y\n"
	      "  unset title\n  unset label 98\n  set format y \"%g\"\n  set key outside right top vertical\n",
	      f);
}

/* Decimals that show one count of the encoder in mm (0.01 mm: 2). */
static int mm_decimals(double resolution_m)
{
	int k = 0;
	for (double d = resolution_m * 1e3; d < 0.999999 && k < 9; d *= 10.0)
		k++;
	return k;
}

/* A panel's letter and what it shows, in its top left corner: (a) .. (d) are
 * the paper's panels; the others are popc's additions and say so. */
static void panel_title(FILE *f, char letter, const char *what)
{
	/* a blank title keeps the line above the panel; the label fills it from
	 * the panel's left edge */
	fprintf(f,
		"  set title \" \"\n  set label 98 \"(%c) %s\" at graph 0, graph 1 offset 0,0.9 "
		"left front\n",
		letter, what);
}

/* The PC force axis, the same in every figure of the report. */
static void f_pc_range(FILE *f, const report_scales *sc)
{
	fprintf(f, "  set yrange [%.6g:%.6g] # shared f_pc scale\n", -sc->f_pc_N, sc->f_pc_N);
}

static void f_c_range(FILE *f, const report_scales *sc)
{
	fprintf(f, "  set yrange [%.6g:%.6g] # shared f_c scale\n", sc->f_c_min_N, sc->f_c_max_N);
}

/* A log's own PC force scale when the shared one would flatten it (its
 * largest |f_pc| under a quarter of the shared axis: improved's +-0.04 N
 * beside ref-energy's +-5 N), else 0: 1.1 x its largest |f_pc|. */
double report_own_f_pc_N(const report_log *lg, const report_scales *sc)
{
	const double own = 1.1 * lg->sum.pc_max_N;
	return lg->sum.has_pc_force && own > 0.0 && own < sc->f_pc_N / 4.0 ? own : 0.0;
}

/* A column of NAME.dat for a using spec: its number, or an expression that
 * converts it ("*1e3"; a bare number is gnuplot's fast path, about half the
 * time of column(N) on a long log's 8000 rows) */
static const char *env_col(int col, const char *unit, char *buf, size_t cap)
{
	if (unit[0])
		snprintf(buf, cap, "(column(%d)%s)", col, unit);
	else
		snprintf(buf, cap, "%d", col);
	return buf;
}

void report_envelope(FILE *f, const char *data, int col, const char *unit, const char *rgb,
		     const char *dash, const char *title, const char *axes)
{
	/* the band between the bucket's min and max, lightly filled, and its
	 * two edges: chatter reads as the band it fills, a quiet signal as a
	 * line (min = max); unit converts for the axis ("*1e3": m to mm) */
	char mn[64], mx[64];
	env_col(REPORT_ENV_MIN(col), unit, mn, sizeof mn);
	env_col(REPORT_ENV_MAX(col), unit, mx, sizeof mx);
	fprintf(f,
		"%s using 1:%s:%s with filledcurves fc rgb \"%s\" fs transparent solid 0.25 "
		"noborder axes %s notitle, "
		"%s using 1:%s with lines lw 1 dt %s lc rgb \"%s\" axes %s notitle, "
		"%s using 1:%s with lines lw 1 dt %s lc rgb \"%s\" axes %s title \"%s\"",
		data, mn, mx, rgb, axes, data, mn, dash, rgb, axes, data, mx, dash, rgb, axes, title);
}

static void true_x(FILE *f, const report_log *lg, const char *unit)
{
	if (!lg->has_x_true)
		return;
	fputs(", ", f);
	report_envelope(f, "data", D_X_TRUE, unit, REPORT_RED, "2", "true x_true", "x1y1");
}

/* (a) zoomed: the measured position in counts (x / delta) where the counts
 * show: the settled stretch (Fig. 4's settle, when the events give it) plus
 * 5 counts either side, or else everything from the first contact plus 3.
 * Returns 0 when there is neither (no contact): no such panel. */
static int counts_range(FILE *f, const report_log *lg)
{
	const double d = lg->sum.enc_resolution_m;
	if (!isnan(lg->x_settled_min_m)) {
		fprintf(f,
			"  set yrange [%.9g:%.9g] # x while settled (from t = %.6g s), 5 counts "
			"either side\n",
			lg->x_settled_min_m / d - 5.0, lg->x_settled_max_m / d + 5.0, lg->t_settle_s);
		return 1;
	}
	if (isnan(lg->t_contact_s))
		return 0;
	fprintf(f, "  set yrange [%.9g:%.9g] # x from the first contact at t = %.6g s\n",
		lg->x_contact_min_m / d - 3.0, lg->x_contact_max_m / d + 3.0, lg->t_contact_s);
	return 1;
}

static void write_contact(FILE *f, const report_log *lg, const report_scales *sc, int fig_asked)
{
	const ana_summary *s = &lg->sum;
	int own = report_contact_paper_fig(s->variant);
	int fig = fig_asked ? fig_asked : own;
	char what[400], unit[64];
	if (fig == 0)
		snprintf(what, sizeof what,
			 "contact response in the form of paper Fig. 3 (the paper shows no figure of "
			 "variant %s)",
			 s->variant);
	else if (fig == own)
		snprintf(what, sizeof what, "paper Fig. %d: contact response, variant %s", fig,
			 s->variant);
	else
		snprintf(what, sizeof what,
			 "paper Fig. %d's panels (the paper's variant %s; this log's %s)", fig,
			 paper_variant(fig), s->variant);
	const int counts = !isnan(lg->x_settled_min_m) || !isnan(lg->t_contact_s);
	const double own_pc = report_own_f_pc_N(lg, sc);
	int panels = 3 + counts + (s->has_w ? 1 : 0) + (s->has_pc_force ? 2 : 0) + (own_pc > 0.0);
	char png[32], pdf[32];
	snprintf(png, sizeof png, "1000,%d", 160 + 190 * panels);
	snprintf(pdf, sizeof pdf, "7.5in,%.2fin", 1.2 + 1.3 * panels);
	begin(f, lg, RF_CONTACT, fig, what, panels, 1, png, pdf);
	fprintf(f, "  data = \"%s.dat\"\n  set xrange [%.9g:%.9g]\n", lg->name, lg->t_first_s,
		lg->t_last_s);
	/* (a): the whole motion, approach included, in mm; then the counts */
	panel_title(f, 'a', "position, whole log (band: min to max per bucket)");
	fputs("  set ylabel \"position x (mm)\"\n  plot ", f);
	report_envelope(f, "data", D_X, "*1e3", REPORT_BLUE, "1", "measured x", "x1y1");
	true_x(f, lg, "*1e3");
	fputc('\n', f);
	reset(f);
	if (counts) {
		snprintf(unit, sizeof unit, "/%.17g", s->enc_resolution_m);
		fprintf(f, "  set ylabel \"x / delta (counts)\"\n");
		panel_title(f, 'a', "position in counts of the encoder, where the counts show");
		counts_range(f, lg);
		fputs("  plot ", f);
		report_envelope(f, "data", D_X, unit, REPORT_BLUE, "1", "measured x", "x1y1");
		true_x(f, lg, unit);
		fputc('\n', f);
		reset(f);
	}
	panel_title(f, 'b', "velocity");
	fputs("  set ylabel \"velocity (m/s)\"\n  plot ", f);
	report_envelope(f, "data", D_V, "", REPORT_PURPLE, "1", "v, the controller's", "x1y1");
	fputc('\n', f);
	reset(f);
	panel_title(f, 'c', "energy");
	fputs("  set ylabel \"energy (J)\"\n  plot ", f);
	if (s->has_w) {
		report_envelope(f, "data", D_W, "", REPORT_BLUE, "1", "W (PO)", "x1y1");
		fputs(", ", f);
	}
	report_envelope(f, "data", D_E_REF, "", REPORT_GREEN, "2", "E_ref", "x1y1");
	if (lg->has_e_port) {
		fputs(", ", f);
		report_envelope(f, "data", D_E_PORT, "", "black", "3", "E_port (true)", "x1y1");
	}
	fputc('\n', f);
	reset(f);
	char letter = 'd';
	if (s->has_pc_force) {
		const popc_chatter_result *c = &s->chatter;
		for (int pass = 0; pass < 1 + (own_pc > 0.0); pass++) {
			char t[200];
			if (pass == 0)
				snprintf(t, sizeof t, "PC force on the report's shared scale");
			else
				snprintf(t, sizeof t,
					 "PC force on this log's own scale, +-%.3g N (the shared one: "
					 "+-%.3g N)",
					 own_pc, sc->f_pc_N);
			panel_title(f, letter, t);
			fputs("  set ylabel \"PC force f_pc (N)\"\n", f);
			for (int i = 0; i < c->n_stored; i++)
				fprintf(f,
					"  set object %d rect from first %.9g, graph 0 to first %.9g, "
					"graph 1 fillcolor rgb \"#ffd8d8\" fillstyle solid 1.0 noborder "
					"behind\n",
					i + 1, c->intervals[i].start_s, c->intervals[i].end_s);
			if (pass == 0)
				f_pc_range(f, sc);
			else
				fprintf(f, "  set yrange [%.6g:%.6g] # this log's own f_pc scale\n",
					-own_pc, own_pc);
			fputs("  plot ", f);
			report_envelope(f, "data", D_F_PC, "", REPORT_RED, "1",
					c->n_intervals ? "f_pc\\n(shaded: chatter)" : "f_pc", "x1y1");
			fputc('\n', f);
			reset(f);
		}
		letter = 'e';
	}
	if (s->has_w) {
		panel_title(f, letter++, "W - E_ref (not a panel of the paper)");
		fputs("  set ylabel \"W - E_ref (J)\"\n  plot ", f);
		report_envelope(f, "data", D_WME, "", REPORT_PURPLE, "1", "W - E_ref", "x1y1");
		fputc('\n', f);
		reset(f);
	}
	if (s->has_pc_force) {
		panel_title(f, letter++, "forces (not a panel of the paper)");
		fputs("  set ylabel \"force (N)\"\n  set xlabel \"t (s)\"\n", f);
		f_c_range(f, sc);
		fputs("  plot ", f);
		report_envelope(f, "data", D_F_C, "", REPORT_GREEN, "1", "f_c = f_e + f_pc", "x1y1");
		fputs(", ", f);
		report_envelope(f, "data", D_F_E, "", "gray40", "2", "f_e", "x1y1");
		fputc('\n', f);
	}
	end(f);
}

static void write_fig4(FILE *f, const report_log *lg)
{
	const ana_summary *s = &lg->sum;
	const double count_v = s->enc_resolution_m / s->period_s; /* one count per tick */
	begin(f, lg, RF_FIG4, 4,
	      "paper Fig. 4: backward velocity v(k) = (x(k) - x(k-1)) / T\\n(the log's v: "
	      "filtered-velocity logs its filtered velocity)",
	      2, 1,
	      "1000,800", "7.5in,5.8in");
	fprintf(f, "  data = \"%s.dat\"\n  set xrange [%.9g:%.9g]\n", lg->name, lg->t_first_s,
		lg->t_last_s);
	panel_title(f, 'a', "velocity, whole log (band: min to max per bucket)");
	fputs("  set ylabel \"v (m/s)\"\n  plot ", f);
	report_envelope(f, "data", D_V, "", REPORT_PURPLE, "1", "v, whole log", "x1y1");
	fputc('\n', f);
	reset(f);
	fprintf(f,
		"  set ylabel \"v (m/s), +-4 counts/T\"\n  set xlabel \"t (s)\"\n"
		"  set yrange [%.6g:%.6g]\n  set ytics %.6g\n",
		-4.5 * count_v, 4.5 * count_v, count_v);
	if (!isnan(lg->t_settle_s)) {
		char final[120] = "", what[300];
		if (!isnan(lg->t_settle_final_s))
			snprintf(final, sizeof final, "; to the end from %.4g s", lg->t_settle_final_s);
		fprintf(f,
			"  set arrow 1 from first %.9g, graph 0 to first %.9g, graph 1 nohead lw 2 "
			"lc rgb \"#d62728\"\n",
			lg->t_settle_s, lg->t_settle_s);
		snprintf(what, sizeof what,
			 "red line: within one count (+-%.3g m/s) for %g s from t = %.4g s%s "
			 "(paper: after 2.5 s)",
			 count_v, ANA_SETTLE_HOLD_S, lg->t_settle_s, final);
		panel_title(f, 'b', what);
	} else {
		panel_title(f, 'b', "velocity zoomed to +-4 counts per period");
	}
	fputs("  plot ", f);
	report_envelope(f, "data", D_V, "", REPORT_PURPLE, "1", "v, zoomed", "x1y1");
	fputs("\n  unset title\n  unset label 98\n  set ytics autofreq\n", f);
	end(f);
}

/* Figs. 5 and 8 and --zoom: raw rows either side of the event. */
static void write_zoom(FILE *f, report_fig fig, const report_log *lg)
{
	const ana_summary *s = &lg->sum;
	report_win w = fig == RF_FIG5	? RW_FIG5
		       : fig == RF_FIG8 ? RW_FIG8
		       : fig == RF_FIG11 ? RW_END
					: RW_ZOOM;
	const double t = lg->t_event_s[w];
	char what[400];
	if (fig == RF_FIG5)
		snprintf(what, sizeof what,
			 "paper Fig. 5: sudden sign change of the velocity, its effect on W - E_ref\\n"
			 "(paper: t = 3.173/3.174 s; here t = %.4f s)",
			 t);
	else if (fig == RF_FIG8)
		snprintf(what, sizeof what,
			 "paper Fig. 8: zero velocity after the PC acts, W - E_ref unchanged\\n"
			 "(paper: t = 2.957/2.958 s; here t = %.4f s)",
			 t);
	else if (fig == RF_FIG11)
		snprintf(what, sizeof what,
			 "paper Fig. 11: true against measured position at low velocity\\n"
			 "(the log's last %d ticks, around t = %.4f s)",
			 2 * REPORT_ZOOM_TICKS + 1, t);
	else
		snprintf(what, sizeof what, "zoom at t = %.6g s (--zoom), in the form of paper Figs. 5 and 8",
			 t);
	int panels = 3 + (s->has_w ? 1 : 0) + (s->has_pc_force ? 1 : 0);
	begin(f, lg, fig, fig == RF_FIG5 ? 5 : fig == RF_FIG8 ? 8 : fig == RF_FIG11 ? 11 : 0, what,
	      panels, 1, "1000,1400",
	      "7.5in,10.2in");
	const double T = s->period_s;
	fprintf(f,
		"  data = \"%s%s.dat\"\n"
		"  set xrange [%.9g:%.9g]\n"
		"  set arrow 1 from first %.9g, graph 0 to first %.9g, graph 1 nohead lw 1 dt 2 "
		"lc rgb \"black\" back\n"
		"  set arrow 2 from first %.9g, graph 0 to first %.9g, graph 1 nohead lw 1 dt 3 "
		"lc rgb \"black\" back\n",
		lg->name, report_fig_suffix[fig], t - (REPORT_ZOOM_TICKS + 0.5) * T,
		t + (REPORT_ZOOM_TICKS + 0.5) * T, t, t, t + T, t + T);
	/* each tick's value holds until the next (ZOH): steps, with the ticks
	 * marked; positions in mm, "%g": a window of two counts has ticks a
	 * quarter count apart (0.9525 mm), which fixed decimals would repeat */
	char letter = 'a';
	panel_title(f, letter++, "position");
	fputs("  set ylabel \"position (mm)\"\n", f);
	fprintf(f,
		"  set format y \"%%g\"\n"
		"  plot data using 1:($2*1e3) with steps lw 2 lc rgb \"" REPORT_BLUE
		"\" title \"measured x\"%s\n"
		"  unset label 99\n  unset title\n"
		"  set key outside right top vertical\n",
		lg->has_x_true ? ", data using 1:($3*1e3) with lines lw 1 dt 2 lc rgb \"" REPORT_RED
				 "\" title \"true x_true\""
			       : "");
	panel_title(f, letter++, "velocity");
	fputs("  set ylabel \"v (m/s)\"\n"
	      "  plot data using 1:4 with linespoints pt 7 ps 0.7 lw 1 lc rgb \"" REPORT_PURPLE
	      "\" title \"v = dx/T\"\n",
	      f);
	if (s->has_w) {
		panel_title(f, letter++, "W - E_ref");
		fputs("  set ylabel \"W - E_ref (J)\"\n"
		      "  plot data using 1:10 with linespoints pt 7 ps 0.7 lw 1 lc rgb \"" REPORT_PURPLE
		      "\" title \"W - E_ref\"\n",
		      f);
	}
	if (s->has_pc_force) {
		panel_title(f, letter++, "PC force");
		fputs("  set ylabel \"f_pc (N)\"\n"
		      "  plot data using 1:6 with steps lw 2 lc rgb \"" REPORT_RED "\" title \"f_pc\", "
		      "data using 1:6 with points pt 7 ps 0.7 lc rgb \"" REPORT_RED "\" notitle\n",
		      f);
	}
	panel_title(f, letter++, "forces");
	fputs("  set ylabel \"force (N)\"\n  set xlabel \"t (s)\"\n"
	      "  plot data using 1:7 with steps lw 2 lc rgb \"" REPORT_GREEN "\" title \"f_c\", "
	      "data using 1:5 with steps lw 1 dt 2 lc rgb \"gray40\" title \"f_e\"\n",
	      f);
	end(f);
}

/* Fig. 7's point labels: ticks at the same (x, f_c) share one label ("-3 -2
 * -1", the paper's Fig. 7 has such repeats: a tick that moves no count and
 * keeps its force), and labels in one column of x alternate right and left
 * of their points in the order of f_c, so that none prints over another. */
static void fig7_labels(FILE *f, const report_log *lg)
{
	int order[REPORT_FIG7_TICKS], n = lg->fig7_n;
	for (int i = 0; i < n; i++)
		order[i] = i;
	for (int i = 1; i < n; i++) /* insertion sort by (x, f_c, tick) */
		for (int j = i; j > 0; j--) {
			int a = order[j - 1], b = order[j];
			double xa = lg->fig7_x_m[a], xb = lg->fig7_x_m[b];
			double fa = lg->fig7_f_c_N[a], fb = lg->fig7_f_c_N[b];
			if (xa < xb || (xa == xb && (fa < fb || (fa == fb && a < b))))
				break;
			order[j - 1] = b;
			order[j] = a;
		}
	int label = 10, in_column = 0;
	for (int i = 0; i < n;) {
		int a = order[i], j = i;
		char text[64] = "";
		size_t len = 0;
		for (; j < n && lg->fig7_x_m[order[j]] == lg->fig7_x_m[a] &&
		       lg->fig7_f_c_N[order[j]] == lg->fig7_f_c_N[a];
		     j++)
			len += (size_t)snprintf(text + len, sizeof text - len, "%s%+d", len ? " " : "",
						lg->fig7_tick[order[j]]);
		if (i > 0 && lg->fig7_x_m[order[i - 1]] != lg->fig7_x_m[a])
			in_column = 0;
		const int left = in_column++ % 2;
		fprintf(f, "  set label %d \"%s\" at %.17g, %.17g %s offset %s0.8,0.4 front\n", label++,
			text, lg->fig7_x_m[a] * 1e3, lg->fig7_f_c_N[a], left ? "right" : "left",
			left ? "-" : "");
		i = j;
	}
}

/* Figs. 6 and 7: force against position, index 0 the first press, index 1 the
 * ticks around the Fig. 5 event (or --zoom). */
static void write_fig6(FILE *f, const report_log *lg, report_win fig7_window)
{
	const ana_summary *s = &lg->sum;
	begin(f, lg, RF_FIG6, 6,
	      "paper Fig. 6: force against position, first press and release\\n"
	      "Fig. 7: the same at the velocity sign change of Fig. 5",
	      1, 2, "1300,650", "10in,5in");
	const char *x = lg->has_x_true ? "3" : "2";
	/* positions in mm: spring(x) takes mm */
	fprintf(f,
		"  data = \"%s-fig6.dat\"\n"
		"  K = %.17g\n  xw = %.17g\n"
		"  spring(x) = x >= xw * 1e3 ? K * (x * 1e-3 - xw) : 0\n"
		"  set lmargin at screen 0.06\n  set rmargin at screen 0.44\n  set key inside top left\n"
		"  set title \"(a) Fig. 6: the first press and release\"\n"
		"  set xlabel \"%s position (mm)\"\n  set ylabel \"force (N)\"\n"
		"  plot data index 0 using ($%s*1e3):5 with steps lw 1 dt 2 lc rgb \"gray30\" title \"f_e "
		"held (ZOH)\", data index 0 using ($%s*1e3):7 with steps lw 1 lc rgb \"" REPORT_GREEN
		"\" title \"f_c held (ZOH)\", spring(x) with lines lw 2 lc rgb \"black\" title \"ideal "
		"spring K_e x\"\n",
		lg->name, s->env_stiffness_Npm, s->env_position_m, lg->has_x_true ? "true" : "measured", x,
		x);
	reset(f);
	fputs("  set lmargin at screen 0.51\n  set rmargin at screen 0.84\n  set key inside top left\n"
	      "  set xlabel \"measured position x (mm)\"\n",
	      f);
	if (!lg->has_window[fig7_window] || isnan(lg->t_event_s[fig7_window]) || lg->fig7_n == 0) {
		fputs("  set title \"(b) Fig. 7\"\n"
		      "  set label 1 \"no Fig. 5 event in this log (give --zoom T)\" at graph 0.5, 0.5 "
		      "center\n  plot 0 with lines lc rgb \"gray\" notitle\n  unset label 1\n",
		      f);
		end(f);
		return;
	}
	/* the ticks k-3 .. k+3 around the event tick k, one count a tic; the
	 * x range one count beyond them either side, so no label is cut */
	double xmin = lg->fig7_x_m[0], xmax = xmin;
	for (int i = 1; i < lg->fig7_n; i++) {
		xmin = fmin(xmin, lg->fig7_x_m[i]);
		xmax = fmax(xmax, lg->fig7_x_m[i]);
	}
	const double d_mm = s->enc_resolution_m * 1e3;
	fprintf(f,
		"  set xrange [%.17g:%.17g]\n  set xtics %.9g\n  set format x \"%%.%df\"\n"
		"  set offsets 0, 0, graph 0.08, graph 0.08\n"
		"  E = %d\n  near(i) = i >= E - 3 && i <= E + 3\n"
		"  set title \"(b) Fig. 7: ticks k-3..k+3 at t(k) = %.4f s%s; labels: tick - k\"\n",
		xmin * 1e3 - d_mm, xmax * 1e3 + d_mm, d_mm, mm_decimals(s->enc_resolution_m),
		lg->fig7_event_row,
		lg->t_event_s[fig7_window], fig7_window == RW_ZOOM ? " (--zoom)" : "");
	fig7_labels(f, lg);
	fputs("  plot data index 1 using (near($0) ? $2*1e3 : 1/0):7 with steps lw 2 lc rgb \""
	      REPORT_GREEN "\" title \"f_c\", data index 1 using (near($0) ? $2*1e3 : 1/0):5 with "
	      "steps lw 1 dt 2 lc rgb \"gray30\" title \"f_e\", data index 1 using (near($0) ? "
	      "$2*1e3 : 1/0):7 with points pt 7 ps 0.8 lc rgb \"black\" notitle, spring(x) with lines "
	      "lw 1 lc rgb \"black\" title \"K_e x\"\n  unset title\n  unset offsets\n",
	      f);
	end(f);
}

int report_write_figure(FILE *f, report_fig fig, const report_log *lg, const report_scales *sc,
			int fig_asked)
{
	switch (fig) {
	case RF_CONTACT: write_contact(f, lg, sc, fig_asked); break;
	case RF_FIG4: write_fig4(f, lg); break;
	case RF_FIG5:
	case RF_FIG8:
	case RF_FIG11:
	case RF_ZOOM: write_zoom(f, fig, lg); break;
	case RF_FIG6:
		write_fig6(f, lg, lg->has_window[RW_FIG5] ? RW_FIG5 : RW_ZOOM);
		break;
	default: return -1;
	}
	return ferror(f) ? -1 : 0;
}
