/* popc map's figure (map_figure.h): K against the first --vary axis (the wall
 * damping B by default), one line per variant and criterion at the first
 * failure with its bracket as error bars, the band where a line is
 * acceptable again above it (from the first failure to the band's top) as a
 * thick bar, and the Colgate-Schenkel line K = 2 (b - |B|) / T from
 * boundary.csv's k_colgate_schenkel_N_per_m column. */
#define _XOPEN_SOURCE 700
#include "map_figure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "popc/util/parse.h"

/* The unit of an x axis key, for its label. */
static const char *unit_of(const char *section, const char *key)
{
	if (strcmp(key, "damping") == 0)
		return "N s/m";
	if (strcmp(key, "stiffness") == 0)
		return "N/m";
	if (strcmp(key, "rate") == 0)
		return "Hz";
	if (strcmp(key, "resolution") == 0)
		return "m";
	if (strcmp(key, "mass") == 0)
		return "kg";
	if (strcmp(key, "delay_ticks") == 0 || strcmp(key, "jitter_ticks") == 0)
		return "periods";
	(void)section;
	return "";
}

int popc_map_figure_write(const popc_sweep_plan *p, const char *dir, const char *const *criteria,
			  int n_criteria, popc_error *err)
{
	char *buf = NULL;
	size_t n = 0;
	FILE *f = open_memstream(&buf, &n);
	if (!f)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	/* boundary.csv's columns, counted from 1 as gnuplot does */
	int n_ax = p->n_axes - 1;           /* variant and --vary axes */
	int c_crit = n_ax + 1, c_out = n_ax + 2, c_ok = n_ax + 3, c_bad = n_ax + 4;
	int c_last_ok = n_ax + 6, c_cs = n_ax + 10;
	int has_x = n_ax >= 2;
	/* x on a log scale when its values are positive and span two decades */
	int log_x = 0;
	if (has_x) {
		double lo = (double)INFINITY, hi = -(double)INFINITY;
		int positive = 1;
		for (int v = 0; v < p->axes[1].n_values; v++) {
			double d;
			if (popc_parse_double_text(p->axes[1].values[v], &d) != POPC_PARSE_OK)
				positive = 0;
			else {
				positive &= d > 0;
				lo = d < lo ? d : lo;
				hi = d > hi ? d : hi;
			}
		}
		log_x = positive && hi >= 100 * lo;
	}
	/* section.key: operator.damping and environment.damping are both "damping" */
	if (has_x)
		fprintf(f, "# popc map's figure: K against %s.%s per variant (boundary.csv)\n",
			p->axes[1].section, p->axes[1].key);
	else
		fputs("# popc map's figure: K against the variant per variant (boundary.csv)\n", f);
	fputs("set datafile separator ','\nset key below maxcols 4\nset logscale y\nset grid\n", f);
	/* every decade labelled (gnuplot skips some over a wide range), minor
	 * ticks at 2..9 times each */
	fputs("set format y '10^{%T}'\nset ytics 10\nset mytics 10\n", f);
	if (log_x)
		fputs("set logscale x\nset xtics 10\nset mxtics 10\n", f);
	if (has_x)
		fprintf(f, "set xlabel '%s.%s (%s)'\n", p->axes[1].section, p->axes[1].key,
			unit_of(p->axes[1].section, p->axes[1].key));
	else
		fputs("set xlabel 'variant (index)'\n", f);
	fputs("set ylabel 'environment.stiffness K (N/m)'\n", f);
	fputs("set title 'Stability map: the first failure per line, bar = bracket [K_{ok}, K_{bad}]; "
	      "thick bar = acceptable again above it, up to the band top'\n", f);
	/* plotted once for the range gnuplot chooses: over three decades or
	 * less, 2 and 5 times each decade are labelled too (a map from 140 to
	 * 2000 N/m has only the labels 10^2 and 10^3 otherwise), drawn again */
	fputs("set terminal pngcairo size 1100,700 enhanced font ',10'\nset output 'map.png'\n", f);
	fputs("plot \\\n", f);
	const char *first_variant = p->axes[0].values[0];
	/* one curve per variant (colour) and criterion (dash) */
	for (int v = 0; v < p->axes[0].n_values; v++) {
		const char *name = p->axes[0].values[v];
		char xv[64];
		snprintf(xv, sizeof xv, "%d", v);
		const char *x = has_x ? "column(2)" : xv;
		/* a teleoperation map's variants are teleop.tdpa's values */
		const char *what = strcmp(p->axes[0].section, "teleop") == 0 ? "PCs " : "";
		for (int c = 0; c < n_criteria; c++) {
			fprintf(f,
				"  'boundary.csv' every ::1 using (strcol(1) eq '%s' && strcol(%d) eq '%s' && "
				"(strcol(%d) eq 'bracket' || strcol(%d) eq 'not-monotonic') ? %s : NaN)"
				":%d:%d:%d with yerrorlines lc %d dt %d title '%s%s (%s)', \\\n",
				name, c_crit, criteria[c], c_out, c_out, x, c_ok, c_ok, c_bad, v + 1, c + 1,
				what, name, criteria[c]);
			/* the band: from the first failure up to the last acceptable K */
			fprintf(f,
				"  'boundary.csv' every ::1 using (strcol(1) eq '%s' && strcol(%d) eq '%s' && "
				"strcol(%d) eq 'not-monotonic' ? %s : NaN):%d:%d:%d with yerrorbars lc %d "
				"lw 5 pt 0 notitle, \\\n",
				name, c_crit, criteria[c], c_out, x, c_bad, c_bad, c_last_ok, v + 1);
		}
	}
	/* a teleoperation map has no such line (boundary.csv's cell is empty) */
	if (p->teleop)
		fputs("  NaN notitle\n", f);
	else
		fprintf(f,
			"  'boundary.csv' every ::1 using (strcol(1) eq '%s' && strcol(%d) eq '%s' && "
			"column(%d) > 0 ? %s : NaN):%d with lines lw 2 lc rgb 'black' dt 3 "
			"title 'Colgate-Schenkel: b > K T/2 + |B|'\n",
			first_variant, c_crit, criteria[0], c_cs, has_x ? "column(2)" : "0", c_cs);
	fputs("if (GPVAL_Y_MIN > 0 && GPVAL_Y_MAX <= 1000 * GPVAL_Y_MIN) {\n"
	      "  do for [d = -3:12] {\n"
	      "    set ytics add (sprintf('2\u00d710^{%d}', d) 2 * 10.0**d, "
	      "sprintf('5\u00d710^{%d}', d) 5 * 10.0**d)\n"
	      "  }\n"
	      "}\n",
	      f);
	fputs("set output 'map.png'\nreplot\n", f);
	fputs("set terminal pdfcairo size 11in,7in enhanced font ',10'\nset output 'map.pdf'\nreplot\n",
	      f);
	fputs("unset output\n", f);
	return popc_cli_commit_memstream(f, &buf, &n, dir, "map.gp", err);
}

int popc_map_figure_plot(const char *dir, popc_error *err)
{
	fflush(stdout);
	fflush(stderr);
	pid_t pid = fork();
	if (pid < 0)
		return popc_error_set(err, POPC_ERR_IO, "cannot start gnuplot");
	if (pid == 0) {
		/* gnuplot's warnings (a curve without points: a variant with no
		 * bracket) go to DIR/map.gp.log, not the map's stderr */
		if (chdir(dir) != 0 || !freopen("map.gp.log", "w", stderr))
			_exit(127);
		execlp("gnuplot", "gnuplot", "map.gp", (char *)NULL);
		_exit(127);
	}
	int ws;
	if (waitpid(pid, &ws, 0) < 0 || !WIFEXITED(ws) || WEXITSTATUS(ws) != 0)
		return popc_error_set(err, POPC_ERR_IO,
				      "gnuplot %s/map.gp failed (status %d, see map.gp.log); "
				      "boundary.csv and map.gp are written",
				      dir, WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
	return 0;
}
