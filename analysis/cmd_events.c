/* popc-analyze events: the paper's timeline events in each log (settling of
 * the velocity, the events of seed Figs. 5 and 8; ana_find_events). */
#include <getopt.h>
#include <math.h>
#include <string.h>

#include "analyze.h"
#include "popc/programs/table_out.h"
#include "popc/util/parse.h"

static void usage(FILE *f)
{
	fputs("usage: popc-analyze events [options] LOG...\n"
	      "\n"
	      "Finds the paper's timeline events in each log (definitions: docs/ANALYSIS.md,\n"
	      "\"Events\"; dcount(k) = count(k) - count(k-1), the PC is active when f_pc != 0):\n"
	      "  settle  from this time |dcount| <= 1 every tick for at least --settle-hold\n"
	      "          (or to the end); seed Fig. 4: the velocity chatters between one\n"
	      "          count per period after 2.5 s. settle_end: the first tick after it\n"
	      "          with |dcount| > 1; settle_final: from here to the end |dcount| <= 1\n"
	      "  fig5    first t(k) from settle on with the PC active, dcount(k) = +-1,\n"
	      "          dcount(k+1) the reverse, and W - E_ref lower at k+1 (seed Fig. 5:\n"
	      "          3.173 s); fig5_first: the first anywhere\n"
	      "  fig8    first t(k) from settle on where the PC turns on and dcount(k+1) = 0,\n"
	      "          so W - E_ref does not move at k+1 (seed Fig. 8: 2.957 s);\n"
	      "          fig8_first: the first anywhere\n"
	      "\n"
	      "  --format text|csv|json   text (default), or CSV with the header\n"
	      "                           log,settle_s,settle_end_s,settle_final_s,fig5_s,\n"
	      "                           fig5_dw_J,fig8_s,fig5_first_s,fig8_first_s,\n"
	      "                           n_fast,n_fig5,n_fig8,\n"
	      "                           x_settled_min_m,x_settled_max_m,ticks\n"
	      "                           (an empty cell: no such event, or not checkable);\n"
	      "                           json: one object per log on one line, the CSV's\n"
	      "                           names and digits, null for an empty cell\n"
	      "  --settle-hold S          least length of the settled stretch, s (default 0.5)\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0, or 2 for bad usage or input (a log without a PC force or W\n"
	      "cannot show the Fig. 5 or 8 event: a note on stderr, and its cells are empty).\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
}

enum { OPT_FORMAT = 256, OPT_SETTLE_HOLD };

static const popc_option events_options[] = {
	{"format", 0, OPT_FORMAT, "text|csv|json"},
	{"settle-hold", 0, OPT_SETTLE_HOLD, "S"},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_events_opts[] = {events_options, ana_input_option_table, NULL};

static void put_cell(FILE *f, double v)
{
	fputc(',', f);
	if (isfinite(v))
		ana_put_double(f, v);
}

static const char csv_header[] =
	"log,settle_s,settle_end_s,settle_final_s,fig5_s,fig5_dw_J,fig8_s,fig5_first_s,"
	"fig8_first_s,n_fast,n_fig5,n_fig8,x_settled_min_m,x_settled_max_m,ticks";

static void print_csv(FILE *f, const char *name, const ana_events *e)
{
	ana_put_csv_text(f, name);
	put_cell(f, e->settle_s);
	put_cell(f, e->settle_end_s);
	put_cell(f, e->settle_final_s);
	put_cell(f, e->fig5_s);
	put_cell(f, e->fig5_dw_J);
	put_cell(f, e->fig8_s);
	put_cell(f, e->fig5_first_s);
	put_cell(f, e->fig8_first_s);
	fprintf(f, ",%lld,%lld,%lld", e->n_fast, e->n_fig5, e->n_fig8);
	put_cell(f, e->x_min_settled_m);
	put_cell(f, e->x_max_settled_m);
	fprintf(f, ",%lld\n", e->ticks);
}

static void print_text(const char *name, const ana_events *e)
{
	printf("%s:\n", name);
	if (isnan(e->settle_s)) {
		printf("  settle: never (the last tick moves more than one count)\n");
	} else {
		printf("  settle: %.3f s (|dcount| <= 1 ", e->settle_s);
		if (isnan(e->settle_end_s))
			printf("to the end");
		else
			printf("until %.3f s", e->settle_end_s);
		printf("; position %.6g to %.6g m)\n", e->x_min_settled_m, e->x_max_settled_m);
	}
	if (isnan(e->settle_final_s))
		printf("  settle_final: never (the last tick moves more than one count); %lld "
		       "ticks move more than one count\n", e->n_fast);
	else
		printf("  settle_final: %.3f s (|dcount| <= 1 to the end); %lld ticks move more "
		       "than one count\n", e->settle_final_s, e->n_fast);
	if (!e->pc_known || !e->w_known)
		printf("  fig5: not checkable (no PC force or no W)\n");
	else if (isnan(e->fig5_s))
		printf("  fig5: none after settle (%lld in all)\n", e->n_fig5);
	else
		printf("  fig5: %.3f s (W - E_ref changes %.3g J at the reversal; first at %.3f s; "
		       "%lld in all)\n", e->fig5_s, e->fig5_dw_J, e->fig5_first_s, e->n_fig5);
	if (!e->pc_known)
		printf("  fig8: not checkable (no PC force)\n");
	else if (isnan(e->fig8_s))
		printf("  fig8: none after settle (%lld in all)\n", e->n_fig8);
	else
		printf("  fig8: %.3f s (first at %.3f s; %lld in all)\n", e->fig8_s, e->fig8_first_s,
		       e->n_fig8);
}

int ana_cmd_events(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_events_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "events";
	ana_format fmt = ANA_TEXT;
	double hold_s = ANA_SETTLE_HOLD_S;
	int c, rc = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_FORMAT:
			if (ana_format_from_name(optarg, &fmt) != 0 || fmt == ANA_MARKDOWN) {
				fprintf(stderr, "popc-analyze events: --format '%s': text, csv or json\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case OPT_SETTLE_HOLD:
			if (popc_parse_double_text(optarg, &hold_s) != POPC_PARSE_OK || !(hold_s >= 0.0) ||
			    !isfinite(hold_s)) {
				fprintf(stderr, "popc-analyze events: --settle-hold '%s': a time in "
						"[0, inf) s\n", optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "events")) != 0)
				goto out;
			break;
		default: usage(stderr); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc-analyze events: missing LOG\n");
		usage(stderr);
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	/* json: the CSV's rows as objects, the same cells (popc_table_out) */
	static const char *const text_columns[] = {"log", NULL};
	popc_table_out table;
	int tabled = fmt == ANA_CSV || fmt == ANA_JSON;
	if (tabled && popc_table_out_begin(&table, stdout, fmt == ANA_JSON, csv_header, text_columns) != 0) {
		fprintf(stderr, "popc-analyze events: out of memory\n");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	for (int i = optind; i < argc; i++) {
		ana_events e;
		popc_error err;
		int st = ana_find_events(argv[i], &in, hold_s, &e, &err);
		if (st) {
			ana_fail("events", st, &err);
			rc = POPC_EXIT_USAGE;
			continue;
		}
		char name[256];
		ana_log_name(argv[i], name, sizeof name);
		if (!e.pc_known || !e.w_known) {
			fprintf(stderr,
				"popc-analyze events: %s: %s, so the %s not checked\n", argv[i],
				!e.pc_known ? "no PC force (f_pc or f_c)" : "no W",
				!e.pc_known ? "Fig. 5 and Fig. 8 events are" : "Fig. 5 event is");
			rc = POPC_EXIT_USAGE;
		}
		if (tabled) {
			print_csv(popc_table_out_row(&table), name, &e);
			if (popc_table_out_flush(&table) != 0) {
				fprintf(stderr, "popc-analyze events: out of memory\n");
				rc = POPC_EXIT_USAGE;
			}
		} else {
			print_text(name, &e);
		}
	}
	if (tabled)
		popc_table_out_end(&table);
out:
	ana_input_free(&in);
	return rc;
}
