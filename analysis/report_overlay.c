/* The report's overlay (variants.gp): every log on shared axes, each in its
 * own colour of the Okabe-Ito palette (strong, told apart with any colour
 * vision), each panel drawing the log with the widest band first so that a
 * small signal is drawn over a large one and not hidden under it; a PC force
 * too small for the shared axis (report_own_f_pc_N) goes on the right axis at
 * a scale its title states. */
#include <math.h>
#include <stdlib.h>

#include "report.h"

static const char *const palette[] = {REPORT_BLUE,   REPORT_RED,   REPORT_GREEN, REPORT_PURPLE,
				      REPORT_ORANGE, REPORT_SKY,   "#000000"};
#define N_PALETTE (int)(sizeof palette / sizeof palette[0])

/* The draw order of one panel: the logs by the span of column col over the
 * whole log, widest first (ties: in the order given). */
static void draw_order(const report_log *logs, int n, int col, int *order)
{
	for (int i = 0; i < n; i++)
		order[i] = i;
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0; j--) {
			const report_log *a = &logs[order[j - 1]], *b = &logs[order[j]];
			double sa = a->col_max[col] - a->col_min[col];
			double sb = b->col_max[col] - b->col_min[col];
			sa = isnan(sa) ? -1.0 : sa;
			sb = isnan(sb) ? -1.0 : sb;
			if (sa > sb || (sa == sb && order[j - 1] < order[j]))
				break;
			int t = order[j - 1];
			order[j - 1] = order[j];
			order[j] = t;
		}
}

int report_write_overlay(FILE *f, const report_log *logs, int n, const report_scales *sc)
{
	int *order = malloc((size_t)n * sizeof *order);
	if (!order)
		return -1;
	fputs("# popc-analyze report: the logs overlaid, on shared axes. Rerun here: gnuplot "
	      "variants.gp\n# paper_figure = 0 (the paper overlays no variants: Figs. 3, 14, 16 "
	      "side by side)\n# data columns: " REPORT_ENV_COLUMNS "\n"
	      "do for [out in \"png pdf\"] {\n",
	      f);
	report_terminal_block(f, "variants", "1000,1400", "7.5in,10.2in");
	fputs("  set multiplot layout 4,1 title \"variants overlaid on shared axes (the paper's "
	      "Figs. 3, 14 and 16 side by side); band: min to max per bucket\"\n"
	      "  set grid\n"
	      "  set key outside right top vertical\n"
	      "  set lmargin at screen 0.1\n"
	      "  set rmargin at screen 0.72\n",
	      f);
	/* the small PC forces' right axis: the largest of their own scales;
	 * time from the first log's first tick to the last one's last */
	double own = 0.0, t0 = (double)INFINITY, t1 = -(double)INFINITY;
	for (int i = 0; i < n; i++) {
		own = fmax(own, report_own_f_pc_N(&logs[i], sc));
		t0 = fmin(t0, logs[i].t_first_s);
		t1 = fmax(t1, logs[i].t_last_s);
	}
	if (t0 < t1)
		fprintf(f, "  set xrange [%.9g:%.9g]\n", t0, t1);
	static const struct {
		int col;
		const char *label, *title, *unit;
		int needs; /* 0 always, 1 W, 2 the PC force */
	} panels[4] = {{D_X, "position x (mm)", "(a) position, whole log", "*1e3", 0},
		       {D_WME, "W - E_ref (J)", "(b) W - E_ref", "", 1},
		       {D_F_PC, "PC force f_pc (N)", "(c) PC force", "", 2},
		       {D_F_C, "f_c (N)", "(d) f_c", "", 2}};
	for (int p = 0; p < 4; p++) {
		int any = 0;
		for (int i = 0; i < n; i++)
			any |= panels[p].needs == 0 ||
			       (panels[p].needs == 1 ? logs[i].sum.has_w : logs[i].sum.has_pc_force);
		fprintf(f,
			"  set title \" \"\n  set label 98 \"%s\" at graph 0, graph 1 offset 0,0.9 "
			"left front\n  set ylabel \"%s\"\n  set xlabel \"%s\"\n",
			panels[p].title, panels[p].label, p == 3 ? "t (s)" : "");
		if (!any) {
			fputs("  set yrange [-1:1]\n"
			      "  set label 1 \"n/a: no log has a PC force\" at graph 0.5, 0.5 center\n"
			      "  plot 0 with lines lc rgb \"gray\" notitle\n"
			      "  unset label 1\n"
			      "  set autoscale y\n",
			      f);
			continue;
		}
		const int right = p == 2 && own > 0.0;
		if (p == 2)
			fprintf(f, "  set yrange [%.6g:%.6g] # shared f_pc scale\n", -sc->f_pc_N,
				sc->f_pc_N);
		if (p == 3)
			fprintf(f, "  set yrange [%.6g:%.6g] # shared f_c scale\n", sc->f_c_min_N,
				sc->f_c_max_N);
		if (right)
			fprintf(f,
				"  set y2range [%.6g:%.6g] # the small PC forces' own scale\n"
				"  set y2tics\n  set ytics nomirror\n"
				"  set y2label \"small f_pc (N), right axis\"\n",
				-own, own);
		draw_order(logs, n, panels[p].col, order);
		fputs("  plot ", f);
		for (int k = 0, m = 0; k < n; k++) {
			const int i = order[k];
			const ana_summary *s = &logs[i].sum;
			if (panels[p].needs == 1 ? !s->has_w : panels[p].needs == 2 ? !s->has_pc_force : 0)
				continue;
			char data[300], title[400];
			snprintf(data, sizeof data, "\"%s.dat\"", logs[i].name);
			const int small = right && report_own_f_pc_N(&logs[i], sc) > 0.0;
			snprintf(title, sizeof title, "%s%s", logs[i].name,
				 small ? " (right axis)" : "");
			fputs(m++ ? ", \\\n       " : "", f);
			report_envelope(f, data, panels[p].col, panels[p].unit,
					palette[i % N_PALETTE], "1", title, small ? "x1y2" : "x1y1");
		}
		fputs("\n  set autoscale y\n", f);
		if (right)
			fputs("  unset y2tics\n  unset y2label\n  set ytics mirror\n", f);
		fputs("  unset title\n  unset label 98\n", f);
	}
	fputs("  unset multiplot\n  set output\n}\n", f);
	free(order);
	return ferror(f) ? -1 : 0;
}
