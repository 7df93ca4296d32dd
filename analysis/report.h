/* popc-analyze report's parts: the figures that reproduce the paper's
 * (report_figures.c: gnuplot scripts), the windows of raw rows the zoom and
 * position-against-force figures plot (report_window.c), the events they zoom
 * at (report_events.c). cmd_report.c reads the logs and writes the index. */
#ifndef POPC_ANALYSIS_REPORT_H
#define POPC_ANALYSIS_REPORT_H

#include <stdio.h>

#include "analyze.h"

/* The data files' columns after t: the windows' raw rows (NAME-figN.dat) hold
 * them in this order; NAME.dat holds each column's minimum over a bucket in
 * this order, then each one's maximum (ana_decim_write). */
enum { D_X, D_X_TRUE, D_V, D_F_E, D_F_PC, D_F_C, D_W, D_E_REF, D_WME, D_E_PORT, D_COLS };
#define REPORT_DAT_COLUMNS "t x x_true v f_e f_pc f_c W E_ref W-E_ref E_port"
#define REPORT_ENV_COLUMNS                                                                         \
	"t x_min x_true_min v_min f_e_min f_pc_min f_c_min W_min E_ref_min W-E_ref_min "          \
	"E_port_min x_max x_true_max v_max f_e_max f_pc_max f_c_max W_max E_ref_max W-E_ref_max "  \
	"E_port_max"
/* gnuplot's column (from 1) of column c's minimum and maximum in NAME.dat */
#define REPORT_ENV_MIN(c) (2 + (c))
#define REPORT_ENV_MAX(c) (2 + D_COLS + (c))
/* Fig. 7's ticks: k-3 .. k+3 around the Fig. 5 event tick k */
#define REPORT_FIG7_TICKS 7

/* The figures a report draws per log. RF_CONTACT is the contact response
 * (paper Figs. 3, 10, 14, 16 by variant), the others one paper figure each;
 * RF_ZOOM is the zoom at a time the user gives (--zoom T). */
typedef enum report_fig {
	RF_CONTACT,
	RF_FIG4,
	RF_FIG5,
	RF_FIG6,
	RF_FIG8,
	RF_FIG11,
	RF_ZOOM,
	RF_COUNT
} report_fig;

/* The file-name suffix of each figure ("" for the contact response: NAME.png). */
extern const char *const report_fig_suffix[RF_COUNT];

/* Windows of raw rows: the events of Figs. 5 and 8, the user's --zoom time,
 * the first press into the wall (Fig. 6), the log's last ticks (Fig. 11: the
 * low-velocity phase at the end of the paper's run). */
typedef enum report_win { RW_FIG5, RW_FIG8, RW_ZOOM, RW_PRESS, RW_END, RW_COUNT } report_win;

/* Ticks kept either side of an event: 15 periods (15 ms at 1 kHz) show the
 * paper's two-tick events with the steps that lead to them and follow. */
#define REPORT_ZOOM_TICKS 15
/* The first press (Fig. 6): at most this many ticks from the first contact
 * tick, to the tick the wall is left again (the paper scene's first press and
 * release takes 60 ticks; 1000 bounds a slow press's memory). */
#define REPORT_PRESS_TICKS 1000

typedef struct report_sample {
	double t_s;
	double v[D_COLS];
} report_sample;

typedef struct report_window {
	int wanted;         /* capture asked for (an event time known, or the press) */
	double t_event_s;   /* the event (RW_PRESS: the first contact tick, once found) */
	int n, cap;         /* rows kept, of at most cap */
	int event_index;    /* rows[event_index] is the event tick; -1: not reached */
	int after;          /* rows still to keep after the event (press: after leaving) */
	int closed;
	int pos;            /* RW_END: the next row to overwrite */
	report_sample *rows;
} report_window;

/* The ring of recent rows every window starts from, and the windows of one log. */
typedef struct report_capture {
	report_sample ring[REPORT_ZOOM_TICKS];
	int ring_n, ring_pos;
	report_window w[RW_COUNT];
} report_capture;

/* Sets up the windows: t_event_s[i] NAN for one not wanted (RW_PRESS is
 * always captured). Returns 0, or -1 out of memory. */
int report_capture_init(report_capture *c, const double t_event_s[RW_COUNT]);
void report_capture_add(report_capture *c, const report_sample *s, int in_contact);
/* After the last row: RW_END's ring in time order, its middle tick the event. */
void report_capture_finish(report_capture *c);
void report_capture_free(report_capture *c);
/* Writes a window's rows ("t x x_true ..." per line, NaN for missing). */
int report_window_write(const report_window *w, FILE *f);

/* What the report knows of one log when it writes the scripts. */
typedef struct report_log {
	char name[256];         /* file-name safe, unique in the report */
	char path[1024];        /* the log as given on the command line */
	int has_x_true, has_e_port;
	ana_summary sum;
	double t_first_s, t_last_s;
	double t_contact_s;     /* the first tick with f_e != 0; NAN: never in contact */
	double x_contact_min_m, x_contact_max_m; /* x and x_true from t_contact on */
	double f_c_min_N, f_c_max_N;
	double col_min[D_COLS], col_max[D_COLS]; /* each column over the log (NaN: never) */
	/* Fig. 7's ticks k-3 .. k+3 (fig7_n of them): measured x and f_c */
	int fig7_n;
	double fig7_x_m[REPORT_FIG7_TICKS], fig7_f_c_N[REPORT_FIG7_TICKS];
	int fig7_tick[REPORT_FIG7_TICKS]; /* -3 .. 3: the tick's place from the event */
	int fig7_event_row;               /* the event's row in NAME-fig6.dat's index 1 */
	/* Fig. 4 (ana_events): the velocity within one count for ANA_SETTLE_HOLD_S
	 * from t_settle_s, to the end from t_settle_final_s; NAN: not found */
	double t_settle_s, t_settle_final_s;
	double x_settled_min_m, x_settled_max_m; /* x over the settled stretch; NAN: none */
	double t_event_s[RW_COUNT]; /* NAN: no such event (RW_ZOOM: no --zoom) */
	int has_window[RW_COUNT];   /* the window has rows in NAME-figN.dat */
} report_log;

/* Scales shared by every figure of the report, so variants compare by eye. */
typedef struct report_scales {
	double f_pc_N;          /* the PC force axes span -f_pc_N .. f_pc_N */
	double f_c_min_N, f_c_max_N;
} report_scales;

/* The report's colours: the Okabe-Ito palette, strong and told apart with
 * any colour vision (no faint yellow). */
#define REPORT_BLUE "#0072B2"
#define REPORT_RED "#D55E00"
#define REPORT_GREEN "#009E73"
#define REPORT_PURPLE "#CC79A7"
#define REPORT_ORANGE "#E69F00"
#define REPORT_SKY "#56B4E9"

/* The terminal lines of a script that draws FILE.png and FILE.pdf. */
void report_terminal_block(FILE *f, const char *file, const char *png_size, const char *pdf_size);
/* Plot items (no "plot", no trailing comma) that draw column col of a
 * NAME.dat as its envelope: the band from the bucket's minimum to its
 * maximum lightly filled, and both edges as lines of colour rgb, dash dt;
 * unit is appended to each column ("*1e3": m to mm; "" as logged); axes
 * "x1y1" or "x1y2". */
void report_envelope(FILE *f, const char *data, int col, const char *unit, const char *rgb,
		     const char *dash, const char *title, const char *axes);
/* A log's own PC force scale (+- this) when the report's shared one would
 * draw it as a flat line, else 0. */
double report_own_f_pc_N(const report_log *lg, const report_scales *sc);

/* The paper figure a log's contact response reproduces (3, 10, 14, 16) by its
 * variant, or 0 (none, po-pc, hold: no such figure in the paper). */
int report_contact_paper_fig(const char *variant);

/* Each writes DIR/NAME<suffix>.gp (the script; gnuplot writes .png and .pdf).
 * fig_asked: the paper figure the user asked for with --figure (0: the log's
 * own), which the contact response's title names. Return 0 or -1 after one
 * message. */
int report_write_figure(FILE *f, report_fig fig, const report_log *lg, const report_scales *sc,
			int fig_asked);
int report_write_overlay(FILE *f, const report_log *logs, int n, const report_scales *sc);

/* The events of paper Figs. 4, 5 and 8 in lg->path (ana_find_events): sets
 * lg->t_event_s[RW_FIG5], [RW_FIG8], t_settle_s, t_settle_final_s (NAN: none).
 * Returns 0 or a negative popc_status with err set. */
int report_find_events(report_log *lg, const ana_input_options *in, popc_error *err);

/* An admittance log's figure (report_admittance.c): NAME-admittance.png from
 * NAME-admittance.dat, whose columns after t are these, minima then maxima. */
enum { RA_F_MEAS, RA_V_VE, RA_V_PC, RA_V, RA_W, RA_COLS };
#define REPORT_ADM_SUFFIX "-admittance"
#define REPORT_ADM_COLUMNS                                                                         \
	"t f_meas_min v_ve_min v_pc_min v_min W_min f_meas_max v_ve_max v_pc_max v_max W_max"
/* Adds an admittance row (has_adm) to d, a decimator of RA_COLS columns. */
void report_admittance_sample(ana_decimator *d, const ana_row *r);
/* A teleoperation log's figure (report_teleop.c): NAME-teleop.png from
 * NAME-teleop.dat, whose columns after t are these, minima then maxima. */
enum { RT_X, RT_XS, RT_F_C, RT_NEG_FS, RT_EM_IN, RT_EM_OUT, RT_EM_RX, RT_ES_IN, RT_ES_OUT,
       RT_ES_RX, RT_DRIFT, RT_COLS };
#define REPORT_TELE_SUFFIX "-teleop"
#define REPORT_TELE_COLUMNS                                                                        \
	"t x_min xs_min f_c_min -fs_min Em_in_min Em_out_min Em_rx_min Es_in_min Es_out_min "      \
	"Es_rx_min x-xs_min x_max xs_max f_c_max -fs_max Em_in_max Em_out_max Em_rx_max "          \
	"Es_in_max Es_out_max Es_rx_max x-xs_max"
/* Where the report goes, and the logs it reads: no output may replace one. */
typedef struct report_out {
	const char *dir;
	char *const *inputs;
	int n_inputs;
} report_out;

/* 0 when path is not one of the input logs; else -1 after saying so. */
int report_check_not_input(const report_out *ro, const char *path);
/* Opens DIR/file for writing (path gets the full name): NULL after one
 * message when it is an input log or cannot be opened. */
FILE *report_open(const report_out *ro, const char *file, char *path, size_t cap);
/* Closes it: 0, or -1 after one message naming the file (failed: an earlier
 * write already failed). */
int report_close(FILE *f, const char *path, int failed);
/* NAME-admittance.dat and .gp of an admittance log (lg->t_first_s, t_last_s
 * and sum set); 0, or -1 after one message. */
int report_admittance_write(const report_out *ro, const report_log *lg, const ana_decimator *d);
/* NAME-teleop.dat and .gp of a teleoperation log (lg->path, name, t_first_s
 * and sum set): reads the log's two ports again; 0, or -1 after one message. */
int report_teleop_write(const report_out *ro, const report_log *lg, const ana_input_options *in,
			int points, popc_error *err);
/* Text from a log made safe for a double-quoted gnuplot string. */
void report_safe_text(const char *in, char *out, size_t cap);

/* What the index shows: the table and overlay (the default report), which
 * figures were drawn. */
typedef struct report_index {
	const char *title;
	int tables;             /* compare table and overlay written */
	int drawn;              /* gnuplot drew every figure */
	unsigned figs;          /* the figures asked for: bit (1u << report_fig) */
	/* the logs with a figure of their own kind (admittance, teleoperation),
	 * drawn outside the paper's figures and the comparison */
	const struct report_own *own;
	int n_own;
} report_index;

/* An admittance or teleoperation log's own figure, for the index. */
typedef struct report_own {
	char name[256];         /* the log's name in the report */
	char kind[32];          /* "admittance", "teleoperation" */
	char file[300];         /* NAME-admittance, NAME-teleop (no extension) */
	char caption[600];
	int drawn;
} report_own;

/* Whether log lg has figure fig in this report (its event found, its data). */
int report_log_has(const report_log *lg, report_fig fig, unsigned figs);

int report_write_index(const report_out *ro, const report_index *ix, const report_log *logs, int n);

#endif
