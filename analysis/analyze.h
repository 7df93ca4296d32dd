/* popc-analyze: shared helpers of the verbs (one cmd_*.c per verb).
 *
 * ana_log wraps the library's streaming log reader for every verb: it maps
 * popc's column names (POPC_LOG_COLUMN_TABLE: t, x, count, ...) to the
 * file's headers, rebuilds the scene from a popc log's header (then --set),
 * derives the columns a foreign log lacks, and hands out one popc_tick per row.
 * Memory is constant in the length of the log. */
#ifndef POPC_ANALYZE_H
#define POPC_ANALYZE_H

#include <stdio.h>
#include <stdint.h>

#include "popc/core/chatter.h"
#include "popc/core/controller.h"
#include "popc/core/environment.h"
#include "popc/util/error.h"
#include "popc/programs/options.h"
#include "popc/log/log_columns.h"
#include "popc/log/log_reader.h"
#include "popc/scene/scene.h"
#include "read_foreign.h"
#include "teleop_log.h"

/* Options every verb that reads logs accepts (--column, --delimiter,
 * --decimal, --comment, --set, --scale). */
#define ANA_MAX_SCALES 16
#define ANA_MAX_EXTRA 4
/* the bit of a popc log column (POPC_LOG_COLUMN_*) in a column mask */
#define ANA_COLUMN_BIT(column) (UINT64_C(1) << (column))
typedef struct ana_input_options {
	popc_log_reader_options reader;
	/* --scale NAME=FACTOR: the file's NAME column times FACTOR is SI */
	int n_scales;
	const char *scale_name[ANA_MAX_SCALES];
	double scale[ANA_MAX_SCALES];
	char **sets;
	int n_sets;
	const char *verb;   /* for the notes ana_log_open prints ("popc-analyze VERB: ...") */
	int quiet;          /* -q: no notes */
	unsigned uses;      /* ANA_USES_*: scene parameters the verb reads beyond the columns */
	unsigned ignores;   /* ANA_USES_*: derived columns the verb does not read (replay: W) */
	/* ANA_COLUMN_BIT(POPC_LOG_COLUMN_*): popc columns the verb never reads; their
	 * cells are only checked to be a number's characters, not parsed
	 * (popc_log_reader_check_columns), and ana_row has NaN for them */
	uint64_t unread;
	/* energy --allow-uneven: a log without a rate may have uneven time steps
	 * (the verb then computes nothing that uses the period) */
	int allow_uneven;
	/* --jitter FRACTION: the time stamps are measured and may be off the
	 * nominal period T = 1 / run.rate by this fraction of T (0: not given;
	 * see ANA_JITTER_MAX and docs/ANALYSIS.md "Recorded device logs") */
	double jitter;
	/* columns outside popc's table that a verb reads by name when a log has
	 * them (report: E_port), handed out in ana_row.extra (NaN when absent) */
	int n_extra;
	const char *extra_name[ANA_MAX_EXTRA];
	/* MAT files, split files, rotary logs (read_foreign.h) */
	ana_foreign_options foreign;
} ana_input_options;

/* --jitter's largest fraction: past half a period a step is a dropped or a
 * doubled sample, not jitter, and the nominal T no longer describes it. */
#define ANA_JITTER_MAX 0.5

/* A log that gives no rate takes its period T from its first time step; every
 * later step must equal T within this relative tolerance, or the log is
 * uneven (ana_log_next refuses it, naming the first offending line).
 * Why 1 %: it must pass what formatting does to even steps t = k T, and catch
 * what uneven sampling does.
 * - popc's shortest round-trip form (or %.17g) prints the double k*T exactly;
 *   a difference of two such doubles is off by at most ulp(t) ~ k T 2^-52,
 *   relative 2.2e-16 k: 2.2e-7 after 1e9 ticks (11 days at 1 kHz).
 * - fixed decimals, %.6f (microseconds, the coarsest common in device logs):
 *   each t rounds by <= 0.5 us, a step by <= 1 us: 0.1 % of a 1 ms period,
 *   1 % at 10 kHz; the first step, T itself, carries the same error.
 * - --scale t=1e-3 of integer milliseconds rounds once per value: ~1e-16.
 * - a time column that cannot resolve its own step (%g's six digits past
 *   t = 100 s at 1 kHz) is refused, rightly: it cannot give the period.
 * Uneven sampling is far outside: a dropped sample is a step of 2T (+100 %),
 * 1000 Hz against 1024 Hz is 2.4 %. Steps within 1 % change the quantities
 * built on T (v = dx/T, rates per second, window lengths in ticks) by at
 * most 1 % on that tick. */
#define ANA_PERIOD_REL_TOL 0.01

/* Scene parameters a verb depends on besides those the derived columns need
 * (ana_log_open adds the encoder always, the environment when f_e is missing,
 * the variant when W or E_ref is missing, the rate when the time column does
 * not give the period). A foreign log's parameter that neither the header nor
 * --set gives comes from the paper scene's defaults, and ana_log_open says so
 * on stderr once per log (docs/ANALYSIS.md). */
enum {
	ANA_USES_ENVIRONMENT = 1u << 0, /* contact share: chatter, compare, report */
	ANA_USES_VARIANT = 1u << 1,     /* the observer that ran online: energy */
	ANA_USES_CONTROLLER = 1u << 2,  /* PC bound, Table I mode, FOAW: replay */
	ANA_USES_ENCODER = 1u << 3,
	ANA_USES_RATE = 1u << 4,
	ANA_USES_PC_BOUND = 1u << 5,    /* the chatter threshold is a share of it */
};

/* The long options of ana_input_options, to splice into a verb's table. */
enum {
	ANA_OPT_COLUMN = 1000,
	ANA_OPT_DELIMITER,
	ANA_OPT_COMMENT,
	ANA_OPT_SET,
	ANA_OPT_SCALE,
	ANA_OPT_DECIMAL,
	ANA_OPT_NO_HEADER,
	ANA_OPT_JITTER,
};
/* Their case labels, for a verb's getopt switch (one list to extend). */
#define ANA_INPUT_OPTION_CASES                                               \
	case ANA_OPT_COLUMN:                                                 \
	case ANA_OPT_DELIMITER:                                              \
	case ANA_OPT_COMMENT:                                                \
	case ANA_OPT_SET:                                                    \
	case ANA_OPT_SCALE:                                                  \
	case ANA_OPT_DECIMAL:                                                \
	case ANA_OPT_NO_HEADER:                                              \
	case ANA_OPT_JITTER:                                                 \
	ANA_FOREIGN_OPTION_CASES
/* The input options' table (common.c), which every verb's list of option
 * tables ends with (options.h). */
extern const popc_option ana_input_option_table[];
/* getopt_long's arrays made from a verb's option tables; opts and shorts of
 * these sizes hold every verb's. */
#define ANA_MAX_OPTIONS 64
void ana_getopt_tables(const popc_option *const *tables, struct option opts[ANA_MAX_OPTIONS],
		       char shorts[2 * ANA_MAX_OPTIONS]);
/* Each verb's option tables (analyze_main.c's verb table points at them). */
extern const popc_option *const ana_energy_opts[];
extern const popc_option *const ana_chatter_opts[];
extern const popc_option *const ana_compare_opts[];
extern const popc_option *const ana_replay_opts[];
extern const popc_option *const ana_events_opts[];
extern const popc_option *const ana_report_opts[];
extern const popc_option *const ana_teleop_opts[];
/* popc's column names, each after a space: " t x count ..."; an admittance
 * log's own columns are left out (a recorded admittance device's log is a
 * later phase, docs/ADMITTANCE.md), and so are a teleoperation log's */
#define ANA_COLUMN_NAME_ALWAYS(text) text
#define ANA_COLUMN_NAME_X_TRUE(text) text
#define ANA_COLUMN_NAME_TIMING(text) text
#define ANA_COLUMN_NAME_ADMITTANCE(text)
#define ANA_COLUMN_NAME_TELEOP(text)
#define ANA_COLUMN_NAME_SLAVE_TRUE(text)
#define ANA_COLUMN_NAME_DRIFT(text)
#define ANA_COLUMN_NAME(ID, name, unit, fill, format, field, meaning) ANA_COLUMN_NAME_##fill(" " #name)
#define ANA_COLUMN_NAMES POPC_LOG_COLUMN_TABLE(ANA_COLUMN_NAME)
#define ANA_INPUT_HELP                                                                         \
	"  --column NAME=HEADER     popc's column NAME is the file's column HEADER, or its\n"    \
	"                           N-th column with HEADER '#N' (repeatable; names:\n"        \
	"                          " ANA_COLUMN_NAMES ")\n"                                     \
	"  --no-header              the file has no column names line (recorded device logs):\n" \
	"                           map its columns by position, e.g. --column x=#2\n"          \
	"  --scale NAME=FACTOR      the file's column NAME times FACTOR is in SI units, e.g.\n"  \
	"                           t=1e-3 (ms), x=1e-3 (mm), f_c=-1 (other sign convention)\n" \
	"  --delimiter C            cell delimiter: ',' ';' tab ('\\t' or 'tab') or 'space'\n"    \
	"                           (runs of spaces and tabs; default: detected from the\n"    \
	"                           column names line, or the first row)\n"                   \
	"  --decimal .|,            decimal mark of the numbers (default '.'); ',' reads\n"    \
	"                           '1,5' as 1.5 exactly (European logs, ';' between cells;\n"  \
	"                           not with --delimiter ',')\n"                                \
	"  --comment C              comment character (default '#')\n"                            \
	"  --set section.key=value  scene parameter the log lacks or overrides, e.g.\n"          \
	"                           encoder.resolution=1e-5 environment.stiffness=1000\n"         \
	"                           run.rate=1000 (repeatable); a log without a time column\n" \
	"                           needs run.rate: its t is k / run.rate\n"                    \
	"  --jitter FRACTION        the time stamps are measured and may be off the period\n"  \
	"                           1 / run.rate by FRACTION of it (<= 0.5; needs run.rate):\n" \
	"                           measured steps are used where a definition allows (v =\n" \
	"                           dx/dt, energy), others refuse a larger step naming it\n"

/* Handles one of the ANA_OPT_* options; returns 0, or 2 after printing why. */
int ana_input_option(ana_input_options *o, int opt, char *arg, const char *verb);
void ana_input_free(ana_input_options *o);

typedef struct ana_log {
	popc_log_reader r;
	popc_scene scene;
	popc_environment env;
	char name[256];           /* file name without directory and ".csv" */
	char variant[64];         /* header's variant, or "unknown" */
	int is_popc;              /* has a popc provenance header */
	double period_s;          /* 1 / run.rate, or the first time step */
	int period_from_time;     /* 1: no rate known, taken from the time column */
	int allow_uneven;         /* the time steps are not checked against period_s */
	/* --jitter: the measured step t(k) - t(k-1) is ana_row.step_s, and when
	 * check_jitter (a verb that uses the nominal T: every verb but energy,
	 * which clears it unless an observer on T is asked for) a step off T by
	 * more than jitter T is refused naming its line */
	double jitter;
	int check_jitter;
	double max_jitter;        /* the largest |step - T| / T seen, noted at the end */
	long long max_jitter_line;
	int quiet;                /* -q: no notes */
	double t_prev_s;          /* the previous row's time, for the step check */
	long long t_prev_line;
	/* a popc log's header facts that its rows can check (docs/ANALYSIS.md,
	 * "A header that contradicts its rows"): each says where the fact came
	 * from ("run.rate = 500 (header, line 8)", or --set) for the message */
	int check_steps;          /* run's t = k T: every step T within ANA_PERIOD_REL_TOL */
	int check_mean_step;      /* replay's t, the recording's stamps: their mean step */
	int check_x;              /* x = count x encoder.resolution */
	int check_no_pc;          /* variant none: f_pc = 0 on every row */
	char rate_from[128], resolution_from[128], variant_from[128];
	double t_first_s;
	long long t_first_line;
	/* column indices, -1 when the file lacks them: c_t, c_x, ... c_rtt, one
	 * per column of popc's log (POPC_LOG_COLUMN_TABLE) */
#define ANA_COLUMN_INDEX(ID, name, unit, fill, format, field, meaning) int c_##name;
	POPC_LOG_COLUMN_TABLE(ANA_COLUMN_INDEX)
#undef ANA_COLUMN_INDEX
	/* the PC force is logged (f_pc) or follows from the command (f_pc = f_c - f_e);
	 * without either, ana_log_next's f_pc is 0 and f_c = f_e, which is no
	 * measurement: a verb must not base a verdict on it (ana_no_pc_force) */
	int has_pc_force;
	/* W is known: logged with E_ref, or recomputable from f_c */
	int has_w;
	/* look-ahead: the first two rows are read at open to find the period */
	double ahead[2][POPC_LOG_MAX_COLUMNS];
	long long ahead_line[2];  /* their line numbers (comments may come between) */
	int n_ahead, ahead_pos, ahead_st;
	double row[POPC_LOG_MAX_COLUMNS];
	double scale[POPC_LOG_MAX_COLUMNS]; /* --scale per file column (1: none) */
	int scaled;                         /* any --scale */
	/* derived columns */
	long long k;              /* ticks handed out */
	double x_prev_m;
	popc_observer obs;        /* recomputes W and E_ref when the file lacks them */
	const char *verb;         /* for the note on an unfinished log */
	int unfinished;           /* popc_log_reader_unfinished at the end, once noted */
	int n_extra;
	int c_extra[ANA_MAX_EXTRA]; /* the file's index of each extra column, -1: absent */
} ana_log;

/* One row as analysed: the tick plus the optional columns. */
typedef struct ana_row {
	popc_tick tick;
	double x_true_m;          /* NAN when absent */
	double E_port_J;          /* the true port energy E_port(k); NAN when absent */
	double dt_s, rtt_s;       /* NAN when absent */
	/* the time step to this row: t(k) - t(k-1) under --jitter, else the
	 * period T (and T on the first row) */
	double step_s;
	double W_logged_J, E_ref_logged_J; /* NAN when absent */
	int pc_force_known, w_known;       /* the ana_log's has_pc_force, has_w */
	long long line;                    /* the row's line in the file, for messages */
	double extra[ANA_MAX_EXTRA];       /* ana_input_options.extra_name's cells; NAN: absent */
	/* an admittance log (has_adm): the force count and reading, the VE's
	 * and the PC's velocities (docs/ADMITTANCE.md) */
	int has_adm;
	long long adm_n;
	double adm_f_N, adm_v_ve_mps, adm_v_pc_mps;
	/* replay of an admittance log: the force count wherever f_count is
	 * there, and the servo's position command (0 without x_cmd) */
	long long adm_count;
	double adm_x_cmd_m;
} ana_row;

/* Opens a log: reader, scene (defaults, header, --set; validated), columns.
 * Requires a position (x or count), and t or a rate (then t = k T, as popc
 * writes it). Errors name the file, line, column.
 * A period taken from the time column must be a normal double (a step of
 * 5e-324 s has no finite rate 1/T: every rate, velocity and window built on it
 * would be inf or NaN). */
int ana_log_open(ana_log *l, const char *path, const ana_input_options *o, popc_error *err);

/* Next row: 1, 0 at the end, or a negative popc_status. Every quantity of
 * the tick is finite: a derived one (v = dx/T, f_e, f_pc = f_c - f_e, the
 * recomputed W and E_ref) and W - E_ref that overflow a double from finite
 * cells are an error naming the line. A log whose period
 * comes from its time column (no rate) must have even steps (within
 * ANA_PERIOD_REL_TOL of the first) unless allow_uneven: the first step that is
 * not is an error naming its line. At the end of an unfinished popc log (no
 * stop line, or a last line cut short: popc_log_reader_unfinished) a note on
 * stderr names the file and the line where its rows end; every verb reads
 * such a log's whole rows (docs/ANALYSIS.md), and l->unfinished says it. */
int ana_log_next(ana_log *l, ana_row *row, popc_error *err);

void ana_log_close(ana_log *l);

/* The error for a log without a PC-force source: names the file, the columns
 * looked for and the --column mapping. Returns POPC_ERR_INVALID. */
int ana_no_pc_force(popc_error *err, const char *path);

/* The observer that ran online for a variant (Table I for ignore/improved). */
void ana_online_observer(const popc_scene *s, popc_variant *variant, popc_ignore_mode *mode);

/* Prints "popc-analyze VERB: msg" and returns the exit code for status. */
int ana_fail(const char *verb, int status, const popc_error *err);

/* Index of the input (of inputs[0..n-1]) that the file out already is (same
 * device and inode: a link or another spelling counts), or -1. Every verb
 * checks its outputs with it before opening them for writing, so that no
 * output replaces a log it reads (energy -o LOG LOG, a report's compare.csv
 * beside a log named compare.csv, a replay prefix naming its own input). */
int ana_output_is_input(const char *out, char *const *inputs, int n);

/* Output paths, checked before any work: a path that cannot be used is bad
 * usage (exit 2), named with its option, not a failure found after reading
 * every log (exit 1 or 2 then). A file path: "-", an existing file that can be
 * written, or a new one in an existing, writable directory (not a directory,
 * not a path through a file). A directory: an existing writable one, or with
 * create, one that mkdir can make (its parent exists and is writable).
 * Return 0, or 2 after printing "popc-analyze VERB: OPT PATH: why". */
int ana_output_file_usable(const char *verb, const char *opt, const char *path);
int ana_output_dir_usable(const char *verb, const char *opt, const char *dir, int create);

/* The name a verb gives a log (its file name without the directory and
 * ".csv"; "stdin" for "-"), as ana_log_open sets ana_log.name. */
void ana_log_name(const char *path, char *out, size_t cap);

/* Names that tell n logs apart in one table (compare's log column): each
 * log's file name without ".csv", and where two logs would share one, the
 * shortest path suffix that tells them apart ("a/improved.csv" and
 * "b/improved.csv": "a/improved", "b/improved"; "improved.csv" beside
 * "b/improved.csv": "improved", "b/improved"). The same path twice keeps its
 * name. "-" is "stdin". Returns 0, or -1 when out of memory. */
#define ANA_LOG_NAME_MAX 256
int ana_log_names(char *const *paths, int n, char (*names)[ANA_LOG_NAME_MAX]);

/* Writes text as one CSV cell: in double quotes (inner quotes doubled) when it
 * holds a comma, a quote or a line end, as a file name may. */
void ana_put_csv_text(FILE *f, const char *text);

/* Writes text as one Markdown table cell ('|' escaped). */
void ana_put_md_text(FILE *f, const char *text);

/* Writes v in shortest round-trip form. */
void ana_put_double(FILE *f, double v);
/* The same with a decimal point always ("0.0", "5.0": popc_format_double_point):
 * a summary's real cells, which readers then type floating point. */
void ana_put_double_point(FILE *f, double v);

/* Chatter thresholds from "--threshold name=value". */
int ana_threshold_option(popc_chatter_config *cfg, char *arg, const char *verb);
/* The chatter detector's messages name its parameters (window_s, period_s,
 * resolution_m, pc_bound_N); this names them as popc-analyze's user sets them
 * (--threshold window=S, --set run.rate=HZ, ...). */
void ana_chatter_name_options(popc_error *err);

/* The paper's timeline events in a log (docs/ANALYSIS.md, "Events"). Ticks
 * k = 0, 1, ... are the log's rows; dcount(k) = count(k) - count(k-1) is the
 * backward-difference velocity in counts per period (seed Fig. 4), "calm" when
 * |dcount(k)| <= 1 (row 0 is calm); the PC is active at k when f_pc(k) != 0.
 * - settle: settle_s = t(k) (tick settle_tick) of the first calm tick that
 *   starts a stretch of calm ticks lasting at least hold_s (or reaching the
 *   end of the log) after at least one tick that is not calm (the approach;
 *   a log calm throughout settles at its first row). Fig. 4: t > 2.5 s. settle_end_s: the first tick after it
 *   that is not calm (NAN: calm to the end). settle_final_s: the start of the
 *   calm stretch that reaches the end (NAN when the last tick is not calm):
 *   "within one count from here to the end". NAN (tick -1) when none.
 * - Fig. 5 event at k: the PC active at k, dcount(k) = +-1, dcount(k+1) =
 *   -dcount(k) and (W - E_ref)(k+1) < (W - E_ref)(k). fig5_s = t(k) of the
 *   first at or after settle_s (the paper shows it in the low-velocity phase:
 *   3.173 s), fig5_dw_J its change of W - E_ref at k+1 (< 0); fig5_first_s
 *   the first anywhere. Needs a PC force and W (pc_known, w_known).
 * - Fig. 8 event at k: the PC active at k, not at k-1 (or k the first row),
 *   and dcount(k+1) = 0, so that the PC's force moves no energy at k+1.
 *   fig8_s = t(k) of the first at or after settle_s (paper: 2.957 s);
 *   fig8_first_s the first anywhere. Needs a PC force.
 *   NAN: no such event (or not checkable).
 * n_* count every occurrence (n_fast: ticks that are not calm);
 * x_*_settled_m is the measured position's range over the settled stretch
 * [settle_s, settle_end_s) (NAN when never settled). */
#define ANA_SETTLE_HOLD_S 0.5
typedef struct ana_events {
	double settle_s, settle_end_s, settle_final_s;
	long long settle_tick;
	long long n_fast;
	double x_min_settled_m, x_max_settled_m;
	double fig5_s, fig5_dw_J, fig5_first_s;
	long long n_fig5;
	double fig8_s, fig8_first_s;
	long long n_fig8;
	long long ticks;
	int pc_known, w_known;       /* the log has a PC force, W */
} ana_events;

/* Streaming form, for a verb that reads the log already (ana_summarize's
 * on_row): init (hold_s: the settle stretch's least length, ANA_SETTLE_HOLD_S
 * by default), one call per row in order, finish. */
typedef struct ana_events_finder {
	ana_events ev;
	double hold_s;
	long long n, count_prev, dcount_prev;
	double t_prev_s, we_prev_J;
	int pc_active_prev, pc_active_prev2;
	int in_run, settled, settle_open;  /* a calm stretch; settle found; still in it */
	double run_start_s, run_x_min_m, run_x_max_m;
	double run_fig5_s, run_fig5_dw_J, run_fig8_s; /* first events of the stretch */
	long long run_start_tick;
} ana_events_finder;
void ana_find_events_init(ana_events_finder *f, double hold_s);
void ana_find_events_row(ana_events_finder *f, const ana_row *row);
void ana_find_events_finish(const ana_events_finder *f, ana_events *ev);

/* Reads the whole log at path and finds its events: 0 or a popc_status. */
int ana_find_events(const char *path, const ana_input_options *o, double hold_s, ana_events *ev,
		    popc_error *err);

/* Verbs */
int ana_cmd_energy(int argc, char **argv);
int ana_cmd_chatter(int argc, char **argv);
int ana_cmd_compare(int argc, char **argv);
int ana_cmd_replay(int argc, char **argv);
/* replay_admittance.c: the n parallel PC variants over l's recorded force
 * counts into out_paths (checked by the caller); returns an exit status. */
int ana_replay_admittance(ana_log *l, const char *path, const popc_scene *base,
			  const popc_admittance_variant *variants, char (*out_paths)[1100], int n,
			  int quiet);
/* replay_teleop.c: a teleoperation log's two PCs off (mask bit 0) and on
 * (bit 1) over the recorded channel into out_paths[0], [1] (checked by the
 * caller); returns an exit status. */
int ana_replay_teleop(const char *path, const popc_scene *sc, unsigned mask,
		      char (*out_paths)[1100], int quiet);
int ana_cmd_report(int argc, char **argv);
int ana_cmd_events(int argc, char **argv);
int ana_cmd_teleop(int argc, char **argv);

/* compare's one row, shared by compare and report. */
typedef struct ana_summary {
	char log[256];
	char variant[64];
	double pc_rms_N, pc_rms_late_N, pc_max_N, pc_active, pc_energy_J;
	double w_minus_eref_min_J, w_minus_eref_end_J;
	double vsign_rate_Hz, vsign_rate_late_Hz;
	popc_chatter_result chatter;
	double duration_s;
	long long ticks;
	double period_s;         /* the period the detector and the metrics used */
	int has_pc_force, has_w; /* 0: the PC (W) columns are n/a */
	/* an admittance log (docs/ANALYSIS.md, "Admittance logs"): the PC columns
	 * (pc_rms, pc_max, pc_energy, the detector's) are the parallel PC's v_pc,
	 * in m/s (pc_energy: T sum f v_pc, J), and pc_bound_N is the detector's
	 * scale, POPC_ADMITTANCE_CHATTER_COUNTS times one count's velocity */
	int admittance;
	/* the true port energy (the log's E_port column, port_energy.h) at the
	 * end, the observer's error W - E_port there and its largest magnitude;
	 * has_port_energy = 0 (n/a, empty in CSV) for a log without E_port or W */
	int has_port_energy;
	double port_energy_end_J, po_error_end_J, po_error_max_J;
	double port_energy_min_J;     /* min of E_port over the log's rows */
	/* least squares f_c / penetration over the rows in contact (0 without
	 * contact), as the run summary's rendered_stiffness */
	double rendered_stiffness_Npm;
	/* the scene the log ran (header, then --set; paper defaults for what a
	 * foreign log lacks): the report's parameter box */
	double env_stiffness_Npm, env_position_m, enc_resolution_m, pc_bound_N;
	char ignore_mode[16];
	/* an admittance log's (report_admittance.c's parameter box) */
	double adm_force_resolution_N, adm_virtual_mass_kg, adm_virtual_damping_Nspm;
	double adm_pc_velocity_bound_mps;
	/* a teleoperation log (teleop.architecture not off): only log, variant,
	 * ticks, duration_s and period_s above are set; its figures are tele's
	 * (teleop_log.h), the scene tele_scene */
	int teleop;
	ana_tele_summary tele;
	popc_scene tele_scene;
} ana_summary;

/* Chatter has a verdict: the log has a PC force and at least one full
 * detection window (chatter.windows > 0). Otherwise chatter_s and
 * chatter_intervals are "not checked", never 0. */
int ana_chatter_checked(const ana_summary *s);

/* The error for a log shorter than one chatter window: names the file, its
 * length and the length it needs. Returns POPC_ERR_INVALID. */
int ana_chatter_too_short(popc_error *err, const char *path, const ana_summary *s);

/* The limit cycle has a verdict: the log covers at least half its window
 * (popc_chatter_lc_checked: 1000 ticks at 1 kHz by default). Otherwise
 * limit_cycle, lc_amplitude and lc_frequency are "not checked", never 0. */
int ana_lc_checked(const ana_summary *s);

/* The message for a log shorter than half a limit-cycle window: names the
 * file, its length and the length it needs. Returns POPC_ERR_INVALID. */
int ana_lc_too_short(popc_error *err, const char *path, const ana_summary *s);

/* Streams a log through popc_metrics and the chatter detector (and on_row,
 * if not NULL, for every row). late_from_s < 0: the second half of the
 * header's run.duration, or the whole log when the header has none. */
typedef void (*ana_row_fn)(void *ctx, const ana_row *row);
int ana_summarize(const char *path, const ana_input_options *o, const popc_chatter_config *ccfg,
		  double late_from_s, ana_summary *s, ana_row_fn on_row, void *ctx,
		  popc_error *err);

/* ANA_JSON: one JSON object per row on one line (JSON Lines), the CSV's names
 * and cells typed (popc/util/json.h); compare only */
typedef enum ana_format { ANA_TEXT, ANA_CSV, ANA_MARKDOWN, ANA_JSON } ana_format;
int ana_format_from_name(const char *name, ana_format *f);
void ana_summary_print_header(FILE *f, ana_format fmt);
void ana_summary_print_row(FILE *f, ana_format fmt, const ana_summary *s);

/* Min/max decimation for plots: at most max_buckets buckets, each keeping
 * the minimum and maximum of every column, so a chattering signal is drawn
 * as its envelope (the band it fills) and a quiet one as a line. When the buckets run out, pairs
 * are merged and the bucket width doubles: memory is bounded whatever the
 * length of the log. */
#define ANA_DECIM_MAX_COLS 12
typedef struct ana_decim_bucket {
	long long n;
	double t0_s, t1_s;
	double mn[ANA_DECIM_MAX_COLS], mx[ANA_DECIM_MAX_COLS];
	long long imn[ANA_DECIM_MAX_COLS], imx[ANA_DECIM_MAX_COLS];
} ana_decim_bucket;

typedef struct ana_decimator {
	int n_cols, cap, n;
	long long width, k;
	ana_decim_bucket *b;
} ana_decimator;

int ana_decim_init(ana_decimator *d, int n_cols, int max_buckets);
void ana_decim_add(ana_decimator *d, double t_s, const double *values);
/* Writes each bucket's envelope, "t min1 .. minN max1 .. maxN" (NaN for a
 * missing value), at the bucket's first and last time (one row for a bucket
 * of one tick); the values are the log's own, exactly. Returns 0 or -1. */
int ana_decim_write(const ana_decimator *d, FILE *f);
void ana_decim_free(ana_decimator *d);

/* Runs "gnuplot SCRIPT" in directory dir (fork/exec); 0 when it exits 0.
 * gnuplot's messages are kept and shown on stderr when it fails, or always
 * when verbose. */
int ana_run_gnuplot(const char *gnuplot, const char *dir, const char *script, int verbose,
		    char *why, size_t why_cap);

#endif
