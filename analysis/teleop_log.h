/* popc-analyze on a teleoperation log (docs/TELEOPERATION.md, "Analysing a
 * log"): a reader of the two ports' columns by name, and one summary per log
 * (chatter per port, PC activity, energies, position drift and force
 * tracking) shared by chatter, compare, the teleop verb and report. */
#ifndef POPC_ANALYZE_TELEOP_LOG_H
#define POPC_ANALYZE_TELEOP_LOG_H

#include <stdio.h>

#include "popc/core/chatter.h"
#include "popc/core/environment.h"
#include "popc/log/log_reader.h"
#include "popc/scene/scene.h"
#include "popc/util/error.h"

/* The columns a teleoperation verb reads (all of them: a log lacking one is
 * refused naming it). */
#define ANA_TELE_COLS(X)                                                                         \
	X(t) X(x) X(v) X(f_e) X(f_pc) X(f_c) X(W) X(flags) X(xs) X(fs) X(vs_rx) X(vs_pc) X(vs_c) \
	X(Ws) X(Em_in) X(Em_out) X(Em_rx) X(Es_in) X(Es_out) X(Es_rx) X(fwd_age) X(bwd_age)
enum {
#define ANA_TELE_ENUM(n) ANA_TC_##n,
	ANA_TELE_COLS(ANA_TELE_ENUM)
#undef ANA_TELE_ENUM
	ANA_TC_COUNT
};
extern const char *const ana_tele_col_names[ANA_TC_COUNT];

typedef struct ana_tele_log {
	popc_log_reader r;
	popc_scene scene;
	popc_environment env;
	double period_s;
	int col[ANA_TC_COUNT];       /* the file's index of each column */
	double row[POPC_LOG_MAX_COLUMNS];
} ana_tele_log;

/* One row: c[ANA_TC_*] the cells, line its line in the file. */
typedef struct ana_tele_row {
	double c[ANA_TC_COUNT];
	long long line;
} ana_tele_row;

/* Opens path again as a teleoperation log of the scene sc (read by
 * ana_log_open from its header and --set). "-" is refused: the first open
 * read standard input already. Errors name the file and the column. */
int ana_tele_open(ana_tele_log *l, const char *path, const popc_scene *sc, popc_error *err);
/* 1 with a row, 0 at the end, or a negative popc_status. */
int ana_tele_next(ana_tele_log *l, ana_tele_row *row, popc_error *err);
void ana_tele_close(ana_tele_log *l);

/* The chatter detector's PC scale per port (docs/ANALYSIS.md, "Teleoperation
 * logs"), as POPC_ADMITTANCE_CHATTER_COUNTS quanta so that the default share
 * (5 %) is one quantum:
 *   master (a force): f_1 = K_e delta, the force one encoder count of
 *     penetration commands at the slave's wall (free space, K_e = 0: one
 *     count of the slave's force sensor, r);
 *   slave (a velocity): v_1 = r / (K_e T), admittance.h's one-count velocity
 *     with the slave's sensor r (K_e = 0: r T / m_s). */
double ana_tele_master_scale_N(const popc_scene *sc);
double ana_tele_slave_scale_mps(const popc_scene *sc);

/* One teleoperation log's figures. Drift e_x = x - xs (master measured
 * position minus slave measured position); aligned, e_x,d(k) = x(k - a_f(k))
 * - xs(k) with a_f = fwd_age, the master position the slave's held packet
 * carries (the delay accounted). Force tracking e_f = f_c + fs (the master's
 * command against the force the slave's sensor reads, f_c = -fs when
 * rendered exactly); aligned, e_f,d(k) = f_c(k) + fs(k - a_b(k)), a_b =
 * bwd_age: what the master's PC and the channel's losses added to the
 * received force. Aligned figures are over the rows whose packet is held
 * (age >= 0); *_n counts them. */
typedef struct ana_tele_port {
	long long active, clamped;     /* ticks the PC corrected; at its bound */
	double pc_rms, pc_max;         /* RMS and max |d| (N at the master, m/s at the slave) */
	double in_J, out_J, rx_J;      /* E_in, E_out and the received E_in at the end */
	double margin_min_J;           /* min over rows of rx - out (the two-port condition) */
	double scale;                  /* the chatter detector's PC scale */
	popc_chatter_result chatter;
} ana_tele_port;

typedef struct ana_tele_summary {
	long long ticks;
	double duration_s, period_s;
	int tdpa;                      /* teleop.tdpa of the scene */
	double fwd_delay_s, bwd_delay_s; /* the channels' constant delays */
	ana_tele_port m, s;
	double drift_end_m, drift_max_m, drift_rms_m;
	double drift_al_end_m, drift_al_max_m, drift_al_rms_m;
	long long drift_al_n;
	double track_rms_N, track_max_N, track_al_rms_N, track_al_max_N;
	long long track_al_n;
} ana_tele_summary;

typedef void (*ana_tele_row_fn)(void *ctx, const ana_tele_row *row, const ana_tele_summary *s);

/* Reads the log at path (scene sc, environment env) and fills *s; on_row, if
 * not NULL, sees every row. 0 or a negative popc_status. */
int ana_tele_summarize(const char *path, const popc_scene *sc, const popc_chatter_config *ccfg,
		       ana_tele_summary *s, ana_tele_row_fn on_row, void *ctx, popc_error *err);

/* The table of ana_tele_summary (compare and the teleop verb): header and
 * one row, CSV cells; text aligned. */
extern const char *const ana_tele_table_columns[];
/* mode: 0 text (aligned), 1 CSV, 2 Markdown */
void ana_tele_print_header(FILE *f, int mode);
void ana_tele_print_row(FILE *f, int mode, const char *log, const ana_tele_summary *s);
/* The whole table in an ana_format (text, csv, markdown, json: one object
 * per log), logs[i] naming s[i] (NULL: skipped). 0, or -1 out of memory. */
int ana_tele_table(FILE *f, int fmt, char *const *logs, const ana_tele_summary *const *s, int n);

#endif
