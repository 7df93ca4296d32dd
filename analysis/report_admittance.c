/* popc-analyze report of an admittance log (docs/ANALYSIS.md, "report"; docs/
 * ADMITTANCE.md): one figure, NAME-admittance.png and .pdf, in the report's
 * style (envelope bands per bucket, the multiplot's title and parameter box):
 * (a) the force reading f_meas, (b) the VE's velocity v_ve and the command
 * v = v_ve + v_pc, (c) the parallel PC's v_pc, (d) the observer's W, against
 * time. The series PC's figures (x, f_pc, f_c) are not drawn for it. */
#include <math.h>
#include <string.h>

#include "report.h"

void report_admittance_sample(ana_decimator *d, const ana_row *r)
{
	if (!r->has_adm)
		return;
	double v[RA_COLS];
	v[RA_F_MEAS] = r->adm_f_N;
	v[RA_V_VE] = r->adm_v_ve_mps;
	v[RA_V_PC] = r->adm_v_pc_mps;
	v[RA_V] = r->tick.v_mps;
	v[RA_W] = r->tick.W_J;
	ana_decim_add(d, r->tick.t_s, v);
}

/* One column's band (min to max per bucket) and its two edges, as
 * report_envelope draws them for NAME.dat. */
static void band(FILE *f, int col, const char *rgb, const char *dash, const char *title)
{
	const int mn = 2 + col, mx = 2 + RA_COLS + col;
	fprintf(f,
		"data using 1:%d:%d with filledcurves fc rgb \"%s\" fs transparent solid 0.25 "
		"noborder notitle, data using 1:%d with lines lw 1 dt %s lc rgb \"%s\" notitle, "
		"data using 1:%d with lines lw 1 dt %s lc rgb \"%s\" title \"%s\"",
		mn, mx, rgb, mn, dash, rgb, mx, dash, rgb, title);
}

static void panel(FILE *f, const char *title, const char *ylabel)
{
	fprintf(f, "  set title \"%s\" offset 0,-0.6\n  set ylabel \"%s\"\n  plot ", title, ylabel);
}

static void panel_end(FILE *f)
{
	fputs("\n  unset title\n  set autoscale y\n", f);
}

int report_admittance_write(const report_out *ro, const report_log *lg, const ana_decimator *d)
{
	const ana_summary *s = &lg->sum;
	char file[300], path[1400], safe[1024];
	snprintf(file, sizeof file, "%s" REPORT_ADM_SUFFIX ".dat", lg->name);
	FILE *f = report_open(ro, file, path, sizeof path);
	if (!f)
		return -1;
	report_safe_text(lg->path, safe, sizeof safe);
	fprintf(f, "# %s decimated: each column's min and max over buckets of %lld ticks, at a "
		   "bucket's first and last t\n# " REPORT_ADM_COLUMNS "\n",
		safe, d->width);
	if (report_close(f, path, ana_decim_write(d, f) != 0) != 0)
		return -1;
	snprintf(file, sizeof file, "%s" REPORT_ADM_SUFFIX ".gp", lg->name);
	if (!(f = report_open(ro, file, path, sizeof path)))
		return -1;
	char name[300];
	snprintf(name, sizeof name, "%s" REPORT_ADM_SUFFIX, lg->name);
	fprintf(f,
		"# popc-analyze report: %s.png and .pdf. Rerun here: gnuplot %s.gp\n"
		"# log = %s, variant %s (admittance)\n"
		"# data columns: " REPORT_ADM_COLUMNS "\n"
		"do for [out in \"png pdf\"] {\n",
		name, name, safe, lg->sum.variant);
	report_terminal_block(f, name, "1000,920", "7.5in,6.4in");
	fprintf(f,
		"  set multiplot layout 4,1 title \"admittance display: force reading, velocities, "
		"W\\nlog %s (variant %s)\"\n"
		"  set grid\n"
		"  set key outside right top vertical\n"
		"  set lmargin at screen 0.1\n"
		"  set rmargin at screen 0.76\n"
		"  set label 99 \"variant %s\\nr = %g N/count, m_v = %g kg\\nb_v = %g N s/m, "
		"K_e = %g N/m\\nT = %g s, v_pc bound = %g m/s\" at screen 0.99, 0.99 right front "
		"boxed\n"
		"  data = \"%s.dat\"\n"
		"  set xrange [%.9g:%.9g]\n"
		"  set xlabel \"t (s)\"\n",
		safe, s->variant, s->variant, s->adm_force_resolution_N, s->adm_virtual_mass_kg,
		s->adm_virtual_damping_Nspm, s->env_stiffness_Npm, s->period_s,
		s->adm_pc_velocity_bound_mps, name, lg->t_first_s, lg->t_last_s);
	panel(f, "(a) force reading f_meas = count x resolution (band: min to max per bucket)",
	      "force (N)");
	band(f, RA_F_MEAS, REPORT_BLUE, "1", "f_meas");
	panel_end(f);
	fputs("  unset label 99\n", f);
	panel(f, "(b) velocity of the VE and the command v = v_ve + v_pc", "velocity (m/s)");
	band(f, RA_V_VE, REPORT_GREEN, "2", "v_ve (VE)");
	fputs(", ", f);
	band(f, RA_V, REPORT_PURPLE, "1", "v (command)");
	panel_end(f);
	panel(f, "(c) the parallel PC's velocity v_pc = beta f", "v_pc (m/s)");
	band(f, RA_V_PC, REPORT_RED, "1", "v_pc");
	panel_end(f);
	panel(f, "(d) energy observed at the port", "energy (J)");
	band(f, RA_W, REPORT_BLUE, "1", "W (PO)");
	panel_end(f);
	fputs("  unset multiplot\n  set output\n}\n", f);
	return report_close(f, path, 0);
}
