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
static void terminal_block(FILE *f, const char *file, const char *png_size, const char *pdf_size)
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
		"# data columns: " REPORT_DAT_COLUMNS "\n"
		"do for [out in \"png pdf\"] {\n",
		file, file, paper_fig, path, lg->sum.variant);
	terminal_block(f, file, png_size, pdf_size);
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
static void reset(FILE *f)
{
	fputs("  unset label 99\n  unset arrow\n  unset object\n  set autoscale y\n"
	      "  set key outside right top vertical\n",
	      f);
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

/* The position axis where the counts show: the settled stretch (Fig. 4's
 * settle, when the events give it) or else everything from the first contact. */
static void contact_x_range(FILE *f, const report_log *lg)
{
	if (!isnan(lg->x_settled_min_m)) {
		double pad = 5.0 * lg->sum.enc_resolution_m;
		fprintf(f,
			"  set yrange [%.9g:%.9g] # x while settled (from t = %.6g s), 5 counts "
			"either side\n"
			"  set ylabel \"position (m), settled range\"\n",
			lg->x_settled_min_m - pad, lg->x_settled_max_m + pad, lg->t_settle_s);
		return;
	}
	if (isnan(lg->t_contact_s))
		return;
	double pad = 3.0 * lg->sum.enc_resolution_m;
	fprintf(f, "  set yrange [%.9g:%.9g] # x from the first contact at t = %.6g s\n",
		lg->x_contact_min_m - pad, lg->x_contact_max_m + pad, lg->t_contact_s);
}

static const char *true_x(const report_log *lg, const char *data, char *buf, size_t cap)
{
	if (!lg->has_x_true)
		return "";
	snprintf(buf, cap, ", %s using 1:3 with lines lw 1 dt 2 lc rgb \"#d62728\" title \"true x_true\"",
		 data);
	return buf;
}

static void write_contact(FILE *f, const report_log *lg, const report_scales *sc, int fig_asked)
{
	const ana_summary *s = &lg->sum;
	int own = report_contact_paper_fig(s->variant);
	int fig = fig_asked ? fig_asked : own;
	char what[400], tx[300];
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
	int panels = 3 + (s->has_w ? 1 : 0) + (s->has_pc_force ? 2 : 0);
	begin(f, lg, RF_CONTACT, fig, what, panels, 1, "1000,1500", "7.5in,10.5in");
	fprintf(f, "  data = \"%s.dat\"\n  set xrange [%.9g:%.9g]\n", lg->name, lg->t_first_s,
		lg->t_last_s);
	fputs("  set ylabel \"position (m)\"\n", f);
	contact_x_range(f, lg);
	fprintf(f, "  plot data using 1:2 with steps lw 1 lc rgb \"#1f77b4\" title \"measured x\"%s\n",
		true_x(lg, "data", tx, sizeof tx));
	reset(f);
	fputs("  set ylabel \"velocity (m/s)\"\n"
	      "  plot data using 1:4 with lines lw 1 title \"v, the controller's\"\n",
	      f);
	fprintf(f, "  set ylabel \"energy (J)\"\n  plot %sdata using 1:9 with lines lw 1 dt 2 title "
		   "\"E_ref\"%s\n",
		s->has_w ? "data using 1:8 with lines lw 1 title \"W (PO)\", " : "",
		lg->has_e_port ? ", data using 1:11 with lines lw 1 dt 3 lc rgb \"black\" title "
				 "\"E_port (true)\""
			       : "");
	if (s->has_w)
		fputs("  set ylabel \"W - E_ref (J)\"\n"
		      "  plot data using 1:10 with lines lw 1 lc rgb \"#9467bd\" title \"W - E_ref\"\n",
		      f);
	if (s->has_pc_force) {
		const popc_chatter_result *c = &s->chatter;
		fputs("  set ylabel \"PC force f_pc (N)\"\n", f);
		for (int i = 0; i < c->n_stored; i++)
			fprintf(f,
				"  set object %d rect from first %.9g, graph 0 to first %.9g, graph 1 "
				"fillcolor rgb \"#ffd8d8\" fillstyle solid 1.0 noborder behind\n",
				i + 1, c->intervals[i].start_s, c->intervals[i].end_s);
		f_pc_range(f, sc);
		fprintf(f, "  plot data using 1:6 with lines lw 1 lc rgb \"#d62728\" title \"f_pc%s\"\n",
			c->n_intervals ? "\\n(shaded: chatter)" : "");
		reset(f);
		fputs("  set ylabel \"force (N)\"\n  set xlabel \"t (s)\"\n", f);
		f_c_range(f, sc);
		fputs("  plot data using 1:7 with lines lw 1 lc rgb \"#2ca02c\" title \"f_c = f_e + f_pc\", "
		      "data using 1:5 with lines lw 1 dt 2 lc rgb \"gray40\" title \"f_e\"\n",
		      f);
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
	      "1000,750", "7.5in,5.5in");
	fprintf(f, "  data = \"%s.dat\"\n  set xrange [%.9g:%.9g]\n", lg->name, lg->t_first_s,
		lg->t_last_s);
	fputs("  set ylabel \"v (m/s)\"\n"
	      "  plot data using 1:4 with lines lw 1 title \"v, whole log\"\n",
	      f);
	reset(f);
	fprintf(f,
		"  set ylabel \"v (m/s), +-4 counts/T\"\n  set xlabel \"t (s)\"\n"
		"  set yrange [%.6g:%.6g]\n  set ytics %.6g\n",
		-4.5 * count_v, 4.5 * count_v, count_v);
	if (!isnan(lg->t_settle_s)) {
		char final[120] = "";
		if (!isnan(lg->t_settle_final_s))
			snprintf(final, sizeof final, "; to the end from %.4g s", lg->t_settle_final_s);
		fprintf(f,
			"  set arrow 1 from first %.9g, graph 0 to first %.9g, graph 1 nohead lw 2 "
			"lc rgb \"#d62728\"\n"
			"  set title \"red line: within one count (+-%.3g m/s) for %g s from t = %.4g s%s "
			"(paper: after 2.5 s)\"\n",
			lg->t_settle_s, lg->t_settle_s, count_v, ANA_SETTLE_HOLD_S, lg->t_settle_s,
			final);
	}
	fputs("  plot data using 1:4 with lines lw 1 title \"v, zoomed\"\n"
	      "  unset title\n  set ytics autofreq\n",
	      f);
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
	char what[400], tx[300];
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
	      panels, 1, "1000,1300",
	      "7.5in,9.5in");
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
	/* each tick's value holds until the next (ZOH): steps, with the ticks marked */
	fprintf(f,
		"  set ylabel \"position (m)\"\n  set format y \"%%.6f\"\n"
		"  plot data using 1:2 with steps lw 2 lc rgb \"#1f77b4\" title \"measured x\"%s\n"
		"  set format y \"%%g\"\n  unset label 99\n  set key outside right top vertical\n",
		true_x(lg, "data", tx, sizeof tx));
	fputs("  set ylabel \"v (m/s)\"\n"
	      "  plot data using 1:4 with linespoints pt 7 ps 0.7 lw 1 title \"v = dx/T\"\n",
	      f);
	if (s->has_w)
		fputs("  set ylabel \"W - E_ref (J)\"\n"
		      "  plot data using 1:10 with linespoints pt 7 ps 0.7 lw 1 lc rgb \"#9467bd\" title "
		      "\"W - E_ref\"\n",
		      f);
	if (s->has_pc_force)
		fputs("  set ylabel \"f_pc (N)\"\n"
		      "  plot data using 1:6 with steps lw 2 lc rgb \"#d62728\" title \"f_pc\", "
		      "data using 1:6 with points pt 7 ps 0.7 lc rgb \"#d62728\" notitle\n",
		      f);
	fputs("  set ylabel \"force (N)\"\n  set xlabel \"t (s)\"\n"
	      "  plot data using 1:7 with steps lw 2 lc rgb \"#2ca02c\" title \"f_c\", "
	      "data using 1:5 with steps lw 1 dt 2 lc rgb \"gray40\" title \"f_e\"\n",
	      f);
	end(f);
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
	fprintf(f,
		"  data = \"%s-fig6.dat\"\n"
		"  K = %.17g\n  xw = %.17g\n"
		"  spring(x) = x >= xw ? K * (x - xw) : 0\n"
		"  set lmargin at screen 0.06\n  set rmargin at screen 0.44\n  set key inside top left\n"
		"  set xlabel \"%s position (m)\"\n  set ylabel \"force (N)\"\n"
		"  plot data index 0 using %s:5 with steps lw 1 dt 2 lc rgb \"gray30\" title \"f_e held "
		"(ZOH)\", data index 0 using %s:7 with steps lw 1 lc rgb \"#2ca02c\" title \"f_c held "
		"(ZOH)\", spring(x) with lines lw 2 lc rgb \"black\" title \"ideal spring K_e x\"\n",
		lg->name, s->env_stiffness_Npm, s->env_position_m, lg->has_x_true ? "true" : "measured", x,
		x);
	reset(f);
	fputs("  set lmargin at screen 0.51\n  set rmargin at screen 0.84\n  set key inside top left\n"
	      "  set xlabel \"measured position x (m)\"\n",
	      f);
	if (!lg->has_window[fig7_window] || isnan(lg->t_event_s[fig7_window])) {
		fputs("  set label 1 \"no Fig. 5 event in this log (give --zoom T)\" at graph 0.5, 0.5 "
		      "center\n  plot 0 with lines lc rgb \"gray\" notitle\n  unset label 1\n",
		      f);
		end(f);
		return;
	}
	/* the ticks k-3 .. k+3 around the event tick k, each point labelled */
	fprintf(f,
		"  set xtics %.9g\n  set format x \"%%.5f\"\n  set xtics rotate by 30 right\n"
		"  E = %d\n  near(i) = i >= E - 3 && i <= E + 3\n"
		"  set title \"Fig. 7: ticks k-3..k+3 at t(k) = %.4f s%s\"\n"
		"  plot data index 1 using (near($0) ? $2 : 1/0):7 with steps lw 2 lc rgb \"#2ca02c\" "
		"title \"f_c\", data index 1 using (near($0) ? $2 : 1/0):5 with steps lw 1 dt 2 lc rgb "
		"\"gray30\" title \"f_e\", data index 1 using (near($0) ? $2 : 1/0):7:(sprintf(\"%%+d\", "
		"int($0) - E)) with labels point pt 7 ps 0.7 offset 0.8,0.6 notitle, spring(x) with lines "
		"lw 1 lc rgb \"black\" title \"K_e x\"\n  unset title\n",
		s->enc_resolution_m, REPORT_ZOOM_TICKS, lg->t_event_s[fig7_window],
		fig7_window == RW_ZOOM ? " (--zoom)" : "");
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

int report_write_overlay(FILE *f, const report_log *logs, int n, const report_scales *sc)
{
	fputs("# popc-analyze report: the logs overlaid, on shared axes. Rerun here: gnuplot "
	      "variants.gp\n# paper_figure = 0 (the paper overlays no variants: Figs. 3, 14, 16 "
	      "side by side)\n"
	      "do for [out in \"png pdf\"] {\n",
	      f);
	terminal_block(f, "variants", "1000,1300", "7.5in,9.5in");
	fputs("  set multiplot layout 4,1 title \"variants overlaid on shared axes (the paper's "
	      "Figs. 3, 14 and 16 side by side)\"\n"
	      "  set grid\n"
	      "  set key outside right top vertical\n"
	      "  set lmargin at screen 0.1\n"
	      "  set rmargin at screen 0.76\n",
	      f);
	double xmin = (double)INFINITY, xmax = -(double)INFINITY, pad = 0.0;
	for (int i = 0; i < n; i++)
		if (!isnan(logs[i].t_contact_s)) {
			xmin = fmin(xmin, logs[i].x_contact_min_m);
			xmax = fmax(xmax, logs[i].x_contact_max_m);
			pad = fmax(pad, 3.0 * logs[i].sum.enc_resolution_m);
		}
	static const struct {
		int col;
		const char *label;
		int needs; /* 0 always, 1 W, 2 the PC force */
	} panels[4] = {{2, "position x (m)", 0},
		       {10, "W - E_ref (J)", 1},
		       {6, "PC force f_pc (N)", 2},
		       {7, "f_c (N)", 2}};
	for (int p = 0; p < 4; p++) {
		int any = 0;
		for (int i = 0; i < n; i++)
			any |= panels[p].needs == 0 ||
			       (panels[p].needs == 1 ? logs[i].sum.has_w : logs[i].sum.has_pc_force);
		fprintf(f, "  set ylabel \"%s\"\n  set xlabel \"%s\"\n", panels[p].label,
			p == 3 ? "t (s)" : "");
		if (!any) {
			fputs("  set yrange [-1:1]\n"
			      "  set label 1 \"n/a: no log has a PC force\" at graph 0.5, 0.5 center\n"
			      "  plot 0 with lines lc rgb \"gray\" notitle\n"
			      "  unset label 1\n"
			      "  set autoscale y\n",
			      f);
			continue;
		}
		if (p == 0 && xmin <= xmax)
			fprintf(f, "  set yrange [%.9g:%.9g] # x from the first contact\n", xmin - pad,
				xmax + pad);
		if (p == 2)
			f_pc_range(f, sc);
		if (p == 3)
			f_c_range(f, sc);
		fputs("  plot ", f);
		for (int i = 0, k = 0; i < n; i++) {
			const ana_summary *s = &logs[i].sum;
			if (panels[p].needs == 1 ? !s->has_w : panels[p].needs == 2 ? !s->has_pc_force : 0)
				continue;
			fprintf(f, "%s\"%s.dat\" using 1:%d with lines lw 1 title \"%s\"",
				k++ ? ", \\\n       " : "", logs[i].name, panels[p].col, logs[i].name);
		}
		fputs("\n  set autoscale y\n", f);
	}
	fputs("  unset multiplot\n  set output\n}\n", f);
	return ferror(f) ? -1 : 0;
}
