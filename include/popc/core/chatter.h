/* Streaming detector of the seed's "noisy behavior" (PC chattering) and of a
 * sustained low-frequency limit cycle, fed one popc_tick per control tick.
 * Memory is constant in the length of the log. Metrics, thresholds and their
 * reasoning: docs/ANALYSIS.md.
 *
 * Chatter (seed Fig. 3(d), Fig. 4): in a sliding window (default 100 ms, slid
 * by a tenth of its length) the PC force is large (RMS), switches sign often
 * (sign flips per second) and the velocity sign changes often while in
 * contact. Windows meeting all three are merged into time intervals.
 *
 * Limit cycle (seed Fig. 10, and the sampled spring without PC, Fig. 6): over
 * the last seconds of the log the position keeps oscillating with an amplitude
 * of several encoder counts, at most a tenth of the control rate, in contact, and does
 * not decay: turning points in the window's first and last quarter (an
 * oscillation that began inside the window, such as an approach from rest and
 * its bounces, is not yet one), the amplitude ratio between them scaled to
 * the full window's 1.5 s. Turning points are found with a hysteresis of a few
 * counts so that quantization dither never counts as motion.
 *
 *   popc_chatter_config cfg;
 *   popc_chatter_config_defaults(&cfg);
 *   cfg.resolution_m = scene.enc_resolution_m;
 *   cfg.pc_bound_N = scene.pc_bound_N;
 *   popc_chatter det;
 *   popc_chatter_init(&det, &cfg, period_s, &env, &err);
 *   for each tick: popc_chatter_add(&det, &tick);
 *   popc_chatter_result res;
 *   popc_chatter_finish(&det, &res);
 */
#ifndef POPC_CHATTER_H
#define POPC_CHATTER_H

#include "popc/core/controller.h"
#include "popc/core/environment.h"
#include "popc/core/sum_squares.h"
#include "popc/util/error.h"

#define POPC_CHATTER_MAX_INTERVALS 32 /* stored; more are counted in n_intervals */
#define POPC_CHATTER_SUBBLOCKS 10     /* the chatter window slides by 1/10 of its length */
#define POPC_CHATTER_LC_SEGMENTS 8    /* the limit-cycle window is kept as 8 segments */

/* The thresholds are relative to the scene (docs/ANALYSIS.md, "Thresholds
 * relative to the scene"): a share of the PC bound, a share of the control
 * rate, encoder counts. The scene's values (pc_bound_N, resolution_m, the
 * period given to popc_chatter_init) turn them into the absolute
 * popc_chatter_thresholds the detector compares with. */
typedef struct popc_chatter_config {
	/* chatter: all three in one window */
	double window_s;               /* sliding window length (s) */
	double pc_rms_share;           /* PC force RMS >= this share of pc_bound_N */
	double pc_flip_share;          /* PC force sign flips per control tick */
	double vsign_share;            /* velocity sign changes per control tick in contact */
	double contact_min;            /* share of the window's ticks in contact */
	/* limit cycle: over the last lc_window_s of the log */
	double lc_window_s;
	double lc_amplitude_min_counts;  /* mean half swing, in encoder counts */
	double lc_hysteresis_counts;     /* a turning point needs this much return */
	double lc_cycles_min;            /* full cycles in lc_window_s at least this */
	double lc_freq_max_share;        /* frequency at most this share of the control rate */
	double lc_contact_min;           /* share of ticks in contact */
	double lc_sustain_min;           /* lc_sustain at least this (below) */
	/* the scene (not thresholds): from the log header or --set */
	double resolution_m;             /* encoder.resolution delta (m) */
	double pc_bound_N;               /* controller.pc_bound (N) */
} popc_chatter_config;

/* The absolute thresholds a configuration gives for one scene. */
typedef struct popc_chatter_thresholds {
	double pc_rms_min_N;           /* pc_rms_share * pc_bound_N */
	double pc_flip_rate_min_Hz;    /* pc_flip_share / T */
	double vsign_rate_min_Hz;      /* vsign_share / T */
	double lc_amplitude_min_m;     /* lc_amplitude_min_counts * resolution_m */
	double lc_hysteresis_m;        /* lc_hysteresis_counts * resolution_m */
	double lc_freq_min_Hz;         /* lc_cycles_min / lc_window_s */
	double lc_freq_max_Hz;         /* lc_freq_max_share / T */
} popc_chatter_thresholds;

typedef struct popc_chatter_interval {
	double start_s, end_s;
	double pc_rms_max_N;           /* largest window PC RMS inside the interval */
} popc_chatter_interval;

typedef struct popc_chatter_result {
	/* full chatter windows evaluated: 0 when the log is shorter than one
	 * window, and then chatter was not checked (no verdict: chatter_s = 0
	 * means nothing, the caller must say "not checked") */
	long long windows;
	long long window_ticks;        /* ticks in one window: the shortest log checked */
	double chatter_s;              /* total flagged time (s) */
	int n_intervals;               /* every interval found */
	int n_stored;                  /* min(n_intervals, POPC_CHATTER_MAX_INTERVALS) */
	popc_chatter_interval intervals[POPC_CHATTER_MAX_INTERVALS];
	popc_chatter_thresholds thr;   /* what the metrics were compared with */
	int limit_cycle;               /* 0 or 1; 0 means nothing unless checked */
	/* the limit cycle is judged on at least half its window (lc_min_ticks =
	 * 4 of the 8 segments: 1000 ticks for 2 s at 1 kHz); lc_ticks is what the
	 * last window covers (the whole log until it is longer than the window).
	 * lc_ticks < lc_min_ticks: not checked (popc_chatter_lc_checked), and the
	 * lc_* metrics below, over less than half a window, are no measurement */
	long long lc_ticks, lc_min_ticks;
	/* chatter metrics: maxima over the full windows */
	double max_pc_rms_N, max_pc_flip_rate_Hz, max_vsign_rate_Hz;
	/* limit-cycle metrics over the last window */
	double lc_span_s;              /* time actually covered (shorter logs: less) */
	double lc_start_s, lc_end_s;   /* the window: [start, end] */
	double lc_amplitude_m;         /* mean half swing between turning points */
	double lc_frequency_Hz;        /* turning points / 2 / span */
	double lc_contact;             /* share of ticks in contact */
	/* amplitude of the last quarter / first quarter (quarters in ticks),
	 * raised to (0.75 lc_window / the time between the quarters' centres):
	 * the ratio over a full window's 1.5 s whatever the log's length; 0 when
	 * either quarter has no turning point */
	double lc_sustain;
	double lc_pc_rms_N;            /* PC force RMS (small: the PC does not act) */
	double lc_w_drift_J;           /* change of W - E_ref over the window */
} popc_chatter_result;

/* Sums over a stretch of ticks (internal, in the struct for constant memory). */
typedef struct popc_chatter_block {
	long long ticks, contact_ticks, pc_flips, vsign_changes;
	popc_sum_squares pc_sq;
	double t_first_s, t_last_s;
} popc_chatter_block;

typedef struct popc_chatter_segment {
	long long ticks, contact_ticks, reversals;
	double swing_sum_m;
	popc_sum_squares pc_sq;
	double t_first_s, t_last_s;
	double wme_first_J, wme_last_J;  /* W - E_ref at the first and last tick */
} popc_chatter_segment;

typedef struct popc_chatter {
	popc_chatter_config cfg;
	popc_chatter_thresholds thr;
	popc_environment env;
	double period_s;
	long long sub_ticks, seg_ticks;  /* ticks per chatter sub-block, per lc segment */
	/* sliding chatter window: ring of completed sub-blocks plus the open one */
	popc_chatter_block ring[POPC_CHATTER_SUBBLOCKS], cur;
	int ring_n, ring_head;
	/* limit cycle: ring of completed segments plus the open one */
	popc_chatter_segment seg[POPC_CHATTER_LC_SEGMENTS], seg_cur;
	int seg_n, seg_head;
	/* running state */
	int started, last_vsign, last_pcsign, lc_dir;
	double x_prev_m, lc_ext_m, lc_turn_m, lc_min_m, lc_max_m;
	/* intervals */
	int open;
	popc_chatter_interval cur_iv;
	popc_chatter_result res;
} popc_chatter;

/* The documented defaults (docs/ANALYSIS.md) with the paper scene's encoder
 * resolution (1e-5 m) and PC bound (5 N); set resolution_m and pc_bound_N
 * from the scene analysed. */
void popc_chatter_config_defaults(popc_chatter_config *cfg);

/* Sets a threshold by name ("window", "pc_rms_share", "pc_flip_share",
 * "vsign_share", "contact", "lc_window", "lc_amplitude", "lc_hysteresis",
 * "lc_cycles", "lc_freq_share", "lc_contact", "lc_sustain") from text. The
 * absolute names of before (pc_rms, pc_flip_rate, vsign_rate, lc_freq_min,
 * lc_freq_max, resolution) are refused with the relative name to use. */
int popc_chatter_config_set(popc_chatter_config *cfg, const char *name, const char *value,
			    popc_error *err);

/* Checks the configuration and the period (s), resolves the thresholds;
 * env says what "in contact" is. */
int popc_chatter_init(popc_chatter *d, const popc_chatter_config *cfg, double period_s,
		      const popc_environment *env, popc_error *err);

/* One control tick (t, x, f_pc, W, E_ref are used). Ticks come in time order. */
void popc_chatter_add(popc_chatter *d, const popc_tick *t);

/* Closes the open interval and fills *r. Call once, after the last tick.
 * r->windows == 0: fewer ticks than r->window_ticks, chatter not checked;
 * r->lc_ticks < r->lc_min_ticks: the limit cycle not checked. */
void popc_chatter_finish(popc_chatter *d, popc_chatter_result *r);

/* A verdict on chatter (chatter_s, n_intervals mean something): at least one
 * full window. A zeroed result is not checked. */
static inline int popc_chatter_checked(const popc_chatter_result *r)
{
	return r->windows > 0;
}

/* A verdict on the limit cycle (limit_cycle and the lc_* metrics mean
 * something): the last window covers at least half its length. A zeroed
 * result is not checked. */
static inline int popc_chatter_lc_checked(const popc_chatter_result *r)
{
	return r->lc_min_ticks > 0 && r->lc_ticks >= r->lc_min_ticks;
}

#endif
