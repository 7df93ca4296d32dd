/* popc-analyze on a teleoperation log: the two ports' columns by name and
 * one summary per log (teleop_log.h; docs/TELEOPERATION.md, "Analysing a
 * log"). Memory: two rings of the longest packet age (the channel's delay
 * is at most 100,000 ticks), constant in the length of the log. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "teleop_log.h"
#include "analyze.h"
#include "popc/core/admittance.h"
#include "popc/core/sum_squares.h"
#include "popc/core/teleop.h"
#include "popc/scene/from_scene.h"
#include "popc/programs/table_out.h"

const char *const ana_tele_col_names[ANA_TC_COUNT] = {
#define ANA_TELE_NAME(n) #n,
	ANA_TELE_COLS(ANA_TELE_NAME)
#undef ANA_TELE_NAME
};

int ana_tele_open(ana_tele_log *l, const char *path, const popc_scene *sc, popc_error *err)
{
	memset(l, 0, sizeof *l);
	if (strcmp(path, "-") == 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "stdin: a teleoperation log (teleop.architecture = %s) is read "
				      "twice, its header then its two ports: give it as a file",
				      popc_teleop_architecture_names[sc->tele_arch]);
	/* position-position's slave PC is a force and its xs_cmd the master
	 * position held (docs/TELEOPERATION.md): the per-port figures here are
	 * position-force's; energy --check reads both architectures */
	if (sc->tele_arch == POPC_TELEOP_POSITION_POSITION)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.architecture = position-position: chatter, teleop, "
				      "compare, replay and report read position-force logs only (energy "
				      "--check reads both; docs/TELEOPERATION.md, \"Next\")",
				      path);
	int st = popc_log_reader_open(&l->r, path, NULL, err);
	if (st)
		return st;
	for (int i = 0; i < ANA_TC_COUNT; i++)
		if ((l->col[i] = popc_log_reader_column(&l->r, ana_tele_col_names[i])) < 0) {
			popc_log_reader_close(&l->r);
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: teleop.architecture = %s needs the column %s "
					      "(docs/TELEOPERATION.md, \"The log\")",
					      path, popc_teleop_architecture_names[sc->tele_arch],
					      ana_tele_col_names[i]);
		}
	l->scene = *sc;
	popc_environment_from_scene(&l->env, sc);
	l->period_s = popc_scene_period_s(sc);
	return 0;
}

int ana_tele_next(ana_tele_log *l, ana_tele_row *row, popc_error *err)
{
	int st = popc_log_reader_next(&l->r, l->row, err);
	if (st != 1)
		return st;
	for (int i = 0; i < ANA_TC_COUNT; i++)
		row->c[i] = l->row[l->col[i]];
	row->line = l->r.lineno;
	for (int i = 0; i < ANA_TC_COUNT; i++)
		if (!isfinite(row->c[i]))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %s: %g is no finite number",
					      l->r.path, row->line, ana_tele_col_names[i], row->c[i]);
	return 1;
}

void ana_tele_close(ana_tele_log *l)
{
	popc_log_reader_close(&l->r);
}

double ana_tele_master_scale_N(const popc_scene *sc)
{
	const double f1 = sc->env_stiffness_Npm > 0.0 ? sc->env_stiffness_Npm * sc->enc_resolution_m
						      : sc->slave_force_resolution_N;
	return POPC_ADMITTANCE_CHATTER_COUNTS * f1;
}

double ana_tele_slave_scale_mps(const popc_scene *sc)
{
	return POPC_ADMITTANCE_CHATTER_COUNTS *
	       popc_admittance_count_velocity_mps(sc->slave_force_resolution_N, sc->env_stiffness_Npm,
						  sc->slave_mass_kg, sc->slave_damping_Nspm,
						  popc_scene_period_s(sc));
}

/* A packet's age is at most the channel's longest delay (delay + jitter <=
 * 100,000 ticks, docs/TELEOPERATION.md): a ring of a power of two above it. */
#define RING 131072
#define RING_MASK (RING - 1)

/* sqrt(sum / n), 0 over no rows (not 0/0) */
static double rms(const popc_sum_squares *q, long long n)
{
	return n > 0 ? popc_sum_squares_rms(q, (double)n) : 0.0;
}

typedef struct port_acc {
	popc_sum_squares sq;
	popc_chatter det;
} port_acc;

static int port_init(port_acc *a, ana_tele_port *p, const popc_chatter_config *ccfg,
		     const ana_tele_log *l, double scale, const char *what, const char *path,
		     popc_error *err)
{
	memset(a, 0, sizeof *a);
	p->scale = scale;
	p->margin_min_J = 0.0;
	popc_chatter_config cc = *ccfg;
	cc.resolution_m = l->scene.enc_resolution_m;
	cc.pc_bound_N = scale;
	int st = popc_chatter_init(&a->det, &cc, l->period_s, &l->env, err);
	if (st) {
		char msg[POPC_ERROR_MSG_MAX];
		snprintf(msg, sizeof msg, "%s", err->msg);
		popc_error_set(err, st, "%s: the %s port's chatter detector (PC scale %g): %s", path,
			       what, scale, msg);
	}
	return st;
}

static void port_row(port_acc *a, ana_tele_port *p, double t, double x, double v, double d,
		     double W, unsigned flags, unsigned active_bit, unsigned clamped_bit,
		     double in, double out, double rx, long long k)
{
	popc_tick tk;
	memset(&tk, 0, sizeof tk);
	tk.t_s = t;
	tk.x_m = x;
	tk.v_mps = v;
	tk.f_pc_N = d;
	tk.W_J = W;
	popc_chatter_add(&a->det, &tk);
	popc_sum_squares_add(&a->sq, d);
	if (fabs(d) > p->pc_max)
		p->pc_max = fabs(d);
	p->active += (flags & active_bit) != 0;
	p->clamped += (flags & clamped_bit) != 0;
	p->in_J = in;
	p->out_J = out;
	p->rx_J = rx;
	const double margin = rx - out;
	if (k == 0 || margin < p->margin_min_J)
		p->margin_min_J = margin;
}

int ana_tele_summarize(const char *path, const popc_scene *sc, const popc_chatter_config *ccfg,
		       ana_tele_summary *s, ana_tele_row_fn on_row, void *ctx, popc_error *err)
{
	memset(s, 0, sizeof *s);
	ana_tele_log l;
	int st = ana_tele_open(&l, path, sc, err);
	if (st)
		return st;
	s->period_s = l.period_s;
	s->tdpa = sc->tele_tdpa;
	s->fwd_delay_s = sc->fwd.delay_ticks * l.period_s;
	s->bwd_delay_s = sc->bwd.delay_ticks * l.period_s;
	port_acc am, as;
	double *x_ring = malloc(RING * sizeof *x_ring), *fs_ring = malloc(RING * sizeof *fs_ring);
	if (!x_ring || !fs_ring) {
		st = popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
		goto out;
	}
	if ((st = port_init(&am, &s->m, ccfg, &l, ana_tele_master_scale_N(sc), "master", path,
			    err)) ||
	    (st = port_init(&as, &s->s, ccfg, &l, ana_tele_slave_scale_mps(sc), "slave", path,
			    err)))
		goto out;
	popc_sum_squares dq, daq, tq, taq;
	memset(&dq, 0, sizeof dq);
	daq = tq = taq = dq;
	double t0 = 0.0;
	ana_tele_row row;
	while ((st = ana_tele_next(&l, &row, err)) == 1) {
		const double *c = row.c;
		const long long k = s->ticks;
		if (k == 0)
			t0 = c[ANA_TC_t];
		s->duration_s = c[ANA_TC_t] - t0;
		x_ring[k & RING_MASK] = c[ANA_TC_x];
		fs_ring[k & RING_MASK] = c[ANA_TC_fs];
		const unsigned flags = (unsigned)c[ANA_TC_flags];
		/* the slave's velocity for the detector's sign changes: its
		 * command (the servo tracks it); its position xs */
		port_row(&am, &s->m, c[ANA_TC_t], c[ANA_TC_x], c[ANA_TC_v], c[ANA_TC_f_pc], c[ANA_TC_W],
			 flags, POPC_TELEOP_FLAG_M_ACTIVE, POPC_TELEOP_FLAG_M_CLAMPED, c[ANA_TC_Em_in],
			 c[ANA_TC_Em_out], c[ANA_TC_Em_rx], k);
		port_row(&as, &s->s, c[ANA_TC_t], c[ANA_TC_xs], c[ANA_TC_vs_c], c[ANA_TC_vs_pc],
			 c[ANA_TC_Ws], flags, POPC_TELEOP_FLAG_S_ACTIVE, POPC_TELEOP_FLAG_S_CLAMPED,
			 c[ANA_TC_Es_in], c[ANA_TC_Es_out], c[ANA_TC_Es_rx], k);
		const double ex = c[ANA_TC_x] - c[ANA_TC_xs];
		popc_sum_squares_add(&dq, ex);
		s->drift_end_m = ex;
		if (fabs(ex) > fabs(s->drift_max_m))
			s->drift_max_m = ex;
		const double ef = c[ANA_TC_f_c] + c[ANA_TC_fs];
		popc_sum_squares_add(&tq, ef);
		if (fabs(ef) > s->track_max_N)
			s->track_max_N = fabs(ef);
		const double af = c[ANA_TC_fwd_age], ab = c[ANA_TC_bwd_age];
		if (af >= 0.0 && af <= (double)k && af < RING) {
			const double exd = x_ring[(k - (long long)af) & RING_MASK] - c[ANA_TC_xs];
			popc_sum_squares_add(&daq, exd);
			s->drift_al_end_m = exd;
			if (fabs(exd) > fabs(s->drift_al_max_m))
				s->drift_al_max_m = exd;
			s->drift_al_n++;
		}
		if (ab >= 0.0 && ab <= (double)k && ab < RING) {
			const double efd = c[ANA_TC_f_c] + fs_ring[(k - (long long)ab) & RING_MASK];
			popc_sum_squares_add(&taq, efd);
			if (fabs(efd) > s->track_al_max_N)
				s->track_al_max_N = fabs(efd);
			s->track_al_n++;
		}
		s->ticks++;
		if (on_row)
			on_row(ctx, &row, s);
	}
	if (st < 0)
		goto out;
	st = 0;
	popc_chatter_finish(&am.det, &s->m.chatter);
	popc_chatter_finish(&as.det, &s->s.chatter);
	s->m.pc_rms = rms(&am.sq, s->ticks);
	s->s.pc_rms = rms(&as.sq, s->ticks);
	s->drift_rms_m = rms(&dq, s->ticks);
	s->drift_al_rms_m = rms(&daq, s->drift_al_n);
	s->track_rms_N = rms(&tq, s->ticks);
	s->track_al_rms_N = rms(&taq, s->track_al_n);
	/* differences of finite cells that a double cannot hold (x = 1e308,
	 * xs = -1e308) are refused by name: no inf reaches a summary */
	const double fig[] = {s->duration_s, s->drift_end_m, s->drift_max_m, s->drift_rms_m,
			      s->drift_al_end_m, s->drift_al_max_m, s->drift_al_rms_m,
			      s->track_rms_N, s->track_max_N, s->track_al_rms_N, s->track_al_max_N,
			      s->m.margin_min_J, s->s.margin_min_J, s->m.pc_rms, s->s.pc_rms,
			      s->m.chatter.chatter_s, s->s.chatter.chatter_s};
	for (size_t i = 0; i < sizeof fig / sizeof fig[0]; i++)
		if (!isfinite(fig[i])) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s: a drift, force-tracking or margin figure overflows a "
					    "double, from finite rows (%lld ticks)",
					    path, s->ticks);
			break;
		}
out:
	free(x_ring);
	free(fs_ring);
	ana_tele_close(&l);
	return st;
}

/* The table: one row per log. Chatter cells are empty where the port was not
 * checked (shorter than a window); "s" is the slave port, "m" the master. */
const char *const ana_tele_table_columns[] = {
	"log", "tdpa", "fwd_delay_s", "bwd_delay_s", "ticks", "duration_s",
	"m_pc_active", "m_pc_rms_N", "m_pc_max_N", "m_clamped", "m_chatter_s", "m_chatter_intervals",
	"m_limit_cycle", "s_pc_active", "s_pc_rms_mps", "s_pc_max_mps", "s_clamped", "s_chatter_s",
	"s_chatter_intervals", "s_limit_cycle", "Em_in_J", "Em_out_J", "Em_rx_J", "Es_in_J",
	"Es_out_J", "Es_rx_J", "m_margin_min_J", "s_margin_min_J", "drift_end_m", "drift_max_m",
	"drift_rms_m", "drift_delayed_end_m", "drift_delayed_max_m", "drift_delayed_rms_m",
	"track_rms_N", "track_max_N", "track_delayed_rms_N", "track_delayed_max_N", NULL,
};

/* mode: 0 text (aligned), 1 CSV, 2 Markdown */
void ana_tele_print_header(FILE *f, int mode)
{
	for (int i = 0; ana_tele_table_columns[i]; i++) {
		if (mode == 1)
			fprintf(f, "%s%s", i ? "," : "", ana_tele_table_columns[i]);
		else if (mode == 2)
			fprintf(f, "| %s ", ana_tele_table_columns[i]);
		else
			fprintf(f, i == 0 ? "%-20s" : " %11.11s", ana_tele_table_columns[i]);
	}
	if (mode == 2) {
		fputs("|\n", f);
		for (int i = 0; ana_tele_table_columns[i]; i++)
			fputs(i ? "|---:" : "|---", f);
		fputs("|", f);
	}
	fputc('\n', f);
}

static void cell(FILE *f, int mode, double v)
{
	if (mode == 1) {
		fputc(',', f);
		ana_put_double(f, v);
	} else if (mode == 2) {
		fprintf(f, "| %.4g ", v);
	} else {
		fprintf(f, " %11.4g", v);
	}
}

static void cell_na(FILE *f, int mode)
{
	fputs(mode == 1 ? "," : mode == 2 ? "| n/a " : "         n/a", f);
}

static void port_cells(FILE *f, int csv, const ana_tele_port *p, long long ticks)
{
	cell(f, csv, ticks > 0 ? (double)p->active / (double)ticks : 0.0);
	cell(f, csv, p->pc_rms);
	cell(f, csv, p->pc_max);
	cell(f, csv, (double)p->clamped);
	if (popc_chatter_checked(&p->chatter)) {
		cell(f, csv, p->chatter.chatter_s);
		cell(f, csv, (double)p->chatter.n_intervals);
	} else {
		cell_na(f, csv);
		cell_na(f, csv);
	}
	if (popc_chatter_lc_checked(&p->chatter))
		cell(f, csv, (double)p->chatter.limit_cycle);
	else
		cell_na(f, csv);
}

void ana_tele_print_row(FILE *f, int mode, const char *log, const ana_tele_summary *s)
{
	const int csv = mode;
	if (mode == 1)
		ana_put_csv_text(f, log);
	else if (mode == 2) {
		fputs("| ", f);
		ana_put_md_text(f, log);
		fputc(' ', f);
	} else
		fprintf(f, "%-20s", log);
	fprintf(f, mode == 1 ? ",%s" : mode == 2 ? "| %s " : " %11s", s->tdpa ? "on" : "off");
	cell(f, csv, s->fwd_delay_s);
	cell(f, csv, s->bwd_delay_s);
	cell(f, csv, (double)s->ticks);
	cell(f, csv, s->duration_s);
	port_cells(f, csv, &s->m, s->ticks);
	port_cells(f, csv, &s->s, s->ticks);
	const double cells[] = {
		s->m.in_J, s->m.out_J, s->m.rx_J, s->s.in_J, s->s.out_J, s->s.rx_J,
		s->m.margin_min_J, s->s.margin_min_J, s->drift_end_m, s->drift_max_m, s->drift_rms_m,
	};
	for (size_t i = 0; i < sizeof cells / sizeof cells[0]; i++)
		cell(f, csv, cells[i]);
	if (s->drift_al_n > 0) {
		cell(f, csv, s->drift_al_end_m);
		cell(f, csv, s->drift_al_max_m);
		cell(f, csv, s->drift_al_rms_m);
	} else {
		for (int i = 0; i < 3; i++)
			cell_na(f, csv);
	}
	cell(f, csv, s->track_rms_N);
	cell(f, csv, s->track_max_N);
	if (s->track_al_n > 0) {
		cell(f, csv, s->track_al_rms_N);
		cell(f, csv, s->track_al_max_N);
	} else {
		cell_na(f, csv);
		cell_na(f, csv);
	}
	fputs(mode == 2 ? "|\n" : "\n", f);
}

int ana_tele_table(FILE *f, int fmt, char *const *logs, const ana_tele_summary *const *s, int n)
{
	/* fmt: ana_format (text, csv, markdown, json) */
	if (fmt == ANA_CSV || fmt == ANA_JSON) {
		char header[2048];
		size_t len = 0;
		for (int i = 0; ana_tele_table_columns[i]; i++)
			len += (size_t)snprintf(header + len, sizeof header - len, "%s%s", i ? "," : "",
						ana_tele_table_columns[i]);
		static const char *const text_columns[] = {"log", "tdpa", NULL};
		popc_table_out t;
		if (popc_table_out_begin(&t, f, fmt == ANA_JSON, header, text_columns) != 0)
			return -1;
		for (int i = 0; i < n; i++) {
			if (!s[i])
				continue;
			ana_tele_print_row(popc_table_out_row(&t), 1, logs[i], s[i]);
			if (popc_table_out_flush(&t) != 0) {
				popc_table_out_end(&t);
				return -1;
			}
		}
		return popc_table_out_end(&t);
	}
	const int mode = fmt == ANA_MARKDOWN ? 2 : 0;
	ana_tele_print_header(f, mode);
	for (int i = 0; i < n; i++)
		if (s[i])
			ana_tele_print_row(f, mode, logs[i], s[i]);
	return 0;
}
