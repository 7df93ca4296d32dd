/* popc-analyze chatter: flags the seed's noisy behavior (PC chattering in the
 * low-velocity phase) as time intervals and a sustained low-frequency limit
 * cycle, with the library's streaming detector (popc/chatter.h). */
#include <getopt.h>
#include <math.h>
#include <string.h>

#include "analyze.h"
#include "popc/programs/table_out.h"
#include "popc/programs/usage_hint.h"

static void usage(FILE *f)
{
	fputs("usage: popc-analyze chatter [options] LOG...\n"
	      "\n"
	      "Flags PC chattering (seed Fig. 3: the PC force switching sign at high rate with\n"
	      "a large RMS while the velocity sign flips in contact) as time intervals, and\n"
	      "separately a sustained low-frequency limit cycle (seed Fig. 10: the contact\n"
	      "keeps oscillating with an amplitude far above the encoder resolution).\n"
	      "Metrics and thresholds: docs/ANALYSIS.md.\n"
	      "\n"
	      "  --format text|csv|json   text (default), or CSV rows log,kind,start_s,end_s,value\n"
	      "                           (json: one object per row on one line, the CSV's\n"
	      "                           names and digits, null for an empty cell)\n"
	      "                           (kind chatter: value = largest window PC RMS, N;\n"
	      "                           kind limit_cycle: value = amplitude, m;\n"
	      "                           kind chatter_not_checked: the log has no PC force\n"
	      "                           or is shorter than one window;\n"
	      "                           kind limit_cycle_not_checked: the log is shorter\n"
	      "                           than half a limit-cycle window)\n"
	      "  --threshold NAME=VALUE   change a threshold (repeatable); relative to the\n"
	      "                           log's scene (header, or --set controller.pc_bound,\n"
	      "                           encoder.resolution, run.rate); names and defaults:\n"
	      "                           window=0.1 s, pc_rms_share=0.05 (of the PC bound),\n"
	      "                           pc_flip_share=0.1 and vsign_share=0.1 (per control\n"
	      "                           tick), contact=0.5 (share of window), lc_window=2 s,\n"
	      "                           lc_amplitude=4 counts, lc_hysteresis=3 counts,\n"
	      "                           lc_cycles=2 (per lc_window), lc_freq_share=0.1 (of\n"
	      "                           the control rate), lc_contact=0.1, lc_sustain=0.8\n"
	      "  -q, --quiet              print nothing; the exit status tells\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
	/* two strings: one would pass the 4095 characters C99 promises */
	fputs("Exit status (like diff): 0 nothing flagged, 1 chatter or a limit cycle flagged,\n"
	      "2 trouble (bad usage or input). A log without a PC force (no f_pc or f_c\n"
	      "column, none mapped with --column) cannot be checked for chatter: its limit\n"
	      "cycle is still reported (it needs only positions), and the exit status is 2.\n"
	      "So is a log shorter than one window (default 0.1 s: 100 ticks at 1 kHz): it\n"
	      "was not checked, which is no 'no chatter'. The limit cycle needs half its\n"
	      "window (default 1 s: 1000 ticks at 1 kHz); a shorter log says 'limit cycle not\n"
	      "checked' (and a note on stderr, also with -q) and exits by its chatter\n"
	      "verdict: 0 or 1 when chatter was checked (a 0.1 to 1 s log), 2 when it was not.\n"
	      "Exit 0 says nothing was flagged, not that there is no limit cycle.\n",
	      f);
	fputs("A teleoperation log is checked per port, LOG:master (f_pc, N, PC scale 20 K_e\n"
	      "delta) and LOG:slave (vs_pc, m/s, PC scale 20 r / (K_e T)): docs/TELEOPERATION.md.\n",
	      f);
}

enum { OPT_FORMAT = 256, OPT_THRESHOLD };

static const popc_option chatter_options[] = {
	{"format", 0, OPT_FORMAT, "text|csv|json"},
	{"threshold", 0, OPT_THRESHOLD, "NAME=VALUE"},
	{"quiet", 'q', 'q', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_chatter_opts[] = {chatter_options, ana_input_option_table, NULL};

static void print_text(const ana_summary *s)
{
	const popc_chatter_result *r = &s->chatter;
	printf("%s: ", s->log);
	const int checked = ana_chatter_checked(s);
	if (!s->has_pc_force)
		printf("chatter not checked (no PC force)");
	else if (!checked)
		printf("chatter not checked (%lld ticks, fewer than one window of %lld)", s->ticks,
		       r->window_ticks);
	else if (r->n_intervals)
		printf("chatter %.3f s in %d interval%s:", r->chatter_s, r->n_intervals,
		       r->n_intervals == 1 ? "" : "s");
	else
		printf("no chatter");
	/* an admittance log's PC is the parallel PC's velocity */
	const char *unit = s->admittance ? "m/s" : "N";
	for (int i = 0; i < r->n_stored; i++)
		printf(" [%.3f, %.3f) s (PC RMS up to %.3g %s)%s", r->intervals[i].start_s,
		       r->intervals[i].end_s, r->intervals[i].pc_rms_max_N, unit,
		       i + 1 < r->n_stored ? "," : "");
	if (r->n_stored < r->n_intervals)
		printf(" ... (%d more)", r->n_intervals - r->n_stored);
	if (!ana_lc_checked(s))
		printf("; limit cycle not checked (%lld ticks, fewer than half a window: %lld)\n",
		       s->ticks, r->lc_min_ticks);
	else
		printf("; %s\n", r->limit_cycle ? "LIMIT CYCLE" : "no limit cycle");
	const popc_chatter_thresholds *th = &r->thr;
	if (checked)
		printf("  windows: max PC RMS %.3g %s (threshold %.3g), max PC sign flips %.4g /s "
		       "(%.4g), ",
		       r->max_pc_rms_N, unit, th->pc_rms_min_N, r->max_pc_flip_rate_Hz,
		       th->pc_flip_rate_min_Hz);
	else
		printf("  windows: max PC RMS n/a, max PC sign flips n/a, ");
	if (r->windows > 0)
		printf("max velocity sign changes %.4g /s in contact (%.4g)\n", r->max_vsign_rate_Hz,
		       th->vsign_rate_min_Hz);
	else
		printf("max velocity sign changes n/a (no full window)\n");
	if (!ana_lc_checked(s)) {
		/* fewer turning points than a frequency or a sustain needs: the
		 * window's metrics are no measurement, as compare's n/a cells */
		printf("  last %.3g s: limit-cycle metrics n/a (fewer than %lld ticks)\n", r->lc_span_s,
		       r->lc_min_ticks);
		return;
	}
	printf("  last %.3g s: amplitude %.3g m (threshold %.3g) at %.3g Hz (%.3g to %.3g), "
	       "%.0f %% in contact, sustain %.3g, ",
	       r->lc_span_s, r->lc_amplitude_m, th->lc_amplitude_min_m, r->lc_frequency_Hz,
	       th->lc_freq_min_Hz, th->lc_freq_max_Hz, 100.0 * r->lc_contact, r->lc_sustain);
	if (s->has_pc_force)
		printf("PC RMS %.3g %s, ", r->lc_pc_rms_N, unit);
	else
		printf("PC RMS n/a, ");
	if (s->has_w)
		printf("W - E_ref drift %.3g J\n", r->lc_w_drift_J);
	else
		printf("W - E_ref drift n/a\n");
}

static void print_csv(FILE *f, const ana_summary *s)
{
	const popc_chatter_result *r = &s->chatter;
	if (!ana_chatter_checked(s)) {
		ana_put_csv_text(f, s->log);
		fprintf(f, ",chatter_not_checked,,,\n");
	}
	for (int i = 0; i < r->n_stored; i++) {
		ana_put_csv_text(f, s->log);
		fprintf(f, ",chatter,");
		ana_put_double(f, r->intervals[i].start_s);
		fputc(',', f);
		ana_put_double(f, r->intervals[i].end_s);
		fputc(',', f);
		ana_put_double(f, r->intervals[i].pc_rms_max_N);
		fputc('\n', f);
	}
	if (!ana_lc_checked(s)) {
		ana_put_csv_text(f, s->log);
		fprintf(f, ",limit_cycle_not_checked,,,\n");
	} else if (r->limit_cycle) {
		ana_put_csv_text(f, s->log);
		fprintf(f, ",limit_cycle,");
		ana_put_double(f, r->lc_start_s);
		fputc(',', f);
		ana_put_double(f, r->lc_end_s);
		fputc(',', f);
		ana_put_double(f, r->lc_amplitude_m);
		fputc('\n', f);
	}
}

/* A teleoperation log's two ports (master f_pc in N, slave vs_pc in m/s),
 * each as a one-port log would be reported; returns 0, or -1 when a port was
 * not checked (the exit status is then 2, as for a one-port log). */
static int teleop_chatter(ana_summary port[2], const char *path, int quiet, popc_table_out *table,
			  int *flagged)
{
	int bad = 0;
	for (int p = 0; p < 2; p++) {
		const ana_summary *s = &port[p];
		popc_error err;
		if (s->chatter.n_intervals || s->chatter.limit_cycle)
			*flagged = 1;
		if (!ana_chatter_checked(s)) {
			ana_chatter_too_short(&err, path, s);
			fprintf(stderr, "popc-analyze chatter: %s (%s port)\n", err.msg,
				p ? "slave" : "master");
			bad = -1;
		}
		if (!ana_lc_checked(s)) {
			ana_lc_too_short(&err, path, s);
			fprintf(stderr, "popc-analyze chatter: %s%s (%s port)\n",
				ana_chatter_checked(s) ? "note: " : "", err.msg, p ? "slave" : "master");
		}
		if (quiet)
			continue;
		if (table) {
			print_csv(popc_table_out_row(table), s);
			if (popc_table_out_flush(table) != 0)
				bad = -1;
		} else {
			print_text(s);
		}
	}
	return bad;
}

int ana_cmd_chatter(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_chatter_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "chatter";
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	ana_format fmt = ANA_TEXT;
	int c, rc = 0, quiet = 0, flagged = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_FORMAT:
			if (ana_format_from_name(optarg, &fmt) != 0 || fmt == ANA_MARKDOWN) {
				fprintf(stderr, "popc-analyze chatter: --format '%s': text, csv or json\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case OPT_THRESHOLD:
			if ((rc = ana_threshold_option(&cc, optarg, "chatter")) != 0)
				goto out;
			break;
		case 'q': quiet = in.quiet = 1; break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "chatter")) != 0)
				goto out;
			break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc-analyze chatter: missing LOG\n");
		popc_help_hint(argv[0], "options");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	/* csv, and json: the CSV's rows as objects, the same cells (popc_table_out) */
	static const char *const text_columns[] = {"log", "kind", NULL};
	popc_table_out table;
	int tabled = !quiet && (fmt == ANA_CSV || fmt == ANA_JSON);
	if (tabled && popc_table_out_begin(&table, stdout, fmt == ANA_JSON,
					   "log,kind,start_s,end_s,value", text_columns) != 0) {
		fprintf(stderr, "popc-analyze chatter: out of memory\n");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	for (int i = optind; i < argc; i++) {
		ana_summary s;
		popc_error err;
		int st = ana_summarize(argv[i], &in, &cc, -1.0, &s, NULL, NULL, &err);
		if (st) {
			ana_fail("chatter", st, &err);
			rc = POPC_EXIT_USAGE;
			continue;
		}
		if (s.teleop) {
			/* each port its own detector, thresholds from its own scale
			 * (teleop_log.h): reported as LOG:master and LOG:slave */
			ana_summary port[2];
			const ana_tele_port *tp[2] = {&s.tele.m, &s.tele.s};
			for (int p = 0; p < 2; p++) {
				memset(&port[p], 0, sizeof port[p]);
				snprintf(port[p].log, sizeof port[p].log, "%.200s:%s", s.log,
					 p ? "slave" : "master");
				port[p].chatter = tp[p]->chatter;
				port[p].has_pc_force = port[p].has_w = 1;
				port[p].admittance = p; /* the slave's PC is a velocity */
				port[p].ticks = s.tele.ticks;
				port[p].period_s = s.tele.period_s;
			}
			if (teleop_chatter(port, argv[i], quiet, tabled ? &table : NULL, &flagged) != 0)
				rc = POPC_EXIT_USAGE;
			continue;
		}
		if (s.chatter.n_intervals || s.chatter.limit_cycle)
			flagged = 1;
		const int lc_checked = ana_lc_checked(&s);
		if (!s.has_pc_force) {
			/* "no chatter" would be a verdict without data: trouble, like a
			 * missing required column; the limit cycle needs only positions,
			 * so it is still reported */
			ana_no_pc_force(&err, argv[i]);
			fprintf(stderr, "popc-analyze chatter: %s; chatter not checked%s\n", err.msg,
				lc_checked ? ", only the limit cycle" : "");
			rc = POPC_EXIT_USAGE;
		} else if (!ana_chatter_checked(&s)) {
			/* shorter than one detection window: no window was judged, so
			 * "no chatter" would again be a verdict without data */
			ana_chatter_too_short(&err, argv[i], &s);
			fprintf(stderr, "popc-analyze chatter: %s\n", err.msg);
			rc = POPC_EXIT_USAGE;
		}
		if (!lc_checked) {
			/* the exit status follows chatter, the verb's question (docs/
			 * ANALYSIS.md): a 0.1 to 1 s log has a chatter verdict and
			 * exits 0 or 1. Nothing else would tell a -q caller that the
			 * limit cycle was not judged, so this note is kept under -q;
			 * it is a note when the exit status is not already 2. */
			ana_lc_too_short(&err, argv[i], &s);
			fprintf(stderr, "popc-analyze chatter: %s%s\n",
				ana_chatter_checked(&s) ? "note: " : "", err.msg);
		}
		if (quiet)
			continue;
		if (tabled) {
			print_csv(popc_table_out_row(&table), &s);
			if (popc_table_out_flush(&table) != 0) {
				fprintf(stderr, "popc-analyze chatter: out of memory\n");
				rc = POPC_EXIT_USAGE;
			}
		} else {
			print_text(&s);
		}
	}
	if (tabled)
		popc_table_out_end(&table);
	if (rc == 0 && flagged)
		rc = POPC_EXIT_RUN_FAILED;
out:
	ana_input_free(&in);
	return rc;
}
