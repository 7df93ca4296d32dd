/* popc-analyze energy: recompute the passivity observer W and the reference
 * energy E_ref from a log's positions and forces with each observer
 * definition of the seed, through the library's popc_observer_* (the code
 * that ran online), and compare with the logged W and E_ref. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "popc/core/tdpa_drift.h"
#include "popc/core/teleop.h"
#include "popc/programs/table_out.h"
#include "popc/programs/usage_hint.h"

typedef enum definition {
	DEF_ONLINE,
	DEF_EQ3,
	DEF_EQ2,
	DEF_FILTERED,
	DEF_IGNORE,
	DEF_IGNORE_UNDO,
	DEF_COUNT
} definition;

static const struct {
	const char *name, *what;
} defs[DEF_COUNT] = {
	{"online", "the observer the log's variant ran online (one of the below)"},
	{"eq3", "seed eq. 3, held force: W(k) = W(k-1) + f_c(k-1) (x(k) - x(k-1))"},
	{"eq2", "seed eq. 2, backward velocity: W(k) = W(k-1) + T f_c(k) v(k), v(k) = dx(k)/T"},
	{"filtered", "eq. 2 with the logged velocity (filtered-velocity): W += f_c(k-1) v(k) T"},
	{"ignore", "Table I: one-count reversal energy ignored, Prev_fc = f_e(k) (literal)"},
	{"ignore-undo", "Table I with Prev_fc = f_c(k-1): a reversal undoes the last increment"},
};

static void usage(FILE *f)
{
	fputs("usage: popc-analyze energy [options] LOG...\n"
	      "\n"
	      "Recomputes the passivity observer W and the reference energy E_ref from each\n"
	      "log's positions (x, count), velocity (v) and forces (f_e, f_c) with the\n"
	      "library's observer, for each observer definition, and reports the largest\n"
	      "difference from the logged W and E_ref (0 for popc's own logs with 'online').\n"
	      "Missing columns are derived: v as the backward difference, f_e from the\n"
	      "environment (--set environment.*), f_c as f_e + f_pc. W needs the command\n"
	      "force: a log with neither f_c nor f_pc is an error (map one with --column).\n"
	      "\n"
	      "observer definitions (E_ref is always the trapezoid of f_e over dx):\n",
	      f);
	for (int i = 0; i < DEF_COUNT; i++)
		fprintf(f, "  %-12s %s\n", defs[i].name, defs[i].what);
	fputs("\n"
	      "  --observer NAME          a definition above (repeatable; default: all)\n"
	      "  --format text|csv|json   summary format (default text); json: one object\n"
	      "                           per row on one line, the CSV's names and digits\n"
	      "  -o, --output FILE        also write the recomputed columns of one LOG as CSV:\n"
	      "                           t,x,f_c,W_logged,E_ref_logged,E_ref,W_<observer>...\n"
	      "                           ending with '# stop = completed', or with\n"
	      "                           '# stop = input error' after the rows read before\n"
	      "                           bad input\n"
	      "  --check                  exit 1 unless 'online' equals the logged W and E_ref\n"
	      "                           bit for bit on every row\n"
	      "  --allow-uneven           accept a log without a rate whose time steps are\n"
	      "                           uneven (refused by default, as by every verb). Only\n"
	      "                           definitions that do not use the period T are computed:\n"
	      "                           eq3, eq2, ignore, ignore-undo, and online when the\n"
	      "                           variant ran one of them; 'filtered' (W += f_c v T) is\n"
	      "                           left out, or refused when asked for by --observer; a\n"
	      "                           log whose E_ref uses T (f_e derived with damping from\n"
	      "                           v = dx/T) is refused\n" ANA_INPUT_HELP
	      "  -h, --help               this help\n"
	      "\n"
	      "Exit status: 0 done, 1 --check found a difference, 2 bad usage or input.\n",
	      f);
	fputs(ANA_FOREIGN_HELP, f); /* its own string: C99 promises 4095 characters */
}

enum { OPT_OBSERVER = 256, OPT_FORMAT, OPT_CHECK, OPT_ALLOW_UNEVEN };

static const popc_option energy_options[] = {
	{"observer", 0, OPT_OBSERVER, "online|eq3|eq2|filtered|ignore|ignore-undo"},
	{"format", 0, OPT_FORMAT, "text|csv|json"},
	{"output", 'o', 'o', "FILE"},
	{"check", 0, OPT_CHECK, NULL},
	{"allow-uneven", 0, OPT_ALLOW_UNEVEN, NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const ana_energy_opts[] = {energy_options, ana_input_option_table, NULL};

typedef struct energy_state {
	definition def;
	popc_observer obs;
	double max_dW_J, max_dE_J;
	long long mismatches;     /* rows whose W or E_ref differ in any bit */
	double wme_min_J;
} energy_state;

static int same_bits(double a, double b)
{
	return memcmp(&a, &b, sizeof a) == 0;
}

static void observer_for(const ana_log *l, definition d, popc_observer *o);

/* Whether definition d of this log uses the period T. Only the filtered
 * observer multiplies by it (W += f_c(k-1) v(k) T, seed eq. 2 with the FOAW
 * velocity); eq3, ignore and ignore-undo sum f_c dx, and eq2 as computed here
 * is f_c(k) dx(k) (T v = dx with the backward velocity). */
static int uses_period(const ana_log *l, definition d)
{
	popc_observer o;
	observer_for(l, d, &o);
	return o.variant == POPC_VARIANT_FILTERED_VELOCITY;
}

static void observer_for(const ana_log *l, definition d, popc_observer *o)
{
	popc_variant v = POPC_VARIANT_REF_ENERGY;
	popc_ignore_mode m = POPC_IGNORE_LITERAL;
	switch (d) {
	case DEF_ONLINE: ana_online_observer(&l->scene, &v, &m); break;
	case DEF_EQ3:
	case DEF_EQ2: v = POPC_VARIANT_REF_ENERGY; break;
	case DEF_FILTERED: v = POPC_VARIANT_FILTERED_VELOCITY; break;
	case DEF_IGNORE: v = POPC_VARIANT_IGNORE; break;
	case DEF_IGNORE_UNDO:
		v = POPC_VARIANT_IGNORE;
		m = POPC_IGNORE_UNDO;
		break;
	default: break;
	}
	popc_observer_init(o, v, m);
}

/* One tick of one definition, with the library's observer. The period it
 * multiplies (filtered only): the measured step under --jitter (the energy
 * that flowed, f_c v dt), except for 'online', which reproduces the observer
 * that ran on the nominal T. */
static void step(energy_state *s, const ana_log *l, const ana_row *row)
{
	const popc_tick *t = &row->tick;
	const double T = s->def == DEF_ONLINE ? l->period_s : row->step_s;
	popc_observation ob;
	if (s->def == DEF_EQ2) {
		/* eq. 2 pairs f(t_k) with v(t_k): store f_c(k) as the force the next
		 * update multiplies, before the update (dcount 0: no Table I memory) */
		popc_observation none = {0.0, 0, 0u};
		popc_observer_commit(&s->obs, &none, t->f_e_N, t->f_c_N);
		popc_observer_update(&s->obs, t->x_m, t->count, t->v_mps, T, t->f_e_N, &ob);
		return;
	}
	popc_observer_update(&s->obs, t->x_m, t->count, t->v_mps, T, t->f_e_N, &ob);
	popc_observer_commit(&s->obs, &ob, t->f_e_N, t->f_c_N);
}

/* An admittance log (docs/ADMITTANCE.md): W recomputed from the force count
 * and reading, the VE's velocity and the PC's with the observer that ran
 * online (popc_admittance_observer_*, the same code), each row's W against
 * the logged one bit for bit. Takes over l (closes it). */
static int energy_admittance(ana_log *l, const char *path, popc_table_out *table, int check,
			     int *check_failed)
{
	popc_error err;
	if (l->c_f_count < 0 || l->c_f_meas < 0 || l->c_v_ve < 0 || l->c_v_pc < 0 || l->c_W < 0) {
		ana_log_close(l);
		fprintf(stderr,
			"popc-analyze energy: %s: device.causality = admittance needs the columns "
			"f_count, f_meas, v_ve, v_pc and W\n",
			path);
		return POPC_EXIT_USAGE;
	}
	popc_admittance_observer o;
	popc_admittance_observer_init(&o, l->scene.adm_variant);
	const double T = l->period_s;
	long long rows = 0, mismatches = 0;
	double max_dW = 0.0, W_min = 0.0;
	ana_row row;
	int st;
	while ((st = ana_log_next(l, &row, &err)) == 1) {
		popc_admittance_observation ob;
		popc_admittance_observer_update(&o, row.adm_n, row.adm_f_N, row.adm_v_ve_mps, T, &ob);
		popc_admittance_observer_commit(&o, row.adm_f_N, row.adm_v_pc_mps, T);
		if (!isfinite(o.W_J)) {
			st = popc_error_set(&err, POPC_ERR_INVALID,
					    "%s:%lld: the admittance W overflows a double here", path,
					    row.line);
			break;
		}
		if (o.W_J < W_min)
			W_min = o.W_J;
		double dW = fabs(o.W_J - row.W_logged_J);
		if (dW > max_dW)
			max_dW = dW;
		if (!same_bits(o.W_J, row.W_logged_J))
			mismatches++;
		rows++;
	}
	char lname[sizeof l->name];
	snprintf(lname, sizeof lname, "%s", l->name);
	ana_log_close(l);
	if (st < 0)
		return ana_fail("energy", st, &err);
	char name[64];
	snprintf(name, sizeof name, "online=%s", popc_admittance_variant_name(o.variant));
	if (table) {
		FILE *c = popc_table_out_row(table);
		ana_put_csv_text(c, lname);
		fprintf(c, ",%s,%lld,", name, rows);
		ana_put_double(c, o.W_J);
		fputs(",0.0,", c);
		ana_put_double(c, o.W_J);
		fputc(',', c);
		ana_put_double(c, W_min);
		fputc(',', c);
		ana_put_double(c, max_dW);
		fprintf(c, ",0.0,%lld\n", mismatches);
	} else {
		printf("%-24s %-20s W_end %11.4e  min %11.4e  max|dW| %.3g  rows differing %lld\n",
		       lname, name, o.W_J, W_min, max_dW, mismatches);
	}
	if (check && mismatches)
		*check_failed = 1;
	return 0;
}

/* A teleoperation log (docs/TELEOPERATION.md, "Checking a log"): each
 * port's tick recomputed from the logged cells with the function that ran
 * online (core/teleop.h: the received energy, the output u against the
 * conjugate c), its correction, output, observer and energy split compared
 * bit for bit; and the two-port condition checked at every row. Reads the
 * file again with its own reader (the columns are the teleop set's, by
 * name). Takes over l (closes it). Position-position: the slave's port
 * from its coupling, recomputed from the cells too (xs_cmd and vs_rx the
 * master's position and velocity the slave holds, v_s the backward
 * difference of xs as online: core/teleop.h). */
#define TELE_COLS(X)                                                                             \
	X(f_e) X(v) X(f_pc) X(f_c) X(W) X(fs) X(vs_rx) X(vs_pc) X(vs_c) X(Ws) X(Em_in) X(Em_out) \
	X(Em_rx) X(Es_in) X(Es_out) X(Es_rx) X(xs) X(xs_cmd)
enum {
#define TELE_ENUM(n) TC_##n,
	TELE_COLS(TELE_ENUM)
#undef TELE_ENUM
	TC_COUNT
};

static int energy_teleop(ana_log *l, const char *path, popc_table_out *table, int check,
			 int *check_failed)
{
	popc_error err;
	const popc_scene sc = l->scene;
	char lname[sizeof l->name];
	snprintf(lname, sizeof lname, "%s", l->name);
	ana_log_close(l);
	static const char *const names[TC_COUNT] = {
#define TELE_NAME(n) #n,
		TELE_COLS(TELE_NAME)
#undef TELE_NAME
	};
	popc_log_reader r;
	int st = popc_log_reader_open(&r, path, NULL, &err);
	if (st)
		return ana_fail("energy", st, &err);
	int col[TC_COUNT];
	for (int i = 0; i < TC_COUNT; i++)
		if ((col[i] = popc_log_reader_column(&r, names[i])) < 0) {
			popc_log_reader_close(&r);
			fprintf(stderr,
				"popc-analyze energy: %s: teleop.architecture = %s needs the column %s "
				"(docs/TELEOPERATION.md)\n",
				path, popc_teleop_architecture_names[sc.tele_arch], names[i]);
			return POPC_EXIT_USAGE;
		}
	/* teleop.drift: the slave's compensation from the master position it
	 * held, its position command and whether it held a packet yet */
	static const char *const drift_names[] = {"xm_rx", "xs_cmd", "fwd_age", "vs_dc"};
	int dcol[4] = {-1, -1, -1, -1};
	const popc_drift_config drift = {sc.tele_drift, sc.tele_drift_max_mps, sc.tele_drift_ratio};
	for (int i = 0; drift.law != POPC_DRIFT_OFF && i < 4; i++)
		if ((dcol[i] = popc_log_reader_column(&r, drift_names[i])) < 0) {
			popc_log_reader_close(&r);
			fprintf(stderr,
				"popc-analyze energy: %s: teleop.drift = %s needs the column %s "
				"(docs/TELEOPERATION.md)\n",
				path, popc_drift_law_names[sc.tele_drift], drift_names[i]);
			return POPC_EXIT_USAGE;
		}
	const double T = popc_scene_period_s(&sc);
	popc_tdpa_side m, sl;
	popc_tdpa_side_init_excess(&m, sc.tele_master_bound_N, sc.tele_excess_J);
	const int pp = sc.tele_arch == POPC_TELEOP_POSITION_POSITION;
	popc_tdpa_side_init_excess(&sl, pp ? sc.tele_slave_bound_N : sc.tele_slave_bound_mps,
				   sc.tele_excess_J);
	double xs_prev = 0.0;
	long long rows = 0, mismatches = 0, broken = 0, first_broken = 0, first_mismatch = 0;
	double margin_min[2] = {0.0, 0.0};
	double v[POPC_LOG_MAX_COLUMNS];
	while ((st = popc_log_reader_next(&r, v, &err)) == 1) {
		double c[TC_COUNT];
		for (int i = 0; i < TC_COUNT; i++)
			c[i] = v[col[i]];
		popc_tdpa_step pm = popc_teleop_port(&m, c[TC_Em_rx], c[TC_f_e], -c[TC_v], T, sc.tele_tdpa);
		popc_tdpa_step ps;
		double v_dc = 0.0;
		if (pp) {
			const double v_s = rows ? (c[TC_xs] - xs_prev) / T : 0.0;
			const double F_S = popc_teleop_coupling_N(sc.tele_coupling_K_Npm, sc.tele_coupling_B_Nspm,
								  c[TC_xs_cmd], c[TC_xs], c[TC_vs_rx], v_s);
			ps = popc_teleop_port(&sl, c[TC_Es_rx], F_S, v_s, T, sc.tele_tdpa);
		} else if (drift.law != POPC_DRIFT_OFF) {
			ps = popc_drift_port(&sl, &drift, c[TC_Es_rx], c[TC_vs_rx], -c[TC_fs], T, sc.tele_tdpa,
					     v[dcol[2]] < 0.0 ? (double)NAN : v[dcol[0]], v[dcol[1]], &v_dc);
		} else {
			ps = popc_teleop_port(&sl, c[TC_Es_rx], c[TC_vs_rx], -c[TC_fs], T, sc.tele_tdpa);
		}
		xs_prev = c[TC_xs];
		const double mine[] = {pm.d, pm.u, pm.W_J, popc_energy_flow_in(&m.flow),
				       popc_energy_flow_out(&m.flow), ps.d, ps.u, ps.W_J,
				       popc_energy_flow_in(&sl.flow), popc_energy_flow_out(&sl.flow)};
		const int theirs[] = {TC_f_pc, TC_f_c, TC_W, TC_Em_in, TC_Em_out,
				      TC_vs_pc, TC_vs_c, TC_Ws, TC_Es_in, TC_Es_out};
		int differ = drift.law != POPC_DRIFT_OFF && !same_bits(v_dc + 0.0, v[dcol[3]] + 0.0);
		for (size_t i = 0; i < sizeof theirs / sizeof theirs[0]; i++)
			differ |= !same_bits(mine[i] + 0.0, c[theirs[i]] + 0.0); /* -0 is 0 */
		if (differ && !mismatches++)
			first_mismatch = r.lineno;
		/* the condition on the recomputed sums (the logged ones when equal) */
		const double mg[2] = {popc_teleop_margin_J(&m), popc_teleop_margin_J(&sl)};
		for (int i = 0; i < 2; i++)
			if (mg[i] < margin_min[i])
				margin_min[i] = mg[i];
		if (!popc_teleop_condition_holds(m.remote_in_J + m.excess_J, popc_energy_flow_out(&m.flow)) ||
		    !popc_teleop_condition_holds(sl.remote_in_J + sl.excess_J,
						 popc_energy_flow_out(&sl.flow))) {
			if (!broken++)
				first_broken = r.lineno;
		}
		rows++;
	}
	popc_log_reader_close(&r);
	if (st < 0)
		return ana_fail("energy", st, &err);
	if (table) {
		FILE *o = popc_table_out_row(table);
		ana_put_csv_text(o, lname);
		fprintf(o, ",online=teleop,%lld,", rows);
		ana_put_double(o, popc_energy_flow_out(&m.flow));
		fputs(",0.0,", o);
		ana_put_double(o, margin_min[0]);
		fputc(',', o);
		ana_put_double(o, margin_min[1]);
		fprintf(o, ",0.0,0.0,%lld\n", mismatches + broken);
	} else {
		printf("%-24s %-20s rows %lld  rows differing %lld  two-port condition broken on %lld "
		       "rows  min margin master %.3g J slave %.3g J\n",
		       lname, "online=teleop", rows, mismatches, broken, margin_min[0], margin_min[1]);
		if (mismatches)
			printf("  first differing row: line %lld\n", first_mismatch);
		if (broken)
			printf("  first row breaking the condition: line %lld\n", first_broken);
	}
	if (check && (mismatches || broken))
		*check_failed = 1;
	return 0;
}

static int energy_one(const char *path, const ana_input_options *in, const int *want_in,
		      int n_want_in, int observers_given, popc_table_out *table, const char *out_path,
		      int check, int *check_failed)
{
	ana_log l;
	popc_error err;
	int st = ana_log_open(&l, path, in, &err);
	if (st)
		return ana_fail("energy", st, &err);
	if (l.scene.causality == POPC_CAUSALITY_ADMITTANCE) {
		if (out_path || observers_given)
			fprintf(stderr, "popc-analyze energy: note: %s: an admittance log: the online "
					"observer only, no -o (docs/ADMITTANCE.md)\n",
				path);
		return energy_admittance(&l, path, table, check, check_failed);
	}
	if (l.scene.tele_arch != POPC_TELEOP_OFF) {
		if (out_path || observers_given)
			fprintf(stderr, "popc-analyze energy: note: %s: a teleoperation log: the online "
					"ports only, no -o (docs/TELEOPERATION.md)\n",
				path);
		return energy_teleop(&l, path, table, check, check_failed);
	}
	int want[DEF_COUNT], n_want = 0;
	const int uneven = in->allow_uneven && l.period_from_time; /* steps not checked */
	if (uneven && l.c_f_e < 0 && l.c_v < 0 && l.env.damping_Nspm != 0.0) {
		/* E_ref is the trapezoid of f_e over dx, and a derived f_e has the
		 * damping term B v with v = dx/T */
		ana_log_close(&l);
		fprintf(stderr,
			"popc-analyze energy: %s: --allow-uneven: E_ref uses the period here: f_e is "
			"derived from the environment with damping %g N s/m times v = dx/T (log f_e "
			"or v, or give the rate with --set run.rate=HZ)\n",
			path, l.env.damping_Nspm);
		return POPC_EXIT_USAGE;
	}
	for (int i = 0; i < n_want_in; i++) {
		definition d = (definition)want_in[i];
		if (uneven && uses_period(&l, d)) {
			if (observers_given || (check && d == DEF_ONLINE)) {
				ana_log_close(&l);
				fprintf(stderr,
					"popc-analyze energy: %s: --allow-uneven: the observer '%s'%s "
					"uses the period T (W += f_c v T), which uneven time steps do not "
					"have\n",
					path, defs[d].name, d == DEF_ONLINE ? " (filtered, the log's variant)" : "");
				return POPC_EXIT_USAGE;
			}
			fprintf(stderr,
				"popc-analyze energy: note: %s: --allow-uneven: observer '%s' left out: "
				"it uses the period T\n",
				path, defs[d].name);
			continue;
		}
		want[n_want++] = (int)d;
	}
	/* --jitter: only an observer on the nominal T ('online' of a
	 * filtered-velocity log: W += f_c v T as it ran) needs the steps within
	 * the tolerance; the others use the measured steps, or none */
	l.check_jitter = 0;
	for (int i = 0; i < n_want; i++)
		if (want[i] == DEF_ONLINE && uses_period(&l, DEF_ONLINE))
			l.check_jitter = l.jitter > 0.0;
	if (!l.has_pc_force) {
		/* W is the sum of the command force over the motion: with neither f_c
		 * nor f_pc it would be the environment's energy, E_ref, relabelled */
		ana_log_close(&l);
		ana_no_pc_force(&err, path);
		return ana_fail("energy", POPC_ERR_INVALID, &err);
	}
	energy_state s[DEF_COUNT];
	for (int i = 0; i < n_want; i++) {
		memset(&s[i], 0, sizeof s[i]);
		s[i].def = (definition)want[i];
		s[i].wme_min_J = (double)INFINITY;
		observer_for(&l, s[i].def, &s[i].obs);
	}
	/* A definition whose observer steps by an earlier one's rule
	 * (popc_observer_same_rule: 'online' of a ref-energy log is eq3) is not
	 * stepped again: it takes the earlier one's state, row by row for -o and
	 * at the end for the table, the same numbers, as the observer reads
	 * nothing else. Not for filtered-velocity (its T differs between
	 * 'online' and 'filtered', step()) nor eq2 (stepped in its own order). */
	int twin[DEF_COUNT];
	for (int i = 0; i < n_want; i++) {
		twin[i] = -1;
		if (s[i].def == DEF_EQ2 || s[i].obs.variant == POPC_VARIANT_FILTERED_VELOCITY)
			continue;
		for (int j = 0; j < i && twin[i] < 0; j++)
			if (twin[j] < 0 && s[j].def != DEF_EQ2 &&
			    popc_observer_same_rule(&s[j].obs, &s[i].obs))
				twin[i] = j;
	}
	const int logged = l.c_W >= 0 && l.c_E_ref >= 0;
	if (check && !logged) {
		ana_log_close(&l);
		fprintf(stderr, "popc-analyze energy: %s: --check needs the logged W and E_ref columns\n",
			path);
		return POPC_EXIT_USAGE;
	}
	FILE *out = NULL;
	if (out_path) {
		char *self[1] = {(char *)path};
		if (ana_output_is_input(out_path, self, 1) >= 0) {
			ana_log_close(&l);
			fprintf(stderr,
				"popc-analyze energy: -o %s is the input log %s: refusing to overwrite it\n",
				out_path, path);
			return POPC_EXIT_USAGE;
		}
		out = strcmp(out_path, "-") == 0 ? stdout : fopen(out_path, "w");
		if (!out) {
			ana_log_close(&l);
			fprintf(stderr, "popc-analyze energy: %s: cannot open for writing\n", out_path);
			return POPC_EXIT_USAGE;
		}
		fprintf(out, "# popc-analyze energy of %s\n# period = %.17g\n", path, l.period_s);
		ana_foreign_provenance(out, &in->foreign);
		if (uneven)
			fputs("# allow_uneven = the time steps were not checked; no column below uses "
			      "the period\n",
			      out);
		fputs("t,x,f_c,W_logged,E_ref_logged,E_ref", out);
		for (int i = 0; i < n_want; i++)
			fprintf(out, ",W_%s", defs[s[i].def].name);
		fputc('\n', out);
	}
	ana_row row;
	long long rows = 0;
	while ((st = ana_log_next(&l, &row, &err)) == 1) {
		const popc_tick *t = &row.tick;
		for (int i = 0; i < n_want; i++) {
			energy_state *e = &s[i];
			if (twin[i] >= 0)
				continue;
			step(e, &l, &row);
			double W = e->obs.W_J, E = e->obs.E_ref_J;
			if (!isfinite(W) || !isfinite(E) || !isfinite(W - E)) {
				/* sums of finite products beyond a double: say where,
				 * never print inf or NaN as a result */
				st = popc_error_set(&err, POPC_ERR_INVALID,
						    "%s:%lld: observer %s: W, E_ref or W - E_ref overflows "
						    "a double here (the sums of f_c dx and f_e dx; f_c %g N, "
						    "x %g m)",
						    path, row.line, defs[e->def].name, t->f_c_N, t->x_m);
				break;
			}
			if (W - E < e->wme_min_J)
				e->wme_min_J = W - E;
			if (logged) {
				double dW = fabs(W - row.W_logged_J), dE = fabs(E - row.E_ref_logged_J);
				if (dW > e->max_dW_J)
					e->max_dW_J = dW;
				if (dE > e->max_dE_J)
					e->max_dE_J = dE;
				if (!same_bits(W, row.W_logged_J) || !same_bits(E, row.E_ref_logged_J))
					e->mismatches++;
			}
		}
		if (st < 0)
			break;
		if (out) {
			ana_put_double(out, t->t_s);
			fputc(',', out);
			ana_put_double(out, t->x_m);
			fputc(',', out);
			ana_put_double(out, t->f_c_N);
			fputc(',', out);
			if (logged) {
				ana_put_double(out, row.W_logged_J);
				fputc(',', out);
				ana_put_double(out, row.E_ref_logged_J);
			} else {
				fputs("nan,nan", out);
			}
			fputc(',', out);
			ana_put_double(out, s[0].obs.E_ref_J);
			for (int i = 0; i < n_want; i++) {
				fputc(',', out);
				ana_put_double(out, s[twin[i] >= 0 ? twin[i] : i].obs.W_J);
			}
			fputc('\n', out);
		}
		rows++;
	}
	/* how the rows end, as a popc log ends: a file cut short by bad input
	 * keeps every row written so far and says so, so it cannot pass for a
	 * complete recompute of a shorter log */
	if (out)
		fprintf(out, "# stop = %s\n",
			st < 0 ? "input error" : l.unfinished ? "input unfinished" : "completed");
	int write_failed = 0;
	if (out && out != stdout)
		write_failed = fclose(out) != 0;
	else if (out)
		write_failed = fflush(out) != 0;
	ana_log_close(&l);
	if (st < 0)
		return ana_fail("energy", st, &err);
	if (write_failed) {
		fprintf(stderr, "popc-analyze energy: %s: write failed\n", out_path);
		return POPC_EXIT_USAGE;
	}
	for (int i = 0; i < n_want; i++)
		if (twin[i] >= 0) {
			const definition d = s[i].def;
			s[i] = s[twin[i]];
			s[i].def = d;
		}
	FILE *f = out == stdout ? stderr : stdout;
	for (int i = 0; i < n_want; i++) {
		const energy_state *e = &s[i];
		const char *name = defs[e->def].name;
		char real[32] = "";
		if (e->def == DEF_ONLINE) {
			popc_observer o;
			observer_for(&l, DEF_ONLINE, &o);
			/* every other variant logs seed eq. 3's W: pc-off-reversals,
			 * energy-bounding (its reservoir is that W) and windowed-po (its
			 * window sums eq. 3's increments; the W column is the whole sum) */
			definition d = o.variant == POPC_VARIANT_FILTERED_VELOCITY ? DEF_FILTERED
				       : o.variant == POPC_VARIANT_IGNORE ||
						 o.variant == POPC_VARIANT_IMPROVED
					       ? (o.ignore_mode == POPC_IGNORE_UNDO ? DEF_IGNORE_UNDO
										    : DEF_IGNORE)
					       : DEF_EQ3;
			snprintf(real, sizeof real, "online=%s", defs[d].name);
			name = real;
			if (check && e->mismatches)
				*check_failed = 1;
		}
		double wme_end = e->obs.W_J - e->obs.E_ref_J;
		if (table) {
			FILE *c = popc_table_out_row(table);
			ana_put_csv_text(c, l.name);
			fprintf(c, ",%s,%lld,", name, rows);
			ana_put_double(c, e->obs.W_J);
			fputc(',', c);
			ana_put_double(c, e->obs.E_ref_J);
			fputc(',', c);
			ana_put_double(c, wme_end);
			fputc(',', c);
			ana_put_double(c, isfinite(e->wme_min_J) ? e->wme_min_J : 0.0);
			if (logged) {
				fputc(',', c);
				ana_put_double(c, e->max_dW_J);
				fputc(',', c);
				ana_put_double(c, e->max_dE_J);
				fprintf(c, ",%lld\n", e->mismatches);
			} else {
				fputs(",,,\n", c);
			}
		} else {
			fprintf(f, "%-24s %-20s W_end %11.4e  E_ref_end %11.4e  W-E_ref end %11.4e min %11.4e",
				l.name, name, e->obs.W_J, e->obs.E_ref_J, wme_end,
				isfinite(e->wme_min_J) ? e->wme_min_J : 0.0);
			if (logged)
				fprintf(f, "  max|dW| %.3g  max|dE_ref| %.3g  rows differing %lld\n",
					e->max_dW_J, e->max_dE_J, e->mismatches);
			else
				fputs("  (no logged W, E_ref)\n", f);
		}
	}
	return 0;
}

int ana_cmd_energy(int argc, char **argv)
{
	struct option opts[ANA_MAX_OPTIONS];
	char shorts[2 * ANA_MAX_OPTIONS];
	ana_getopt_tables(ana_energy_opts, opts, shorts);
	ana_input_options in;
	memset(&in, 0, sizeof in);
	in.verb = "energy";
	/* the observers read the measured motion and the forces, never the
	 * simulated truth */
	in.unread = ANA_COLUMN_BIT(POPC_LOG_COLUMN_X_TRUE) | ANA_COLUMN_BIT(POPC_LOG_COLUMN_E_PORT);
	int want[DEF_COUNT], n_want = 0, check = 0, c, rc = 0;
	ana_format fmt = ANA_TEXT;
	const char *out_path = NULL;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_OBSERVER: {
			int found = -1;
			for (int i = 0; i < DEF_COUNT; i++)
				if (strcmp(optarg, defs[i].name) == 0)
					found = i;
			if (found < 0) {
				fprintf(stderr, "popc-analyze energy: --observer '%s': unknown (see --help)\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			int dup = 0;
			for (int i = 0; i < n_want; i++)
				dup |= want[i] == found;
			if (!dup)
				want[n_want++] = found;
			break;
		}
		case OPT_FORMAT:
			if (ana_format_from_name(optarg, &fmt) != 0 || fmt == ANA_MARKDOWN) {
				fprintf(stderr, "popc-analyze energy: --format '%s': text, csv or json\n",
					optarg);
				rc = POPC_EXIT_USAGE;
				goto out;
			}
			break;
		case 'o': out_path = optarg; break;
		case OPT_CHECK: check = 1; break;
		case OPT_ALLOW_UNEVEN: in.allow_uneven = 1; break;
		case 'h': usage(stdout); goto out;
		ANA_INPUT_OPTION_CASES:
			if ((rc = ana_input_option(&in, c, optarg, "energy")) != 0)
				goto out;
			break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; goto out;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc-analyze energy: missing LOG\n");
		popc_help_hint(argv[0], "options");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	if (out_path && argc - optind != 1) {
		fprintf(stderr, "popc-analyze energy: --output takes exactly one LOG\n");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	if (out_path && (rc = ana_output_file_usable("energy", "-o", out_path)) != 0)
		goto out; /* before any log is read */
	const int observers_given = n_want > 0;
	if (n_want == 0)
		for (int i = 0; i < DEF_COUNT; i++)
			want[n_want++] = i;
	if (check) {
		int has_online = 0;
		for (int i = 0; i < n_want; i++)
			has_online |= want[i] == DEF_ONLINE;
		if (!has_online)
			want[n_want++] = DEF_ONLINE;
	}
	for (int i = 0; i < n_want; i++)
		if (want[i] == DEF_ONLINE) /* 'online' is the scene's variant's observer */
			in.uses |= ANA_USES_VARIANT;
	/* csv, and json: the CSV's rows as objects, the same cells (popc_table_out) */
	static const char *const text_columns[] = {"log", "observer", NULL};
	popc_table_out table;
	popc_table_out *tp = fmt == ANA_CSV || fmt == ANA_JSON ? &table : NULL;
	if (tp && popc_table_out_begin(tp, stdout, fmt == ANA_JSON,
				       "log,observer,rows,W_end,E_ref_end,w_minus_eref_end,"
				       "w_minus_eref_min,max_abs_dW,max_abs_dE_ref,rows_differing",
				       text_columns) != 0) {
		fprintf(stderr, "popc-analyze energy: out of memory\n");
		rc = POPC_EXIT_USAGE;
		goto out;
	}
	int check_failed = 0;
	for (int i = optind; i < argc; i++) {
		int r = energy_one(argv[i], &in, want, n_want, observers_given, tp, out_path, check,
				   &check_failed);
		if (tp && popc_table_out_flush(tp) != 0) {
			fprintf(stderr, "popc-analyze energy: out of memory\n");
			r = 2;
		}
		if (r > rc)
			rc = r;
	}
	if (tp)
		popc_table_out_end(tp);
	if (rc == 0 && check_failed)
		rc = POPC_EXIT_RUN_FAILED;
out:
	ana_input_free(&in);
	return rc;
}
