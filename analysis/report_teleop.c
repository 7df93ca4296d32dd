/* popc-analyze report of a teleoperation log (docs/TELEOPERATION.md,
 * "Analysing a log"): one figure, NAME-teleop.png and .pdf, in the report's
 * style (envelope bands per bucket, the multiplot's title and parameter box):
 * (a) the master's and the slave's positions, (b) the master's force command
 * f_c against the force on the slave, -fs (equal when rendered exactly),
 * (c) the master port's energies E_in, E_out and the slave's E_in as
 * received, (d) the same at the slave, (e) the drift x - xs. The one-port
 * figures (the paper's) are not drawn for it. */
#include <math.h>
#include <string.h>

#include "report.h"

typedef struct tele_pass {
	ana_decimator d;
} tele_pass;

static void on_row(void *ctx, const ana_tele_row *row, const ana_tele_summary *s)
{
	(void)s;
	tele_pass *p = ctx;
	const double *c = row->c;
	double v[RT_COLS];
	v[RT_X] = c[ANA_TC_x];
	v[RT_XS] = c[ANA_TC_xs];
	v[RT_F_C] = c[ANA_TC_f_c];
	v[RT_NEG_FS] = -c[ANA_TC_fs];
	v[RT_EM_IN] = c[ANA_TC_Em_in];
	v[RT_EM_OUT] = c[ANA_TC_Em_out];
	v[RT_EM_RX] = c[ANA_TC_Em_rx];
	v[RT_ES_IN] = c[ANA_TC_Es_in];
	v[RT_ES_OUT] = c[ANA_TC_Es_out];
	v[RT_ES_RX] = c[ANA_TC_Es_rx];
	v[RT_DRIFT] = c[ANA_TC_x] - c[ANA_TC_xs];
	ana_decim_add(&p->d, c[ANA_TC_t], v);
}

/* One column's band (min to max per bucket) and its two edges; scale "*1e3"
 * draws metres in mm, "" as logged. */
static void band(FILE *f, int col, const char *scale, const char *rgb, const char *dash,
		 const char *title)
{
	const int mn = 2 + col, mx = 2 + RT_COLS + col;
	fprintf(f,
		"data using 1:($%d%s):($%d%s) with filledcurves fc rgb \"%s\" fs transparent solid "
		"0.25 noborder notitle, data using 1:($%d%s) with lines lw 1 dt %s lc rgb \"%s\" "
		"notitle, data using 1:($%d%s) with lines lw 1 dt %s lc rgb \"%s\" title \"%s\"",
		mn, scale, mx, scale, rgb, mn, scale, dash, rgb, mx, scale, dash, rgb, title);
}

static void panel(FILE *f, const char *title, const char *ylabel)
{
	fprintf(f, "  set title \"%s\" offset 0,-0.6\n  set ylabel \"%s\"\n  plot ", title, ylabel);
}

static void panel_end(FILE *f)
{
	fputs("\n  unset title\n", f);
}

int report_teleop_write(const report_out *ro, const report_log *lg, const ana_input_options *in,
			int points, popc_error *err)
{
	(void)in;
	const ana_summary *s = &lg->sum;
	const popc_scene *sc = &s->tele_scene;
	tele_pass p;
	if (ana_decim_init(&p.d, RT_COLS, points * 2) != 0) {
		popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
		fprintf(stderr, "popc-analyze report: out of memory\n");
		return -1;
	}
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	ana_tele_summary ts;
	int st = ana_tele_summarize(lg->path, sc, &cc, &ts, on_row, &p, err);
	if (st) {
		ana_decim_free(&p.d);
		ana_fail("report", st, err);
		return -1;
	}
	char file[300], path[1400], safe[1024];
	snprintf(file, sizeof file, "%s" REPORT_TELE_SUFFIX ".dat", lg->name);
	FILE *f = report_open(ro, file, path, sizeof path);
	if (!f) {
		ana_decim_free(&p.d);
		return -1;
	}
	report_safe_text(lg->path, safe, sizeof safe);
	fprintf(f, "# %s decimated: each column's min and max over buckets of %lld ticks, at a "
		   "bucket's first and last t\n# " REPORT_TELE_COLUMNS "\n",
		safe, p.d.width);
	int bad = report_close(f, path, ana_decim_write(&p.d, f) != 0) != 0;
	ana_decim_free(&p.d);
	if (bad)
		return -1;
	snprintf(file, sizeof file, "%s" REPORT_TELE_SUFFIX ".gp", lg->name);
	if (!(f = report_open(ro, file, path, sizeof path)))
		return -1;
	char name[300];
	snprintf(name, sizeof name, "%s" REPORT_TELE_SUFFIX, lg->name);
	const double t_end = ts.duration_s > 0.0 ? ts.duration_s : ts.period_s;
	fprintf(f,
		"# popc-analyze report: %s.png and .pdf. Rerun here: gnuplot %s.gp\n"
		"# log = %s (teleoperation, %s)\n"
		"# data columns: " REPORT_TELE_COLUMNS "\n"
		"do for [out in \"png pdf\"] {\n",
		name, name, safe, popc_teleop_architecture_names[sc->tele_arch]);
	report_terminal_block(f, name, "1000,1100", "7.5in,8in");
	fprintf(f,
		"  set multiplot layout 5,1 title \"teleoperation: positions, forces, energies per "
		"port, drift\\nlog %s (%s, PCs %s)\"\n"
		"  set grid\n"
		"  set key outside right top vertical\n"
		"  set lmargin at screen 0.1\n"
		"  set rmargin at screen 0.76\n"
		"  data = \"%s.dat\"\n"
		"  set xrange [%.9g:%.9g]\n"
		"  set xlabel \"t (s)\"\n",
		safe, popc_teleop_architecture_names[sc->tele_arch], ts.tdpa ? "on" : "off", name,
		lg->t_first_s, lg->t_first_s + t_end);
	panel(f, "(a) positions: master x, slave xs (band: min to max per bucket)", "position (mm)");
	band(f, RT_X, "*1e3", REPORT_BLUE, "1", "x (master)");
	fputs(", ", f);
	band(f, RT_XS, "*1e3", REPORT_RED, "2", "xs (slave)");
	panel_end(f);
	panel(f, "(b) forces: master command f_c, force on the slave -fs", "force (N)");
	band(f, RT_F_C, "", REPORT_BLUE, "1", "f_c (master)");
	fputs(", ", f);
	band(f, RT_NEG_FS, "", REPORT_RED, "2", "-fs (slave sensor)");
	panel_end(f);
	panel(f, "(c) master port energies", "energy (J)");
	band(f, RT_EM_IN, "", REPORT_BLUE, "1", "Em_in");
	fputs(", ", f);
	band(f, RT_EM_OUT, "", REPORT_RED, "1", "Em_out");
	fputs(", ", f);
	band(f, RT_EM_RX, "", REPORT_GREEN, "2", "Em_rx (slave E_in received)");
	panel_end(f);
	panel(f, "(d) slave port energies", "energy (J)");
	band(f, RT_ES_IN, "", REPORT_BLUE, "1", "Es_in");
	fputs(", ", f);
	band(f, RT_ES_OUT, "", REPORT_RED, "1", "Es_out");
	fputs(", ", f);
	band(f, RT_ES_RX, "", REPORT_GREEN, "2", "Es_rx (master E_in received)");
	panel_end(f);
	/* the parameter box below the last panel's key, clear of the others' */
	fprintf(f,
		"  set label 99 \"PCs %s\\ndelay %g s fwd, %g s bwd\\nK_e = %g N/m\\nT = %g s\\n"
		"bounds %g N, %g m/s\" at screen 0.99, 0.14 right front boxed\n",
		ts.tdpa ? "on" : "off", ts.fwd_delay_s, ts.bwd_delay_s, sc->env_stiffness_Npm,
		ts.period_s, sc->tele_master_bound_N, sc->tele_slave_bound_mps);
	panel(f, "(e) position drift x - xs", "drift (mm)");
	band(f, RT_DRIFT, "*1e3", REPORT_PURPLE, "1", "x - xs");
	panel_end(f);
	fputs("  unset multiplot\n  set output\n}\n", f);
	return report_close(f, path, 0);
}
