/* popc map SCENE --variant V... [--vary KEY=LIST...] -o DIR [options]
 *
 * A stability map (docs/MAPS.md): for every variant and every value of the
 * other axes, the first wall stiffness K whose run is not acceptable, and
 * the last acceptable K above it where the line folds, by a coarse scan of
 * log K and bisection (popc/sweep/sweep_map.h). The map is a sweep whose last
 * axis is a log grid of K (sweep_plan.h); it runs only the points the search
 * asks for, step by step: each step's runs are one batch for the sweep's
 * worker pool (-j), its shards and its resumption. The figure is written by
 * map_figure.c. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "map_figure.h"
#include "popc/axes/axis.h"
#include "popc/programs/env.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_lock.h"
#include "popc/sweep/sweep_map.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/sweep/sweep_results.h"
#include "popc/util/numfmt.h"
#include "popc/util/parse.h"
#include "sweep_dry_run.h"
#include "sweep_pool.h"
#include "sweep_progress.h"

static void usage(FILE *f)
{
	fputs("usage: popc map SCENE --variant V[,V...] [--vary section.key=LIST ...] -o DIR [options]\n"
	      "\n"
	      "For every variant and every value of the --vary axes (a line), finds the\n"
	      "first wall stiffness environment.stiffness at which the run is not\n"
	      "acceptable: a scan of every --scan-th point of a log grid whose neighbours\n"
	      "differ by at most --tol, then bisection between the last acceptable scan\n"
	      "point and the first unacceptable one. Where the line is acceptable again\n"
	      "above that, the band's top (the last acceptable K) is bisected too.\n"
	      "Writes DIR/boundary.csv (one row per line and criterion), DIR/map.gp and\n"
	      "DIR/map.png, DIR/map.pdf (gnuplot), and a table on stdout. Every run's row is\n"
	      "kept as in popc sweep (DIR/rows/); running the same map again resumes it.\n"
	      "\n"
	      "  --variant V[,V...]       controller variants (repeatable; admittance.variant\n"
	      "                           on an admittance scene, teleop.tdpa (off, on) on a\n"
	      "                           teleoperation scene)\n"
	      "  --vary section.key=LIST  another axis of the map (repeatable), e.g.\n"
	      "                           --vary environment.damping=0:0.75:16\n"
	      "  --set section.key=value  a fixed override of the scene (repeatable)\n"
	      "  --stiffness LO:HI        the K range, N/m (default 1e2:1e6)\n"
	      "  --tol R                  relative width of the bracket (default 0.02)\n"
	      "  --scan N                 grid steps between scan points (default 16: a\n"
	      "                           factor 1.37 at 2 %); a fold narrower than that\n"
	      "                           may go unseen\n"
	      "  --criterion C[,C...]     diverged, limit-cycle, chatter, passive,\n"
	      "                           device-passive, stable (default passive; diverged\n"
	      "                           on an admittance scene; stable, completed and\n"
	      "                           settled, on a teleoperation scene, its only one\n"
	      "                           with diverged); one boundary per criterion\n"
	      "  --port-tol J             passive: E_port never below -J; device-passive:\n"
	      "                           E_dev = E_port + the plant's damping's dissipation\n"
	      "                           never below -J (default 1e-6 J)\n"
	      "  -o, --output DIR         the map directory (created if needed)\n"
	      "  -j, --jobs N             parallel runs (default: SLURM_CPUS_PER_TASK, else\n"
	      "                           every online core). -j N makes runs in this\n"
	      "                           process beside N - 1 worker processes; if one\n"
	      "                           crashes it, the rows so far are kept, the workers\n"
	      "                           stopped, and popc goes on as with --isolate\n"
	      "  --isolate                make the runs in N worker processes only\n"
	      "  --shard I/N              make only shard I of N's runs (as popc sweep; the\n"
	      "                           shards share DIR). Runs until nothing of its shard\n"
	      "                           is pending, then exits; run every shard again until\n"
	      "                           DIR/boundary.csv exists (docs/MAPS.md)\n"
	      "  --keep-log               keep every run's log.csv (default: rows only)\n"
	      "  --allow-other-build      resume a map that another popc build made\n"
	      "  --dry-run                print the map's grid, scan and lines (one\n"
	      "                           'LINE<TAB>values' each) and what DIR holds, and\n"
	      "                           write nothing: no DIR, plan, lock or row\n"
	      "  -q, --quiet              no progress\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done (or this shard's part done), 1 a run failed without a\n"
	      "verdict (the same command again makes it again), 2 bad scene or usage,\n"
	      "5 interrupted (finished runs kept).\n",
	      f);
}

enum { OPT_VARIANT = 256, OPT_VARY, OPT_SET, OPT_STIFFNESS, OPT_TOL, OPT_CRITERION, OPT_PORT_TOL,
       OPT_SHARD, OPT_KEEP_LOG, OPT_ALLOW_OTHER_BUILD, OPT_ISOLATE, OPT_SCAN, OPT_DRY_RUN };

static const popc_option map_options[] = {
	{"variant", 0, OPT_VARIANT, "VARIANT"},
	{"vary", 0, OPT_VARY, "KEY=LIST"},
	{"set", 0, OPT_SET, "KEY=VALUE"},
	{"stiffness", 0, OPT_STIFFNESS, "LO:HI"},
	{"tol", 0, OPT_TOL, "R"},
	{"scan", 0, OPT_SCAN, "N"},
	/* popc_map_criterion_name's names (sweep_map.c), a comma list */
	{"criterion", 0, OPT_CRITERION, "diverged|limit-cycle|chatter|passive|device-passive|stable"},
	{"port-tol", 0, OPT_PORT_TOL, "J"},
	{"output", 'o', 'o', "DIR"},
	{"jobs", 'j', 'j', "N"},
	{"isolate", 0, OPT_ISOLATE, NULL},
	{"shard", 0, OPT_SHARD, "I/N"},
	{"keep-log", 0, OPT_KEEP_LOG, NULL},
	{"allow-other-build", 0, OPT_ALLOW_OTHER_BUILD, NULL},
	{"dry-run", 0, OPT_DRY_RUN, NULL},
	{"quiet", 'q', 'q', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const popc_cli_map_opts[] = {map_options, NULL};

typedef struct map_args {
	char **variants, **vary, **sets;
	int n_variants, n_vary, n_sets;
	const char *scene_path, *dir, *shard_text, *stiffness;
	double tol, port_tol_J;
	unsigned criteria;
	int criteria_given; /* --criterion given: else passive, or diverged on an admittance scene */
	long long jobs, scan_steps;
	int quiet, keep_log, allow_other_build, isolate, dry_run;
} map_args;

/* The searches of every line and criterion, from the rows in DIR. */
typedef struct map_state {
	long n_k, scan_steps, n_scan, n_lines;
	int n_crit;
	popc_map_criterion crit[POPC_MAP_N_CRITERIA];
	popc_map_search *search;        /* n_lines * n_crit */
	long *need;                     /* n_scan: the needs of one search */
	unsigned char *asked;           /* n_k: a line's points already in todo */
	unsigned char *made_now;        /* per run: made by this invocation */
	long *line_runs;                /* runs with a row, per line */
	popc_sweep_results res;
	int have_res;
	long long *todo;                /* needed runs of the shard without a row */
	long long n_todo, n_pending_other, n_needed;
} map_state;

static void state_release(map_state *m)
{
	if (m->have_res)
		popc_sweep_results_free(&m->res);
	m->have_res = 0;
}

/* Everything the state holds, on every way out of map_main. */
static void state_free(map_state *m)
{
	state_release(m);
	free(m->search);
	free(m->line_runs);
	free(m->need);
	free(m->asked);
	free(m->made_now);
	free(m->todo);
}

/* Reads the rows and replays every search; fills todo with the shard's
 * runs that some search needs and that have no row yet. A run whose row
 * says it failed without a verdict (exit status other than 0 and 6: a
 * worker killed, a run that could not start) counts as not made unless this
 * invocation made it: a map run again makes it again, as a sweep does
 * (docs/SWEEPS.md), and within one invocation it stops its line. */
static int evaluate(map_state *m, const popc_sweep_plan *p, const char *dir,
		    const popc_sweep_shard *shard, double port_tol_J, popc_error *err)
{
	state_release(m);
	const char *dirs[1] = {dir};
	int st = popc_sweep_results_load(&m->res, p, dirs, 1, 0, err);
	if (st)
		return st;
	m->have_res = 1;
	unsigned char *v = malloc((size_t)m->n_k * POPC_MAP_N_CRITERIA);
	if (!v)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	m->n_todo = m->n_pending_other = m->n_needed = 0;
	for (long line = 0; line < m->n_lines && !st; line++) {
		m->line_runs[line] = 0;
		memset(v, POPC_MAP_UNKNOWN, (size_t)m->n_k * POPC_MAP_N_CRITERIA);
		for (long k = 0; k < m->n_k && !st; k++) {
			const popc_sweep_result_entry *e = &m->res.run[line * m->n_k + k];
			if (!e->row)
				continue;
			popc_map_facts f;
			if ((st = popc_map_facts_from_row(p, e->row, &f, err)) != 0)
				break;
			if (f.exit_status != 0 && f.exit_status != 6 && !m->made_now[line * m->n_k + k])
				continue;
			m->line_runs[line]++;
			for (int c = 0; c < m->n_crit; c++)
				v[(size_t)c * (size_t)m->n_k + (size_t)k] = (unsigned char)popc_map_verdict_of(m->crit[c], &f, port_tol_J);
		}
		memset(m->asked, 0, (size_t)m->n_k);
		for (int c = 0; c < m->n_crit && !st; c++) {
			popc_map_search *s = &m->search[line * m->n_crit + c];
			popc_map_search_line(v + (size_t)c * (size_t)m->n_k, m->n_k, m->scan_steps, m->need,
					     s);
			for (int q = 0; q < s->n_need; q++) {
				long long i = line * m->n_k + s->need[q];
				/* two criteria may need the same run */
				if (m->asked[s->need[q]])
					continue;
				m->asked[s->need[q]] = 1;
				m->n_needed++;
				if (!popc_sweep_in_shard(shard, i))
					m->n_pending_other++;
				else
					m->todo[m->n_todo++] = i;
			}
		}
	}
	free(v);
	return st;
}

static const char *outcome_name(popc_map_outcome o)
{
	switch (o) {
	case POPC_MAP_NEEDS_RUNS: return "pending";
	case POPC_MAP_BRACKET: return "bracket";
	case POPC_MAP_ALL_OK: return "above-range";
	case POPC_MAP_NONE_OK: return "below-range";
	case POPC_MAP_NOT_MONOTONIC: return "not-monotonic";
	case POPC_MAP_UNDECIDED_RUN: return "undecided";
	}
	return "?";
}

/* K of grid point k, as the plan's last axis writes it. */
static double k_of(const popc_sweep_plan *p, long k)
{
	double d = (double)NAN;
	popc_parse_double_text(p->axes[p->n_axes - 1].values[k], &d);
	return d;
}

static void put_double(FILE *f, double d)
{
	char b[64];
	popc_format_double(d, b);
	fputs(b, f);
}

/* A metric of run i's row (empty when it has none). */
static void put_cell(FILE *f, const map_state *m, const popc_sweep_plan *p, long long i,
		     const char *name)
{
	const char *cell;
	size_t len;
	if (i >= 0 && m->res.run[i].row && popc_map_row_cell(p, m->res.run[i].row, name, &cell, &len) == 0)
		fwrite(cell, 1, len, f);
}

/* The reference line of a line's scene (docs/MAPS.md):
 * - impedance, Colgate and Schenkel: passive when b > K T / 2 + |B|, b the
 *   device side's damping, so K < 2 (b - |B|) / T;
 * - admittance, its dual: the sampled VE m_v a + b_v v + K x_v + B v = f
 *   (semi-implicit Euler, the environment at the state before the step,
 *   docs/ADMITTANCE.md "The admittance map") is stable when
 *   m_v = 0: K < 2 (b_v - B) / T (the virtual damper b_v in the place of
 *   the device's b); m_v > 0: K < (4 m_v - 2 (b_v + B) T) / T^2 (Jury's
 *   test on its 2 x 2 step). A value <= 0 means no K is. */
static double line_condition_Npm(const popc_scene *s)
{
	/* a teleoperation line: no such line is derived here (an empty cell) */
	if (s->tele_arch != POPC_TELEOP_OFF)
		return (double)NAN;
	double T = popc_scene_period_s(s);
	double B = fabs(s->env_damping_Nspm);
	if (s->causality == POPC_CAUSALITY_ADMITTANCE) {
		double m = s->adm_virtual_mass_kg, b = s->adm_virtual_damping_Nspm;
		if (m > 0.0)
			return (4.0 * m - 2.0 * (b + B) * T) / (T * T);
		return 2.0 * (b - B) / T;
	}
	double b = s->op_damping_Nspm + s->dev_damping_Nspm;
	return 2.0 * (b - B) / T;
}

/* DIR/boundary.csv: one row per line and criterion. */
static int write_boundary(const map_state *m, const popc_sweep_plan *p, const char *dir,
			  popc_error *err)
{
	char *buf = NULL;
	size_t n = 0;
	FILE *f = open_memstream(&buf, &n);
	if (!f)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	for (int a = 0; a < p->n_axes - 1; a++)
		fprintf(f, "%s.%s,", p->axes[a].section, p->axes[a].key);
	fputs("criterion,outcome,k_ok_N_per_m,k_bad_N_per_m,width,k_last_ok_N_per_m,"
	      "k_last_bad_N_per_m,runs,line_runs,k_colgate_schenkel_N_per_m,pc_energy_J,pc_rms_N,"
	      "chatter_s,port_energy_min_J,device_energy_min_J,run_ok,run_bad,note\n", f);
	int *vi = malloc((size_t)p->n_axes * sizeof *vi);
	if (!vi) {
		fclose(f);
		free(buf);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	for (long line = 0; line < m->n_lines; line++) {
		long long first = line * m->n_k;
		popc_sweep_run_values(p, first, vi);
		popc_scene s;
		popc_error serr;
		double k_cs = (double)NAN;
		if (popc_sweep_run_scene(p, first, &s, &serr) == 0)
			k_cs = line_condition_Npm(&s);
		for (int c = 0; c < m->n_crit; c++) {
			const popc_map_search *se = &m->search[line * m->n_crit + c];
			for (int a = 0; a < p->n_axes - 1; a++)
				fprintf(f, "%s,", p->axes[a].values[vi[a]]);
			fprintf(f, "%s,%s,", popc_map_criterion_name(m->crit[c]), outcome_name(se->outcome));
			long ok = se->ok_index, bad = se->bad_index;
			if (ok >= 0)
				put_double(f, k_of(p, ok));
			fputc(',', f);
			if (bad >= 0)
				put_double(f, k_of(p, bad));
			fputc(',', f);
			if (ok >= 0 && bad >= 0)
				put_double(f, k_of(p, bad) / k_of(p, ok) - 1.0);
			fputc(',', f);
			if (se->last_ok_index >= 0)
				put_double(f, k_of(p, se->last_ok_index));
			fputc(',', f);
			if (se->last_bad_index >= 0)
				put_double(f, k_of(p, se->last_bad_index));
			fprintf(f, ",%ld,%ld,", se->runs, m->line_runs[line]);
			if (isfinite(k_cs))
				put_double(f, k_cs);
			fputc(',', f);
			long long i_ok = ok >= 0 ? first + ok : -1;
			put_cell(f, m, p, i_ok, "pc_energy");
			fputc(',', f);
			put_cell(f, m, p, i_ok, "pc_rms");
			fputc(',', f);
			put_cell(f, m, p, i_ok, "chatter_s");
			fputc(',', f);
			put_cell(f, m, p, i_ok, "port_energy_min");
			fputc(',', f);
			put_cell(f, m, p, i_ok, "device_energy_min");
			fputc(',', f);
			char id[POPC_SWEEP_ID_MAX];
			if (ok >= 0) {
				popc_sweep_run_id(p, first + ok, id);
				fputs(id, f);
			}
			fputc(',', f);
			if (bad >= 0) {
				popc_sweep_run_id(p, first + bad, id);
				fputs(id, f);
			}
			fputc(',', f);
			if (se->outcome == POPC_MAP_NOT_MONOTONIC)
				fprintf(f, "acceptable again above the first failure at K = %.6g up to "
					   "K = %.6g%s",
					k_of(p, bad), k_of(p, se->last_ok_index),
					se->last_bad_index < 0 ? " (the range's top)" : "");
			else if (se->outcome == POPC_MAP_UNDECIDED_RUN) {
				popc_sweep_run_id(p, first + se->culprit, id);
				fprintf(f, "run %s at K = %.6g failed or lacks the criterion's cell", id,
					k_of(p, se->culprit));
			}
			fputc('\n', f);
		}
	}
	free(vi);
	return popc_cli_commit_memstream(f, &buf, &n, dir, "boundary.csv", err);
}

/* The short table on stdout. */
static void print_table(const map_state *m, const popc_sweep_plan *p)
{
	int *vi = malloc((size_t)p->n_axes * sizeof *vi);
	if (!vi)
		return;
	/* a --vary axis' heading: its key, or section.key where another axis
	 * has the same key (operator.damping and environment.damping are both
	 * "damping"); a column as wide as its heading, at least 12 */
	char head[POPC_SWEEP_AXES_MAX][130];
	int width[POPC_SWEEP_AXES_MAX];
	for (int a = 1; a < p->n_axes - 1 && a < POPC_SWEEP_AXES_MAX; a++) {
		int shared = 0;
		for (int b = 1; b < p->n_axes - 1; b++)
			shared |= b != a && strcmp(p->axes[a].key, p->axes[b].key) == 0;
		if (shared)
			snprintf(head[a], sizeof head[a], "%s.%s", p->axes[a].section, p->axes[a].key);
		else
			snprintf(head[a], sizeof head[a], "%s", p->axes[a].key);
		int len = (int)strlen(head[a]);
		width[a] = len > 12 ? len : 12;
	}
	printf("%-16s", "variant");
	for (int a = 1; a < p->n_axes - 1; a++)
		printf(" %-*.*s", width[a], width[a], head[a]);
	printf(" %-12s %-13s %12s %12s %5s\n", "criterion", "outcome", "K_ok N/m", "K_bad N/m", "runs");
	for (long line = 0; line < m->n_lines; line++) {
		popc_sweep_run_values(p, line * m->n_k, vi);
		for (int c = 0; c < m->n_crit; c++) {
			const popc_map_search *se = &m->search[line * m->n_crit + c];
			printf("%-16s", p->axes[0].values[vi[0]]);
			for (int a = 1; a < p->n_axes - 1; a++)
				printf(" %-*.*s", width[a], width[a], p->axes[a].values[vi[a]]);
			printf(" %-12s %-13s", popc_map_criterion_name(m->crit[c]), outcome_name(se->outcome));
			long ok = se->ok_index, bad = se->bad_index;
			if (ok >= 0)
				printf(" %12.5g", k_of(p, ok));
			else
				printf(" %12s", "-");
			if (bad >= 0)
				printf(" %12.5g", k_of(p, bad));
			else
				printf(" %12s", "-");
			printf(" %5ld\n", se->runs);
		}
	}
	free(vi);
}

/* Builds the map's plan: variants, the --vary axes, then the K grid. */
static int make_plan(map_args *a, popc_sweep_plan *plan, popc_error *err)
{
	popc_scene base;
	int st = popc_env_scene_defaults(&base, err);
	if (!st)
		st = popc_scene_load(&base, a->scene_path, err);
	for (int m = 0; m < a->n_sets && !st; m++) {
		if (popc_cli_set_names_key(a->sets[m], "environment", "stiffness") ||
		    popc_cli_set_names_key(a->sets[m], "controller", "variant") ||
		    popc_cli_set_names_key(a->sets[m], "admittance", "variant") ||
		    popc_cli_set_names_key(a->sets[m], "teleop", "tdpa"))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "--set %s: the map varies this key itself (--stiffness, "
					      "--variant)",
					      a->sets[m]);
		st = popc_scene_set_assignment(&base, a->sets[m], err);
	}
	if (st)
		return st;
	/* an admittance run logs no true port energy E_port nor the device's
	 * E_dev (docs/ADMITTANCE.md, "The log"): those criteria could only be
	 * undecided on every line */
	if (base.causality == POPC_CAUSALITY_ADMITTANCE && !a->criteria_given)
		a->criteria = 1u << POPC_MAP_DIVERGED;
	if (base.causality == POPC_CAUSALITY_ADMITTANCE &&
	    (a->criteria & (1u << POPC_MAP_PASSIVE | 1u << POPC_MAP_DEVICE_PASSIVE))) {
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--criterion %s: %s is an admittance scene (device.causality = "
				      "admittance), whose runs have no port energy E_port or E_dev; "
				      "use diverged, limit-cycle or chatter (docs/MAPS.md, \"The "
				      "admittance display\")",
				      a->criteria & (1u << POPC_MAP_PASSIVE) ? "passive" : "device-passive",
				      a->scene_path);
	}
	/* a teleoperation scene (docs/MAPS.md, "Teleoperation: stiffness against
	 * delay"): --variant names teleop.tdpa, the PCs off or on; its runs have
	 * the tele_* verdict, stable; the master's E_port and E_dev are not in
	 * their summary, and limit-cycle and chatter would judge the master's
	 * log columns alone */
	const int teleop = base.tele_arch != POPC_TELEOP_OFF;
	if (teleop && !a->criteria_given)
		a->criteria = 1u << POPC_MAP_STABLE;
	if (teleop && (a->criteria & ~(1u << POPC_MAP_STABLE | 1u << POPC_MAP_DIVERGED)))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--criterion: %s is a teleoperation scene (teleop.architecture "
				      "= %s): its criteria are stable and diverged (docs/MAPS.md, "
				      "\"Teleoperation\")",
				      a->scene_path, popc_teleop_architecture_names[base.tele_arch]);
	if (!teleop && (a->criteria & (1u << POPC_MAP_STABLE)))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--criterion stable: %s is not a teleoperation scene "
				      "(teleop.architecture = off); stable judges a teleoperation run's "
				      "slave (docs/MAPS.md, \"Teleoperation\")",
				      a->scene_path);
	double k_lo = 1e2, k_hi = 1e6;
	if (a->stiffness) {
		const char *colon = strchr(a->stiffness, ':');
		if (!colon || popc_parse_double_span(a->stiffness, colon, &k_lo) != POPC_PARSE_OK ||
		    popc_parse_double_text(colon + 1, &k_hi) != POPC_PARSE_OK || !(k_lo > 0) ||
		    !(k_hi > k_lo))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "--stiffness '%s': LO:HI in N/m with 0 < LO < HI",
					      a->stiffness);
	}
	long n_k = popc_map_grid_points(k_lo, k_hi, a->tol);
	if (n_k < 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--stiffness %s with --tol %g: the grid would have more than %ld "
				      "points (log(HI / LO) / log(1 + R) + 1); narrow --stiffness or "
				      "raise --tol (in [1e-4, 1])",
				      a->stiffness ? a->stiffness : "1e2:1e6", a->tol, POPC_MAP_GRID_MAX);
	int n_axes = a->n_vary + 2;
	popc_sweep_axis *axes = calloc((size_t)n_axes, sizeof *axes);
	char spec[POPC_SWEEP_VALUE_MAX * 4];
	size_t used = 0;
	if (!axes)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	/* an admittance scene's controller is the parallel PC of [admittance]
	 * (docs/ADMITTANCE.md): --variant names its variants */
	const char *variant_key = teleop ? "teleop.tdpa="
				  : base.causality == POPC_CAUSALITY_ADMITTANCE ? "admittance.variant="
										: "controller.variant=";
	used += (size_t)snprintf(spec, sizeof spec, "%s", variant_key);
	for (int v = 0; v < a->n_variants && used < sizeof spec; v++)
		used += (size_t)snprintf(spec + used, sizeof spec - used, "%s%s", v ? "," : "", a->variants[v]);
	st = popc_sweep_axis_parse(spec, &axes[0], err);
	for (int k = 0; k < a->n_vary && !st; k++) {
		st = popc_sweep_axis_parse(a->vary[k], &axes[k + 1], err);
		if (!st && ((strcmp(axes[k + 1].section, "environment") == 0 &&
			     strcmp(axes[k + 1].key, "stiffness") == 0) ||
			    (strcmp(axes[k + 1].section, "controller") == 0 &&
			     strcmp(axes[k + 1].key, "variant") == 0) ||
			    (strcmp(axes[k + 1].section, "admittance") == 0 &&
			     strcmp(axes[k + 1].key, "variant") == 0) ||
			    (strcmp(axes[k + 1].section, "teleop") == 0 &&
			     strcmp(axes[k + 1].key, "tdpa") == 0)))
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "--vary %s: the map varies this key itself (--stiffness, "
					    "--variant)",
					    a->vary[k]);
		for (int m = 0; m < a->n_sets && !st; m++)
			if (popc_cli_set_names_key(a->sets[m], axes[k + 1].section, axes[k + 1].key))
				st = popc_error_set(err, POPC_ERR_INVALID,
						    "--set %s and --vary %s: the key is both fixed and "
						    "varied; give it once",
						    a->sets[m], a->vary[k]);
	}
	if (!st) {
		snprintf(spec, sizeof spec, "environment.stiffness=%.17g:%.17g:%ld:log", k_lo, k_hi, n_k);
		st = popc_sweep_axis_parse(spec, &axes[n_axes - 1], err);
	}
	if (st) {
		for (int k = 0; k < n_axes; k++)
			popc_sweep_axis_free(&axes[k]);
		free(axes);
		return st;
	}
	/* every run's scene is checked when it is made; here the lines' ends,
	 * and that they run on the simulated axis: the runs share no drive,
	 * so a real axis is refused before any run, as popc sweep does */
	st = popc_sweep_plan_init(plan, &base, axes, n_axes, 0, err);
	for (long long i = 0; !st && i < plan->n_runs; i += n_k) {
		popc_scene s;
		st = popc_sweep_run_scene(plan, i, &s, err);
		if (!st)
			st = popc_sweep_run_scene(plan, i + n_k - 1, &s, err);
		if (!st && !popc_axis_is_simulated(&s))
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "axis.kind = %s: a map runs the simulated axis only "
					    "(drive a real axis with popc run)",
					    s.axis);
	}
	if (!st)
		popc_sweep_plan_set_build(plan, popc_cli_version(), popc_cli_build_id());
	return st;
}

/* --dry-run: the grid, the scan, the criteria and the lines on stdout (what
 * the map would search), what DIR holds; nothing written. Returns the exit
 * code: 2 when DIR holds another sweep (the map would be refused). */
static int dry_run(const map_args *a, const popc_sweep_plan *p, const popc_sweep_shard *sh)
{
	const popc_sweep_axis *kax = &p->axes[p->n_axes - 1];
	long n_k = kax->n_values;
	long scan = a->scan_steps < n_k - 1 ? (long)a->scan_steps : n_k - 1;
	long n_lines = (long)(p->n_runs / n_k);
	printf("# popc map --dry-run: %ld lines x %ld stiffness points (%s to %s N/m, log grid, "
	       "neighbours within %g); a scan of %ld points a line (every %ld-th), then bisection "
	       "to one grid step; criteria",
	       n_lines, n_k, kax->values[0], kax->values[n_k - 1], a->tol,
	       popc_map_scan_points(n_k, scan), scan);
	for (int c = 0; c < POPC_MAP_N_CRITERIA; c++)
		if (a->criteria & (1u << c))
			printf(" %s", popc_map_criterion_name((popc_map_criterion)c));
	if (sh->count > 1)
		printf("; shard %lld of %lld", sh->index + 1, sh->count);
	printf("; ");
	int refused = sweep_dry_run_dir(stdout, p, a->dir);
	printf("; nothing written\n");
	char values[4096];
	for (long line = 0; line < n_lines; line++) {
		/* the line's values: its first run's, less the stiffness (the last axis) */
		popc_sweep_run_describe(p, (long long)line * n_k, values, sizeof values);
		char *k = strstr(values, " environment.stiffness=");
		if (k)
			*k = '\0';
		printf("%ld\t%s\n", line, values);
	}
	if (fflush(stdout) != 0 || ferror(stdout))
		return POPC_EXIT_RUN_FAILED;
	return refused ? POPC_EXIT_USAGE : POPC_EXIT_OK;
}

static int map_main(map_args *a)
{
	popc_error err;
	popc_sweep_plan plan;
	memset(&plan, 0, sizeof plan);
	/* an unusable -o is bad usage, said before any work (as popc sweep) */
	int st = popc_sweep_output_dir_check("-o", a->dir, &err);
	if (st)
		return popc_cli_fail("map", st, &err);
	st = make_plan(a, &plan, &err);
	if (st) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("map", st, &err);
	}
	popc_sweep_shard shard;
	st = sweep_pool_shard(a->shard_text, &shard, &err);
	if (st < 0) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("map", st, &err);
	}
	if (a->dry_run) {
		/* before the directory is opened: nothing is made, locked or written */
		int r = dry_run(a, &plan, &shard);
		popc_sweep_plan_free(&plan);
		return r;
	}
	char scene_abs[PATH_MAX];
	char *r = realpath(plan.base.source, NULL);
	snprintf(scene_abs, sizeof scene_abs, "%s", r ? r : plan.base.source);
	free(r);
	st = popc_sweep_dir_open(&plan, a->dir, scene_abs, a->allow_other_build, &shard, &err);
	if (st < 0) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("map", st, &err);
	}
	map_state m = {0};
	int trouble = 0, step = 0;
	long long made = 0;
	popc_sweep_axis *kax = &plan.axes[plan.n_axes - 1];
	m.n_k = kax->n_values;
	m.scan_steps = a->scan_steps < m.n_k - 1 ? (long)a->scan_steps : m.n_k - 1;
	m.n_scan = popc_map_scan_points(m.n_k, m.scan_steps);
	m.n_lines = (long)(plan.n_runs / m.n_k);
	for (int c = 0; c < POPC_MAP_N_CRITERIA; c++)
		if (a->criteria & (1u << c))
			m.crit[m.n_crit++] = (popc_map_criterion)c;
	m.search = calloc((size_t)m.n_lines * (size_t)m.n_crit, sizeof *m.search);
	m.line_runs = calloc((size_t)m.n_lines, sizeof *m.line_runs);
	m.need = malloc((size_t)m.n_scan * sizeof *m.need);
	m.asked = malloc((size_t)m.n_k);
	m.made_now = calloc((size_t)plan.n_runs, 1);
	/* a line asks at once for at most its scan (shared by the criteria)
	 * or two bisection points per criterion, and never for more than its
	 * points */
	long per_line = m.n_scan + 2L * m.n_crit < m.n_k ? m.n_scan + 2L * m.n_crit : m.n_k;
	m.todo = malloc((size_t)m.n_lines * (size_t)per_line * sizeof *m.todo);
	if (!m.search || !m.line_runs || !m.need || !m.asked || !m.made_now || !m.todo) {
		st = popc_error_set(&err, POPC_ERR_NOMEM, "out of memory");
		goto out;
	}
	sweep_pool_config pool = {.plan = &plan, .dir = a->dir, .keep_log = a->keep_log,
				  .jobs = a->jobs > 0 ? (int)a->jobs : sweep_pool_default_jobs(), .rows_pid = 0,
				  .die_after_claim = -1, .crash_at = -1, .interrupt_after = -1, .isolate = a->isolate};
	sweep_pool_test_hooks(&pool);
	popc_cli_install_signals(0); /* the simulated axis only */
	for (;;) {
		if ((st = evaluate(&m, &plan, a->dir, &shard, a->port_tol_J, &err)) != 0)
			goto out;
		if (m.n_todo == 0 || popc_cli_stop)
			break;
		step++;
		sweep_progress prog;
		sweep_progress_start(&prog, a->quiet, m.n_todo, 0);
		prog.map = 1;
		if (!a->quiet)
			fprintf(stderr, "popc map: step %d: %lld runs\n", step, m.n_todo);
		for (long long t = 0; t < m.n_todo; t++)
			m.made_now[m.todo[t]] = 1;
		trouble |= sweep_pool_run(&pool, m.todo, m.n_todo, &prog);
		made += prog.done_now;
		if (trouble || popc_cli_stop)
			break;
	}
	if (!a->quiet)
		fprintf(stderr, "popc map: %lld runs made now in %d steps\n", made, step);
	if (popc_cli_stop) {
		fprintf(stderr, "popc map: interrupted; run the same command again to resume\n");
		state_free(&m);
		popc_sweep_plan_free(&plan);
		return POPC_EXIT_INTERRUPTED;
	}
	if (m.n_needed > 0 && trouble) {
		fprintf(stderr, "popc map: a run's row could not be recorded (above); run the same "
				"command again to resume\n");
		goto out;
	}
	if (m.n_needed > 0) {
		fprintf(stderr,
			"popc map: %lld runs of other shards pending; run every shard again until "
			"%s/boundary.csv exists\n",
			m.n_pending_other, a->dir);
		goto out;
	}
	if ((st = write_boundary(&m, &plan, a->dir, &err)) != 0)
		goto out;
	const char *crit_names[POPC_MAP_N_CRITERIA];
	for (int c = 0; c < m.n_crit; c++)
		crit_names[c] = popc_map_criterion_name(m.crit[c]);
	if ((st = popc_map_figure_write(&plan, a->dir, crit_names, m.n_crit, &err)) != 0)
		goto out;
	if (popc_map_figure_plot(a->dir, &err) != 0)
		fprintf(stderr, "popc map: note: %s\n", err.msg);
	print_table(&m, &plan);
	for (long s = 0; s < m.n_lines * m.n_crit; s++)
		trouble |= m.search[s].outcome == POPC_MAP_UNDECIDED_RUN;
out:
	state_free(&m);
	popc_sweep_plan_free(&plan);
	if (st)
		return popc_cli_fail("map", st, &err);
	return trouble ? POPC_EXIT_RUN_FAILED : 0;
}

int popc_cmd_map(int argc, char **argv)
{
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_map_opts, opts, shorts);
	map_args a = {.tol = 0.02, .port_tol_J = 1e-6, .criteria = 1u << POPC_MAP_PASSIVE,
		      .scan_steps = POPC_MAP_SCAN_STEPS_DEFAULT};
	int c, rc = -1, oom = 0;
	popc_error err;
	optind = 1;
	while (rc < 0 && (c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_VARIANT: oom |= popc_arg_push(&a.variants, &a.n_variants, optarg); break;
		case OPT_VARY: oom |= popc_arg_push(&a.vary, &a.n_vary, optarg); break;
		case OPT_SET: oom |= popc_arg_push(&a.sets, &a.n_sets, optarg); break;
		case OPT_STIFFNESS: a.stiffness = optarg; break;
		case OPT_TOL:
			if (popc_parse_double_text(optarg, &a.tol) != POPC_PARSE_OK || !(a.tol >= 1e-4) ||
			    !(a.tol <= 1)) {
				fprintf(stderr, "popc map: --tol '%s': a number in [1e-4, 1]\n", optarg);
				rc = POPC_EXIT_USAGE;
			}
			break;
		case OPT_SCAN:
			if (popc_parse_ll_text(optarg, 1, POPC_SWEEP_RANGE_MAX, &a.scan_steps) != 0) {
				fprintf(stderr, "popc map: --scan '%s': grid steps, a whole number in [1, %ld]\n",
					optarg, POPC_SWEEP_RANGE_MAX);
				rc = POPC_EXIT_USAGE;
			}
			break;
		case OPT_PORT_TOL:
			if (popc_parse_double_text(optarg, &a.port_tol_J) != POPC_PARSE_OK ||
			    !(a.port_tol_J >= 0) || !(a.port_tol_J <= 1e6)) {
				fprintf(stderr, "popc map: --port-tol '%s': joules in [0, 1e6]\n", optarg);
				rc = POPC_EXIT_USAGE;
			}
			break;
		case OPT_CRITERION:
			a.criteria_given = 1;
			if (popc_map_criteria_parse(optarg, &a.criteria, &err) != 0) {
				fprintf(stderr, "popc map: %s\n", err.msg);
				rc = POPC_EXIT_USAGE;
			}
			break;
		case 'o': a.dir = optarg; break;
		case 'j':
			if (popc_parse_ll_text(optarg, 1, 4096, &a.jobs) != 0) {
				fprintf(stderr, "popc map: -j '%s': a whole number in [1, 4096]\n", optarg);
				rc = POPC_EXIT_USAGE;
			}
			break;
		case OPT_SHARD: a.shard_text = optarg; break;
		case OPT_KEEP_LOG: a.keep_log = 1; break;
		case OPT_DRY_RUN: a.dry_run = 1; break;
		case OPT_ALLOW_OTHER_BUILD: a.allow_other_build = 1; break;
		case OPT_ISOLATE: a.isolate = 1; break;
		case 'q': a.quiet = 1; break;
		case 'h': usage(stdout); rc = 0; break;
		default: usage(stderr); rc = POPC_EXIT_USAGE; break;
		}
	}
	if (rc < 0 && !oom && (popc_cli_assignment_split("map", "--set", a.sets, a.n_sets) ||
				popc_cli_assignment_split("map", "--vary", a.vary, a.n_vary)))
		rc = POPC_EXIT_USAGE;
	if (rc < 0) {
		const char *why = optind >= argc       ? "missing SCENE file"
				  : optind + 1 != argc ? "more than one SCENE file"
				  : !a.dir             ? "missing -o DIR"
				  : !a.dir[0]          ? "-o '': give a directory name"
				  : a.n_variants == 0  ? "no --variant given"
						       : NULL;
		if (oom) {
			fprintf(stderr, "popc map: out of memory\n");
			rc = POPC_EXIT_RUN_FAILED;
		} else if (why) {
			fprintf(stderr, "popc map: %s\n", why);
			usage(stderr);
			rc = POPC_EXIT_USAGE;
		} else {
			a.scene_path = argv[optind];
			rc = map_main(&a);
		}
	}
	free(a.variants);
	free(a.vary);
	free(a.sets);
	return rc;
}
