/* popc-analyze compare: one row of metrics per log (popc_metrics and the
 * chatter detector), as text, CSV or Markdown. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "popc/core/admittance.h"
#include "popc/core/compensated.h"
#include "popc/core/metrics.h"
#include "popc/util/json.h"
#include "popc/util/parse.h"
#include "popc/programs/usage_hint.h"

/* Every number of the summary is finite: the rows are (ana_log_next), the
 * RMS is taken without overflow (popc_sum_squares), the rates per second are
 * at most 1/T (a normal T: ana_log_open); what is left is a difference of
 * finite values that a double cannot hold (the duration from t = -1e308 to
 * 1e308, the W - E_ref drift between two huge values), refused by name. */
static int summary_finite(const char *path, const ana_summary *s, popc_error *err)
{
	const popc_chatter_result *c = &s->chatter;
	const struct {
		const char *name;
		double v;
	} q[] = {
		{"duration_s (last t - first t)", s->duration_s},
		{"pc_rms", s->pc_rms_N},
		{"pc_rms_late", s->pc_rms_late_N},
		{"pc_max", s->pc_max_N},
		{"pc_energy", s->pc_energy_J},
		{"w_minus_eref_min", s->w_minus_eref_min_J},
		{"w_minus_eref_end", s->w_minus_eref_end_J},
		{"vsign_rate", s->vsign_rate_Hz},
		{"vsign_rate_late", s->vsign_rate_late_Hz},
		{"chatter_s", c->chatter_s},
		{"the chatter windows' largest PC RMS", c->max_pc_rms_N},
		{"the chatter windows' largest PC flip rate", c->max_pc_flip_rate_Hz},
		{"the chatter windows' largest velocity sign change rate", c->max_vsign_rate_Hz},
		{"lc_amplitude", c->lc_amplitude_m},
		{"lc_frequency", c->lc_frequency_Hz},
		{"the limit cycle's sustain", c->lc_sustain},
		{"the limit cycle's PC RMS", c->lc_pc_rms_N},
		{"the limit cycle's W - E_ref drift", c->lc_w_drift_J},
		{"port_energy_end", s->port_energy_end_J},
		{"po_error_end (W - E_port)", s->po_error_end_J},
		{"po_error_max (max |W - E_port|)", s->po_error_max_J},
		{"port_energy_min", s->port_energy_min_J},
		{"rendered_stiffness", s->rendered_stiffness_Npm},
	};
	for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
		if (!isfinite(q[i].v))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %s overflows a double, from finite rows (%lld ticks; "
					      "the last limit-cycle window: t = %g to %g s)",
					      path, q[i].name, s->ticks, c->lc_start_s, c->lc_end_s);
	return 0;
}

int ana_summarize(const char *path, const ana_input_options *o, const popc_chatter_config *ccfg,
		  double late_from_s, ana_summary *s, ana_row_fn on_row, void *ctx,
		  popc_error *err)
{
	memset(s, 0, sizeof *s);
	ana_log l;
	/* the detector's and the metrics' contact share read the environment */
	ana_input_options oe = *o;
	oe.uses |= ANA_USES_ENVIRONMENT | ANA_USES_PC_BOUND;
	int st = ana_log_open(&l, path, &oe, err);
	if (st)
		return st;
	s->has_pc_force = l.has_pc_force;
	s->period_s = l.period_s;
	s->has_w = l.has_w;
	s->has_port_energy = l.c_E_port >= 0 && l.has_w;
	snprintf(s->log, sizeof s->log, "%s", l.name);
	snprintf(s->variant, sizeof s->variant, "%s", l.variant);
	s->env_stiffness_Npm = l.scene.env_stiffness_Npm;
	s->env_position_m = l.scene.env_position_m;
	s->enc_resolution_m = l.scene.enc_resolution_m;
	s->pc_bound_N = l.scene.pc_bound_N;
	s->admittance = l.scene.causality == POPC_CAUSALITY_ADMITTANCE && l.c_v_pc >= 0;
	s->adm_force_resolution_N = l.scene.adm_force_resolution_N;
	s->adm_virtual_mass_kg = l.scene.adm_virtual_mass_kg;
	s->adm_virtual_damping_Nspm = l.scene.adm_virtual_damping_Nspm;
	s->adm_pc_velocity_bound_mps = l.scene.adm_pc_velocity_bound_mps;
	if (s->admittance)
		s->pc_bound_N = POPC_ADMITTANCE_CHATTER_COUNTS *
				popc_admittance_count_velocity_mps(
					l.scene.adm_force_resolution_N, l.scene.env_stiffness_Npm,
					l.scene.adm_virtual_mass_kg, l.scene.adm_virtual_damping_Nspm,
					l.period_s);
	snprintf(s->ignore_mode, sizeof s->ignore_mode, "%s",
		 popc_ignore_mode_names[l.scene.ignore_mode]);
	if (l.scene.tele_arch != POPC_TELEOP_OFF) {
		/* two ports: the file again, by the teleop columns' names */
		s->teleop = 1;
		s->tele_scene = l.scene;
		ana_log_close(&l);
		st = ana_tele_summarize(path, &s->tele_scene, ccfg, &s->tele, NULL, NULL, err);
		s->ticks = s->tele.ticks;
		s->duration_s = s->tele.duration_s;
		return st;
	}
	if (late_from_s < 0.0) {
		/* the online summary's late window: the second half of the run, the
		 * seed's low-velocity phase; a log without a duration: all of it */
		late_from_s = popc_log_reader_header(&l.r, "run.duration") ? 0.5 * l.scene.duration_s
									   : -(double)INFINITY;
	}
	popc_metrics m;
	popc_metrics_init(&m, &l.env, l.period_s, late_from_s);
	popc_chatter_config cc = *ccfg;
	/* the thresholds are relative to the scene analysed (its header, --set) */
	cc.resolution_m = l.scene.enc_resolution_m;
	cc.pc_bound_N = s->pc_bound_N;
	popc_chatter det;
	st = popc_chatter_init(&det, &cc, l.period_s, &l.env, err);
	if (st) {
		ana_chatter_name_options(err);
		char msg[POPC_ERROR_MSG_MAX];
		snprintf(msg, sizeof msg, "%s", err->msg);
		popc_error_set(err, st, "%s: %s", path, msg);
		ana_log_close(&l);
		return st;
	}
	ana_row row;
	double t0 = 0.0, t1 = 0.0;
	double adm_e_sum = 0.0, adm_e_comp = 0.0, adm_e = 0.0;
	while ((st = ana_log_next(&l, &row, err)) == 1) {
		if (s->ticks == 0)
			t0 = row.tick.t_s;
		t1 = row.tick.t_s;
		if (s->admittance && row.has_adm) {
			/* the parallel PC's output in f_pc's place, as a sweep's
			 * detector sees it (run_admittance.c's on_tick) */
			row.tick.f_pc_N = row.adm_v_pc_mps;
			adm_e = popc_compensated_add(&adm_e_sum, &adm_e_comp,
						     l.period_s * row.adm_f_N * row.adm_v_pc_mps);
		}
		popc_metrics_add(&m, &row.tick);
		/* f_pc(k-1) dx(k) of finite cells, summed: 1e308 N over 10 m is no
		 * double */
		if (!isfinite(m.pc_energy_J)) {
			ana_log_close(&l);
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: the PC energy, the sum of f_pc(k-1) (x(k) - "
					      "x(k-1)), overflows a double here (f_pc %g N, x %g m)",
					      path, row.line, row.tick.f_pc_N, row.tick.x_m);
		}
		popc_chatter_add(&det, &row.tick);
		if (s->has_port_energy) {
			/* W(k) - E_port(k): the observer's error at tick k */
			const double e = row.tick.W_J - row.E_port_J;
			s->port_energy_end_J = row.E_port_J;
			if (s->ticks == 0 || row.E_port_J < s->port_energy_min_J)
				s->port_energy_min_J = row.E_port_J;
			s->po_error_end_J = e;
			if (fabs(e) > s->po_error_max_J)
				s->po_error_max_J = fabs(e);
		}
		if (on_row)
			on_row(ctx, &row);
		s->ticks++;
	}
	ana_log_close(&l);
	if (st < 0)
		return st;
	popc_chatter_finish(&det, &s->chatter);
	s->duration_s = t1 - t0;
	s->pc_rms_N = popc_metrics_pc_rms(&m.all);
	s->pc_rms_late_N = popc_metrics_pc_rms(&m.late);
	s->pc_max_N = m.all.pc_max_N;
	s->pc_active = popc_metrics_active_fraction(&m.all);
	s->pc_energy_J = s->admittance ? adm_e : m.pc_energy_J;
	s->w_minus_eref_min_J = isfinite(m.w_minus_eref_min_J) ? m.w_minus_eref_min_J : 0.0;
	s->w_minus_eref_end_J = m.w_minus_eref_end_J;
	s->vsign_rate_Hz = popc_metrics_vsign_rate(&m.all, m.period_s);
	s->vsign_rate_late_Hz = popc_metrics_vsign_rate(&m.late, m.period_s);
	s->rendered_stiffness_Npm = popc_metrics_rendered_stiffness(&m);
	return summary_finite(path, s, err);
}

int ana_chatter_checked(const ana_summary *s)
{
	return s->has_pc_force && popc_chatter_checked(&s->chatter);
}

int ana_lc_checked(const ana_summary *s)
{
	/* positions only: a log without a PC force is checked too */
	return popc_chatter_lc_checked(&s->chatter);
}

int ana_lc_too_short(popc_error *err, const char *path, const ana_summary *s)
{
	const long long need = s->chatter.lc_min_ticks;
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: limit cycle not checked: the log has %lld tick%s (%.4g s at T = "
			      "%.4g s), fewer than half a limit-cycle window (%lld ticks, %.4g s); it "
			      "needs at least %lld ticks (%.4g s), or a shorter window (--threshold "
			      "lc_window=S)",
			      path, s->ticks, s->ticks == 1 ? "" : "s", (double)s->ticks * s->period_s,
			      s->period_s, need, (double)need * s->period_s, need,
			      (double)need * s->period_s);
}

int ana_chatter_too_short(popc_error *err, const char *path, const ana_summary *s)
{
	const long long need = s->chatter.window_ticks;
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: chatter not checked: the log has %lld tick%s (%.4g s at T = %.4g s), "
			      "fewer than one detection window of %lld ticks (%.4g s); it needs at least "
			      "%lld ticks (%.4g s), or a shorter window (--threshold window=S)",
			      path, s->ticks, s->ticks == 1 ? "" : "s", (double)s->ticks * s->period_s,
			      s->period_s, need, (double)need * s->period_s, need,
			      (double)need * s->period_s);
}

static const char *const columns[] = {
	"log", "variant", "ticks", "duration_s", "pc_rms", "pc_rms_late", "pc_max", "pc_active",
	"pc_energy", "w_minus_eref_min", "w_minus_eref_end", "vsign_rate", "vsign_rate_late",
	"chatter_s", "chatter_intervals", "limit_cycle", "lc_amplitude", "lc_frequency",
	"port_energy_end", "po_error_end", "po_error_max", "port_energy_min", "rendered_stiffness",
};
#define N_COLUMNS ((int)(sizeof columns / sizeof columns[0]))
/* The columns that are text in JSON (the others are numbers, or null where
 * the CSV cell is empty): the log's name and its variant. */
#define N_TEXT_COLUMNS 2

/* A row in JSON: the CSV row, as one object of the columns' names. */
static void print_json_row(FILE *f, const ana_summary *s)
{
	char *row = NULL;
	size_t len = 0;
	FILE *m = open_memstream(&row, &len);
	if (!m)
		return;
	ana_summary_print_row(m, ANA_CSV, s);
	if (fclose(m) == 0 && row) {
		popc_json_kind kinds[N_COLUMNS];
		for (int i = 0; i < N_COLUMNS; i++)
			kinds[i] = i < N_TEXT_COLUMNS ? POPC_JSON_TEXT : POPC_JSON_NUMBER;
		popc_json_csv_object(f, N_COLUMNS, columns, kinds, row, len);
	}
	free(row);
}

void ana_summary_print_header(FILE *f, ana_format fmt)
{
	switch (fmt) {
	case ANA_JSON: break; /* each object names its columns */
	case ANA_CSV:
		for (int i = 0; i < N_COLUMNS; i++)
			fprintf(f, "%s%s", i ? "," : "", columns[i]);
		fputc('\n', f);
		break;
	case ANA_MARKDOWN:
		for (int i = 0; i < N_COLUMNS; i++)
			fprintf(f, "| %s ", columns[i]);
		fputs("|\n", f);
		for (int i = 0; i < N_COLUMNS; i++)
			fputs(i < 2 ? "|---" : "|---:", f);
		fputs("|\n", f);
		break;
	default:
		fprintf(f, "%-20s %-18s %7s %8s %8s %8s %8s %8s %10s %10s %10s %8s %8s %8s %4s %3s %10s %8s "
			   "%10s %10s %10s %10s %9s\n",
			"log", "variant", "ticks", "dur_s", "pc_rms", "rms_late", "pc_max", "active",
			"pc_energy", "wme_min", "wme_end", "vsign/s", "vs_late", "chat_s", "n", "lc",
			"lc_amp_m", "lc_Hz", "E_port_end", "poerr_end", "poerr_max", "E_port_min",
			"K_rend");
	}
}

void ana_summary_print_row(FILE *f, ana_format fmt, const ana_summary *s)
{
	if (fmt == ANA_JSON) {
		print_json_row(f, s);
		return;
	}
	const popc_chatter_result *c = &s->chatter;
	double v[] = {s->duration_s,     s->pc_rms_N,          s->pc_rms_late_N,
		      s->pc_max_N,       s->pc_active,         s->pc_energy_J,
		      s->w_minus_eref_min_J, s->w_minus_eref_end_J, s->vsign_rate_Hz,
		      s->vsign_rate_late_Hz, c->chatter_s};
	const int nv = (int)(sizeof v / sizeof v[0]);
	/* which cells have data behind them: without a PC force the PC metrics and
	 * the chatter verdict are n/a (empty in CSV), without W also W - E_ref;
	 * never a 0 that reads as "the PC was idle" */
	int known[sizeof v / sizeof v[0]];
	for (int i = 0; i < nv; i++)
		known[i] = 1;
	known[1] = known[2] = known[3] = known[4] = known[5] = s->has_pc_force;
	/* chatter also needs one full detection window: a shorter log has no
	 * verdict (n/a, empty in CSV), not "0 s of chatter" */
	known[10] = ana_chatter_checked(s);
	known[6] = known[7] = s->has_w;
	if (fmt == ANA_TEXT) {
		static const int width[] = {8, 8, 8, 8, 8, 10, 10, 10, 8, 8, 8};
		fprintf(f, "%-20s %-18s %7lld", s->log, s->variant, s->ticks);
		for (int i = 0; i < nv; i++) {
			if (!known[i])
				fprintf(f, " %*s", width[i], "n/a");
			else if (width[i] == 10)
				fprintf(f, " %10.3e", v[i]);
			else
				fprintf(f, " %8.4g", v[i]);
		}
		if (ana_chatter_checked(s))
			fprintf(f, " %4d", c->n_intervals);
		else
			fprintf(f, " %4s", "n/a");
		if (ana_lc_checked(s))
			fprintf(f, " %3d %10.3e %8.4g", c->limit_cycle, c->lc_amplitude_m,
				c->lc_frequency_Hz);
		else
			fprintf(f, " %3s %10s %8s", "n/a", "n/a", "n/a");
		if (s->has_port_energy)
			fprintf(f, " %10.3e %10.3e %10.3e %10.3e", s->port_energy_end_J,
				s->po_error_end_J, s->po_error_max_J, s->port_energy_min_J);
		else
			fprintf(f, " %10s %10s %10s %10s", "n/a", "n/a", "n/a", "n/a");
		fprintf(f, " %9.4g\n", s->rendered_stiffness_Npm);
		return;
	}
	const char *sep = fmt == ANA_CSV ? "," : " | ";
	const char *na = fmt == ANA_CSV ? "" : "n/a";
	if (fmt == ANA_MARKDOWN)
		fputs("| ", f);
	/* the log's name is its file name and the variant the header's text:
	 * either may hold the separator */
	void (*put_text)(FILE *, const char *) = fmt == ANA_CSV ? ana_put_csv_text : ana_put_md_text;
	put_text(f, s->log);
	fputs(sep, f);
	put_text(f, s->variant);
	fprintf(f, "%s%lld", sep, s->ticks);
	for (int i = 0; i < nv; i++) {
		fputs(sep, f);
		if (!known[i])
			fputs(na, f);
		else if (fmt == ANA_MARKDOWN)
			fprintf(f, "%.4g", v[i]);
		else
			ana_put_double_point(f, v[i]);
	}
	fputs(sep, f);
	if (ana_chatter_checked(s))
		fprintf(f, "%d", c->n_intervals);
	else
		fputs(na, f);
	/* the limit cycle needs half its window: a shorter log has no verdict,
	 * and its amplitude and frequency, from a few turning points, are no
	 * measurement */
	if (!ana_lc_checked(s)) {
		fprintf(f, "%s%s%s%s%s%s", sep, na, sep, na, sep, na);
	} else if (fmt == ANA_MARKDOWN) {
		fprintf(f, "%s%d%s%.4g%s%.4g", sep, c->limit_cycle, sep, c->lc_amplitude_m, sep,
			c->lc_frequency_Hz);
	} else {
		fprintf(f, "%s%d%s", sep, c->limit_cycle, sep);
		ana_put_double_point(f, c->lc_amplitude_m);
		fputs(sep, f);
		ana_put_double_point(f, c->lc_frequency_Hz);
	}
	/* the true port energy: only a log with E_port (and W) has it */
	const double port[] = {s->port_energy_end_J, s->po_error_end_J, s->po_error_max_J,
			       s->port_energy_min_J};
	for (int i = 0; i < 4; i++) {
		fputs(sep, f);
		if (!s->has_port_energy)
			fputs(na, f);
		else if (fmt == ANA_MARKDOWN)
			fprintf(f, "%.4g", port[i]);
		else
			ana_put_double_point(f, port[i]);
	}
	fputs(sep, f);
	if (fmt == ANA_MARKDOWN)
		fprintf(f, "%.4g", s->rendered_stiffness_Npm);
	else
		ana_put_double_point(f, s->rendered_stiffness_Npm);
	fputs(fmt == ANA_MARKDOWN ? " |\n" : "\n", f);
}

static void usage(FILE *f)
{
	fputs("usage: popc-analyze compare [options] LOG...\n"
	      "\n"
	      "One row per log, one column per metric, for comparing controller variants and\n"
	      "parameter values. Columns (SI units; docs/ANALYSIS.md):\n"
	      "  log (the file name; logs that would share one: the shortest path suffix\n"
	      "  that tells them apart, a/improved and b/improved), variant, ticks, duration_s;\n"
	      "  pc_rms, pc_rms_late, pc_max (N); pc_active\n"
	      "  (share of ticks with f_pc != 0); pc_energy (J, sum f_pc(k-1) dx(k));\n"
	      "  w_minus_eref_min, w_minus_eref_end (J); vsign_rate, vsign_rate_late (velocity\n"
	      "  sign changes per second in contact); chatter_s, chatter_intervals, limit_cycle,\n"
	      "  lc_amplitude (m), lc_frequency (Hz) from the chatter detector; port_energy_end\n"
	      "  (J, the log's true port energy E_port at the end), po_error_end and\n"
	      "  po_error_max (J, the observer's error W - E_port at the end, largest |.|),\n"
	      "  port_energy_min (J, the smallest E_port), n/a (empty in CSV) for a log\n"
	      "  without E_port (a real axis, a foreign log); rendered_stiffness (N/m, least\n"
	      "  squares f_c / penetration over the rows in contact; 0 without contact).\n"
	      "The late window is the second half of run.duration (popc logs), else --late-from.\n"
	      "A log without a PC force (no f_pc or f_c column) gets n/a (empty in CSV) for the\n"
	      "PC and chatter columns, and for W - E_ref unless W and E_ref are logged; a log\n"
	      "shorter than one chatter window (--threshold window, default 0.1 s) gets n/a\n"
	      "for chatter_s and chatter_intervals, and one shorter than half a limit-cycle\n"
	      "window (--threshold lc_window, default 2 s: 1 s) for limit_cycle,\n"
	      "lc_amplitude and lc_frequency: they were not checked (a note on stderr).\n"
	      "\n"
	      "  --format text|csv|markdown|json  output format (default text); json: one\n"
	      "                           object per log on one line (JSON Lines), the CSV's\n"
	      "                           names, numbers as JSON numbers, null for n/a\n"
	      "  --late-from T            start of the late window (s)\n"
	      "  --threshold NAME=VALUE   a chatter threshold (see 'chatter --help'; repeatable)\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 2 bad usage or input (the other logs are still compared).\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
	fputs("\nTeleoperation logs (teleop.architecture in the header) get the two-port table\n"
	      "of 'popc-analyze teleop' (each port's PC and chatter, energies, margins, drift,\n"
	      "force tracking); one comparison of them with one-port logs is refused (exit 2).\n",
	      f);
}

enum { OPT_FORMAT = 256, OPT_LATE, OPT_THRESHOLD };

static const popc_option compare_options[] = {
	{"format", 0, OPT_FORMAT, "text|csv|markdown|json"},
	{"late-from", 0, OPT_LATE, "S"},
	{"threshold", 0, OPT_THRESHOLD, "NAME=VALUE"},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_compare_opts[] = {compare_options, ana_input_option_table, NULL};

int ana_cmd_compare(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_compare_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "compare";
	in.unread = ANA_COLUMN_BIT(POPC_LOG_COLUMN_X_TRUE); /* the summary has no true position */
	popc_chatter_config cc;
	popc_chatter_config_defaults(&cc);
	ana_format fmt = ANA_TEXT;
	double late_from = -1.0;
	int c, rc = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_FORMAT:
			if (ana_format_from_name(optarg, &fmt) != 0) {
				fprintf(stderr, "popc-analyze compare: --format '%s': text, csv, markdown or json\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case OPT_LATE: {
			if (popc_parse_double_text(optarg, &late_from) != 0 || late_from < 0) {
				fprintf(stderr, "popc-analyze compare: --late-from '%s': a time >= 0 s\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		}
		case OPT_THRESHOLD:
			if ((rc = ana_threshold_option(&cc, optarg, "compare")) != 0)
				goto out;
			break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "compare")) != 0)
				goto out;
			break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc-analyze compare: missing LOG\n");
		popc_help_hint(argv[0], "options");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	/* the log column tells the logs apart: a/improved.csv and b/improved.csv
	 * are a/improved and b/improved, not improved twice */
	char (*names)[ANA_LOG_NAME_MAX] = malloc((size_t)(argc - optind) * sizeof *names);
	if (!names || ana_log_names(argv + optind, argc - optind, names) != 0) {
		fprintf(stderr, "popc-analyze compare: out of memory\n");
		free(names);
		rc = POPC_EXIT_RUN_FAILED;
		goto out;
	}
	/* every log first: teleoperation logs have their own table (two ports,
	 * drift, tracking), and one table cannot hold both kinds */
	const int n_logs = argc - optind;
	ana_summary *all = calloc((size_t)n_logs, sizeof *all);
	int *ok = calloc((size_t)n_logs, sizeof *ok);
	if (!all || !ok) {
		fprintf(stderr, "popc-analyze compare: out of memory\n");
		free(all);
		free(ok);
		free(names);
		rc = POPC_EXIT_RUN_FAILED;
		goto out;
	}
	int first_tele = -1, first_port = -1;
	for (int i = 0; i < n_logs; i++) {
		popc_error err;
		int st = ana_summarize(argv[optind + i], &in, &cc, late_from, &all[i], NULL, NULL, &err);
		if (st) {
			rc = ana_fail("compare", st, &err);
			continue;
		}
		ok[i] = 1;
		if (all[i].teleop && first_tele < 0)
			first_tele = i;
		if (!all[i].teleop && first_port < 0)
			first_port = i;
	}
	if (first_tele >= 0 && first_port >= 0) {
		fprintf(stderr,
			"popc-analyze compare: %s is a teleoperation log (teleop.architecture = %s) and "
			"%s a one-port log: compare one kind at a time (docs/TELEOPERATION.md, "
			"\"Analysing a log\")\n",
			argv[optind + first_tele],
			popc_teleop_architecture_names[all[first_tele].tele_scene.tele_arch],
			argv[optind + first_port]);
		rc = POPC_EXIT_USAGE;
	} else if (first_tele >= 0) {
		char **lognames = calloc((size_t)n_logs, sizeof *lognames);
		const ana_tele_summary **ts = calloc((size_t)n_logs, sizeof *ts);
		if (!lognames || !ts) {
			rc = POPC_EXIT_RUN_FAILED;
		} else {
			for (int i = 0; i < n_logs; i++) {
				lognames[i] = names[i];
				ts[i] = ok[i] ? &all[i].tele : NULL;
			}
			if (ana_tele_table(stdout, (int)fmt, lognames, ts, n_logs) != 0) {
				fprintf(stderr, "popc-analyze compare: out of memory\n");
				rc = POPC_EXIT_RUN_FAILED;
			}
		}
		free(lognames);
		free(ts);
	} else {
		ana_summary_print_header(stdout, fmt);
		for (int i = optind; i < argc; i++) {
			if (!ok[i - optind])
				continue;
			ana_summary s = all[i - optind];
			snprintf(s.log, sizeof s.log, "%s", names[i - optind]);
			if (!s.has_pc_force) {
				popc_error why;
				ana_no_pc_force(&why, argv[i]);
				fprintf(stderr, "popc-analyze compare: note: %s; its PC and chatter columns%s are n/a\n",
					why.msg, s.has_w ? "" : " and W - E_ref");
			} else if (!ana_chatter_checked(&s)) {
				popc_error why;
				ana_chatter_too_short(&why, argv[i], &s);
				fprintf(stderr, "popc-analyze compare: note: %s; its chatter columns are n/a\n",
					why.msg);
			}
			if (!ana_lc_checked(&s)) {
				popc_error why;
				ana_lc_too_short(&why, argv[i], &s);
				fprintf(stderr,
					"popc-analyze compare: note: %s; its limit-cycle columns are n/a\n",
					why.msg);
			}
			ana_summary_print_row(stdout, fmt, &s);
		}
	}
	free(all);
	free(ok);
	free(names);
	if (fflush(stdout) != 0)
		rc = POPC_EXIT_USAGE;
out:
	ana_input_free(&in);
	return rc;
}
