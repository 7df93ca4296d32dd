/* Streaming chatter and limit-cycle detector (chatter.h; docs/ANALYSIS.md). */
#include "popc/core/chatter.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/util/parse.h"

void popc_chatter_config_defaults(popc_chatter_config *c)
{
	memset(c, 0, sizeof *c);
	/* 100 ms: ten cycles of a 100 Hz switching, one cycle of the ~9 Hz contact mode */
	c->window_s = 0.1;
	/* 5 % of the bound: chatter at the bound has an RMS near the bound (20
	 * times this); the paper scene's improved stays below 1.7 % (0.082 N of
	 * 5 N), its one-count dither with a +-0.3 N PC is 6 % (docs/ANALYSIS.md) */
	c->pc_rms_share = 0.05;
	/* a flip every 10 control ticks or faster (100 /s at 1 kHz): chatter
	 * switches on the scale of the control period; the 9 Hz contact mode
	 * reverses 18 times a second, 5.6 times fewer */
	c->pc_flip_share = 0.1;
	c->vsign_share = 0.1;
	c->contact_min = 0.5;
	c->lc_window_s = 2.0;
	/* 4 counts of half swing (8 peak to peak): 4 times the one-count
	 * quantization dither's swing; the smallest cycle a coarse encoder still
	 * shows as motion */
	c->lc_amplitude_min_counts = 4.0;
	/* a reversal needs a return of 3 counts: a one-count dither (swing 1)
	 * and one straddling two boundaries (swing 2) never count */
	c->lc_hysteresis_counts = 3.0;
	/* two full cycles in the window (1 Hz in 2 s) */
	c->lc_cycles_min = 2.0;
	/* at least 10 samples per cycle (100 Hz at 1 kHz): the sample nearest a
	 * peak is within pi/10 of phase of it, so a swing is measured to within
	 * 1 - cos(pi/10) = 5 % */
	c->lc_freq_max_share = 0.1;
	c->lc_contact_min = 0.1;
	c->lc_sustain_min = 0.8;
	c->resolution_m = 1e-5;
	c->pc_bound_N = 5.0;
}

typedef struct threshold_key {
	const char *name;
	size_t offset;
	double lo, hi;
} threshold_key;

static const threshold_key keys[] = {
	{"window", offsetof(popc_chatter_config, window_s), 1e-6, 1e3},
	{"pc_rms_share", offsetof(popc_chatter_config, pc_rms_share), 0.0, 1e6},
	{"pc_flip_share", offsetof(popc_chatter_config, pc_flip_share), 0.0, 1.0},
	{"vsign_share", offsetof(popc_chatter_config, vsign_share), 0.0, 1.0},
	{"contact", offsetof(popc_chatter_config, contact_min), 0.0, 1.0},
	{"lc_window", offsetof(popc_chatter_config, lc_window_s), 1e-6, 1e6},
	{"lc_amplitude", offsetof(popc_chatter_config, lc_amplitude_min_counts), 0.0, 1e12},
	{"lc_hysteresis", offsetof(popc_chatter_config, lc_hysteresis_counts), 1e-3, 1e12},
	{"lc_cycles", offsetof(popc_chatter_config, lc_cycles_min), 0.0, 1e9},
	{"lc_freq_share", offsetof(popc_chatter_config, lc_freq_max_share), 0.0, 0.5},
	{"lc_contact", offsetof(popc_chatter_config, lc_contact_min), 0.0, 1.0},
	{"lc_sustain", offsetof(popc_chatter_config, lc_sustain_min), 0.0, 1e9},
};

/* The absolute thresholds of before and what replaces each. A hint names this
 * module's own parameters (popc_chatter_config's and the control period);
 * a program names them as its user sets them (popc_error_name_params). */
static const struct {
	const char *old_name, *hint;
} renamed[] = {
	{"pc_rms", "pc_rms_share (a share of pc_bound_N; 0.05: 0.25 N at 5 N)"},
	{"pc_flip_rate", "pc_flip_share (flips per control tick; 0.1: 100 /s at 1 kHz)"},
	{"vsign_rate", "vsign_share (sign changes per control tick; 0.1: 100 /s at 1 kHz)"},
	{"lc_freq_min", "lc_cycles (full cycles in lc_window; 2: 1 Hz in 2 s)"},
	{"lc_freq_max", "lc_freq_share (a share of the control rate; 0.1: 100 Hz at 1 kHz)"},
	{"resolution", "resolution_m (the scene's, not a threshold)"},
};

int popc_chatter_config_set(popc_chatter_config *c, const char *name, const char *value,
			    popc_error *err)
{
	for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
		if (strcmp(keys[i].name, name) != 0)
			continue;
		double v;
		if (popc_parse_double_text(value, &v) != 0 || v < keys[i].lo || v > keys[i].hi)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "threshold %s = '%s': expected a number in [%g, %g]", name,
					      value, keys[i].lo, keys[i].hi);
		*(double *)(void *)((char *)c + keys[i].offset) = v;
		return 0;
	}
	for (size_t i = 0; i < sizeof renamed / sizeof renamed[0]; i++)
		if (strcmp(renamed[i].old_name, name) == 0)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "threshold '%s' is relative to the scene now: use %s", name,
					      renamed[i].hint);
	char list[256] = "";
	size_t n = 0;
	for (size_t i = 0; i < sizeof keys / sizeof keys[0] && n < sizeof list; i++)
		n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", keys[i].name);
	return popc_error_set(err, POPC_ERR_INVALID, "unknown threshold '%s' (%s)", name, list);
}

int popc_chatter_init(popc_chatter *d, const popc_chatter_config *cfg, double period_s,
		      const popc_environment *env, popc_error *err)
{
	memset(d, 0, sizeof *d);
	if (!(period_s > 0.0) || !isfinite(period_s))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "chatter detector: period %g s must be positive", period_s);
	if (!(cfg->resolution_m > 0.0) || !(cfg->window_s > 0.0) || !(cfg->lc_window_s > 0.0) ||
	    !(cfg->lc_hysteresis_counts > 0.0) || !(cfg->pc_bound_N >= 0.0) ||
	    !isfinite(cfg->pc_bound_N) || !isfinite(cfg->resolution_m))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "chatter detector: resolution, window, lc_window and "
				      "lc_hysteresis must be positive, the PC bound finite and >= 0");
	popc_chatter_thresholds th = {
		.pc_rms_min_N = cfg->pc_rms_share * cfg->pc_bound_N,
		.pc_flip_rate_min_Hz = cfg->pc_flip_share / period_s,
		.vsign_rate_min_Hz = cfg->vsign_share / period_s,
		.lc_amplitude_min_m = cfg->lc_amplitude_min_counts * cfg->resolution_m,
		.lc_hysteresis_m = cfg->lc_hysteresis_counts * cfg->resolution_m,
		.lc_freq_min_Hz = cfg->lc_cycles_min / cfg->lc_window_s,
		.lc_freq_max_Hz = cfg->lc_freq_max_share / period_s,
	};
	/* lc_freq_min above lc_freq_max (a log sampled below 20 Hz with the
	 * defaults) is no error: no frequency passes, and the limit cycle cannot
	 * be flagged at that rate */
	d->cfg = *cfg;
	d->thr = th;
	d->res.thr = th;
	d->env = *env;
	d->period_s = period_s;
	double sub = cfg->window_s / period_s / POPC_CHATTER_SUBBLOCKS;
	double seg = cfg->lc_window_s / period_s / POPC_CHATTER_LC_SEGMENTS;
	if (sub > 1e12 || seg > 1e12)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "chatter detector: window %g s and lc_window %g s at a period of "
				      "%g s are %.3g and %.3g ticks, more than 1e13 (at most 1e12 ticks "
				      "per sub-block): give shorter windows (window_s, lc_window_s) or the "
				      "log's true period (period_s)",
				      cfg->window_s, cfg->lc_window_s, period_s, cfg->window_s / period_s,
				      cfg->lc_window_s / period_s);
	d->sub_ticks = sub < 1.0 ? 1 : llround(sub);
	d->seg_ticks = seg < 1.0 ? 1 : llround(seg);
	d->res.window_ticks = d->sub_ticks * POPC_CHATTER_SUBBLOCKS;
	/* half the limit-cycle window, in whole segments as the window is kept:
	 * a shorter stretch holds too few turning points for a frequency and a
	 * sustain (first against last quarter) to mean anything */
	d->res.lc_min_ticks = d->seg_ticks * (POPC_CHATTER_LC_SEGMENTS / 2);
	return 0;
}

static void close_interval(popc_chatter *d)
{
	if (!d->open)
		return;
	popc_chatter_result *r = &d->res;
	r->chatter_s += d->cur_iv.end_s - d->cur_iv.start_s;
	if (r->n_stored < POPC_CHATTER_MAX_INTERVALS)
		r->intervals[r->n_stored++] = d->cur_iv;
	r->n_intervals++;
	d->open = 0;
}

/* A full window: the POPC_CHATTER_SUBBLOCKS newest sub-blocks. */
static void evaluate_window(popc_chatter *d)
{
	popc_chatter_block w;
	memset(&w, 0, sizeof w);
	for (int i = 0; i < d->ring_n; i++) {
		const popc_chatter_block *b = &d->ring[(d->ring_head + i) % POPC_CHATTER_SUBBLOCKS];
		if (i == 0)
			w.t_first_s = b->t_first_s;
		w.t_last_s = b->t_last_s;
		w.ticks += b->ticks;
		w.contact_ticks += b->contact_ticks;
		w.pc_flips += b->pc_flips;
		w.vsign_changes += b->vsign_changes;
		popc_sum_squares_merge(&w.pc_sq, &b->pc_sq);
	}
	const double T = d->period_s;
	double rms = popc_sum_squares_rms(&w.pc_sq, (double)w.ticks);
	double flips = (double)w.pc_flips / ((double)w.ticks * T);
	double contact = (double)w.contact_ticks / (double)w.ticks;
	double vrate = w.contact_ticks ? (double)w.vsign_changes / ((double)w.contact_ticks * T) : 0.0;
	popc_chatter_result *r = &d->res;
	r->windows++;
	if (rms > r->max_pc_rms_N)
		r->max_pc_rms_N = rms;
	if (flips > r->max_pc_flip_rate_Hz)
		r->max_pc_flip_rate_Hz = flips;
	if (contact >= d->cfg.contact_min && vrate > r->max_vsign_rate_Hz)
		r->max_vsign_rate_Hz = vrate;
	const popc_chatter_thresholds *th = &d->thr;
	int flagged = contact >= d->cfg.contact_min && rms >= th->pc_rms_min_N &&
		      flips >= th->pc_flip_rate_min_Hz && vrate >= th->vsign_rate_min_Hz;
	if (!flagged)
		return;
	/* the flagged stretch: from the first to the last sub-block in which the
	 * PC force switched sign, so an interval does not grow by a window length
	 * at each end; a sub-block covers its ticks: [t_first, t_last + T) */
	double start = w.t_first_s, end = w.t_last_s + T;
	int first = -1, last = -1;
	for (int i = 0; i < d->ring_n; i++) {
		if (d->ring[(d->ring_head + i) % POPC_CHATTER_SUBBLOCKS].pc_flips > 0) {
			if (first < 0)
				first = i;
			last = i;
		}
	}
	if (first >= 0) {
		start = d->ring[(d->ring_head + first) % POPC_CHATTER_SUBBLOCKS].t_first_s;
		end = d->ring[(d->ring_head + last) % POPC_CHATTER_SUBBLOCKS].t_last_s + T;
	}
	if (d->open && start <= d->cur_iv.end_s) {
		d->cur_iv.end_s = end;
		if (rms > d->cur_iv.pc_rms_max_N)
			d->cur_iv.pc_rms_max_N = rms;
		return;
	}
	close_interval(d);
	d->open = 1;
	d->cur_iv.start_s = start;
	d->cur_iv.end_s = end;
	d->cur_iv.pc_rms_max_N = rms;
}

/* Turning points with hysteresis h: a reversal is recorded when the position
 * has come back by h from its extreme; its swing is extreme - previous turn. */
static void track_turns(popc_chatter *d, double x)
{
	const double h = d->thr.lc_hysteresis_m;
	double swing = 0.0;
	if (d->lc_dir == 0) {
		if (!d->started) {
			d->lc_min_m = d->lc_max_m = x;
			return;
		}
		if (x < d->lc_min_m)
			d->lc_min_m = x;
		if (x > d->lc_max_m)
			d->lc_max_m = x;
		if (d->lc_max_m - x >= h) {
			d->lc_dir = -1;
			d->lc_turn_m = d->lc_max_m;
			d->lc_ext_m = x;
		} else if (x - d->lc_min_m >= h) {
			d->lc_dir = 1;
			d->lc_turn_m = d->lc_min_m;
			d->lc_ext_m = x;
		}
		return;
	}
	if (d->lc_dir > 0) {
		if (x > d->lc_ext_m) {
			d->lc_ext_m = x;
			return;
		}
		if (d->lc_ext_m - x < h)
			return;
		swing = d->lc_ext_m - d->lc_turn_m;
	} else {
		if (x < d->lc_ext_m) {
			d->lc_ext_m = x;
			return;
		}
		if (x - d->lc_ext_m < h)
			return;
		swing = d->lc_turn_m - d->lc_ext_m;
	}
	d->lc_turn_m = d->lc_ext_m;
	d->lc_ext_m = x;
	d->lc_dir = -d->lc_dir;
	d->seg_cur.reversals++;
	d->seg_cur.swing_sum_m += swing;
}

static int sign_of(double v)
{
	return v > 0.0 ? 1 : v < 0.0 ? -1 : 0;
}

void popc_chatter_add(popc_chatter *d, const popc_tick *t)
{
	int vchange = 0, flip = 0;
	if (d->started) {
		/* velocity sign: sign of the last nonzero displacement (as metrics.c) */
		int s = sign_of(t->x_m - d->x_prev_m);
		if (s != 0) {
			vchange = d->last_vsign != 0 && s != d->last_vsign;
			d->last_vsign = s;
		}
	}
	int ps = sign_of(t->f_pc_N);
	if (ps != 0) {
		flip = d->last_pcsign != 0 && ps != d->last_pcsign;
		d->last_pcsign = ps;
	}
	int contact = popc_environment_in_contact(&d->env, t->x_m);

	popc_chatter_block *b = &d->cur;
	if (b->ticks == 0)
		b->t_first_s = t->t_s;
	b->t_last_s = t->t_s;
	b->ticks++;
	b->contact_ticks += contact;
	b->pc_flips += flip;
	b->vsign_changes += contact && vchange;
	popc_sum_squares_add(&b->pc_sq, t->f_pc_N);
	if (b->ticks == d->sub_ticks) {
		if (d->ring_n < POPC_CHATTER_SUBBLOCKS) {
			d->ring[(d->ring_head + d->ring_n) % POPC_CHATTER_SUBBLOCKS] = *b;
			d->ring_n++;
		} else {
			d->ring[d->ring_head] = *b;
			d->ring_head = (d->ring_head + 1) % POPC_CHATTER_SUBBLOCKS;
		}
		memset(b, 0, sizeof *b);
		if (d->ring_n == POPC_CHATTER_SUBBLOCKS)
			evaluate_window(d);
	}

	track_turns(d, t->x_m);
	popc_chatter_segment *g = &d->seg_cur;
	double wme = t->W_J - t->E_ref_J;
	if (g->ticks == 0) {
		g->t_first_s = t->t_s;
		g->wme_first_J = wme;
	}
	g->t_last_s = t->t_s;
	g->wme_last_J = wme;
	g->ticks++;
	g->contact_ticks += contact;
	popc_sum_squares_add(&g->pc_sq, t->f_pc_N);
	if (g->ticks == d->seg_ticks) {
		if (d->seg_n < POPC_CHATTER_LC_SEGMENTS) {
			d->seg[(d->seg_head + d->seg_n) % POPC_CHATTER_LC_SEGMENTS] = *g;
			d->seg_n++;
		} else {
			d->seg[d->seg_head] = *g;
			d->seg_head = (d->seg_head + 1) % POPC_CHATTER_LC_SEGMENTS;
		}
		memset(g, 0, sizeof *g);
	}
	d->x_prev_m = t->x_m;
	d->started = 1;
}

/* How many whole segments, taken from one end of the window (the oldest first,
 * or the newest: the open segment then the full ones before it), hold the
 * number of ticks nearest a quarter of the window's ticks (ties: fewer). A
 * quarter counted in segments (n / 4) would make a log ending one tick into a
 * new segment compare that one tick with the first quarter; counted in ticks,
 * a quarter is within half a segment of a quarter wherever the log ends. */
static int quarter_segments(const popc_chatter_segment *const *list, int n, long long ticks,
			    int newest, long long *quarter_ticks)
{
	long long acc = 0; /* ticks of the m segments taken, times 4 below */
	int m = 0;
	while (m < n) {
		long long next = list[newest ? n - 1 - m : m]->ticks;
		if (m > 0 && llabs(4 * acc - ticks) <= llabs(4 * (acc + next) - ticks))
			break;
		acc += next;
		m++;
	}
	*quarter_ticks = acc;
	return m;
}

/* Mean half swing over segments [from, to) of the chronological list. */
static double amplitude_of(const popc_chatter_segment *const *list, int from, int to,
			   long long *reversals)
{
	double sum = 0.0;
	long long n = 0;
	for (int i = from; i < to; i++) {
		sum += list[i]->swing_sum_m;
		n += list[i]->reversals;
	}
	*reversals = n;
	return n ? sum / (double)n / 2.0 : 0.0;
}

void popc_chatter_finish(popc_chatter *d, popc_chatter_result *r)
{
	close_interval(d);
	/* the last lc window: completed segments, oldest first, then the open one */
	const popc_chatter_segment *list[POPC_CHATTER_LC_SEGMENTS + 1];
	int n = 0;
	for (int i = 0; i < d->seg_n; i++)
		list[n++] = &d->seg[(d->seg_head + i) % POPC_CHATTER_LC_SEGMENTS];
	if (d->seg_cur.ticks > 0)
		list[n++] = &d->seg_cur;
	popc_chatter_result *res = &d->res;
	long long ticks = 0, contact = 0, rev = 0;
	popc_sum_squares pc_sq = {0.0, 0.0, 0.0};
	for (int i = 0; i < n; i++) {
		ticks += list[i]->ticks;
		contact += list[i]->contact_ticks;
		popc_sum_squares_merge(&pc_sq, &list[i]->pc_sq);
	}
	res->lc_ticks = ticks;
	if (ticks > 0) {
		res->lc_span_s = (double)ticks * d->period_s;
		res->lc_start_s = list[0]->t_first_s;
		res->lc_end_s = list[n - 1]->t_last_s;
		res->lc_amplitude_m = amplitude_of(list, 0, n, &rev);
		res->lc_frequency_Hz = (double)rev / 2.0 / res->lc_span_s;
		res->lc_contact = (double)contact / (double)ticks;
		res->lc_pc_rms_N = popc_sum_squares_rms(&pc_sq, (double)ticks);
		res->lc_w_drift_J = list[n - 1]->wme_last_J - list[0]->wme_first_J;
		/* sustained: the last quarter still swings like the first; the
		 * quarters in ticks (quarter_segments) */
		long long ticks_first, ticks_last;
		int q_first = quarter_segments(list, n, ticks, 0, &ticks_first);
		int q_last = quarter_segments(list, n, ticks, 1, &ticks_last);
		long long rev_first, rev_last;
		double a_first = amplitude_of(list, 0, q_first, &rev_first);
		double a_last = amplitude_of(list, n - q_last, n, &rev_last);
		/* A quarter without a turning point shows no oscillation to
		 * compare: sustain 0. At the end: the motion stopped. At the
		 * start: the oscillation began inside the window, e.g. an
		 * approach from rest and its bounces on the wall (the seed's
		 * scene: at rest until 0.5 s, first turning point at the wall at
		 * 0.75 s), which is no evidence of a cycle that persists; a real
		 * limit cycle is flagged once the window's first quarter holds
		 * it (the paper scene without PC: from 2.67 s of log on).
		 *
		 * Both present: the amplitude ratio is a decay over the time
		 * between the quarters' centres, 0.75 of the window's span, so a
		 * fixed ratio would accept a faster decay in a shorter log (a
		 * 1 s log: twice as fast as a 2 s one). The ratio is scaled to
		 * the full window's separation, 0.75 lc_window (1.5 s):
		 * sustain = ratio^(full separation / separation). lc_sustain =
		 * 0.8 then means an amplitude that loses at most a fifth in 1.5 s
		 * (a decay time constant of 6.7 s or longer). Measured on the
		 * paper scene's turning points (popc run data/scenes/paper.ini
		 * --variant V): ref-energy's and improved's contact bounce
		 * decays with a time constant of 1.0-1.2 s (swing 4.3 mm at
		 * 0.85 s, 2.0 mm at 1.55 s, 1.4 mm at 1.97 s), 0.22-0.29 over
		 * 1.5 s, but the 1 s log of its ticks 800-1799 measured 0.59,
		 * which passed unscaled (0.35 scaled); po-pc's decays with 2.2 s
		 * early, 3.2 s late (sustain 0.48-0.62 over 3.4-5 s logs: the
		 * close call of docs/ANALYSIS.md, flagged at 3.5-4.25 s while the
		 * threshold was 0.5); none's keeps its swing of 3.5 mm (0.97):
		 * 0.8 lies between, 1.2-1.3 from each. */
		if (rev_last == 0 || rev_first == 0) {
			res->lc_sustain = 0.0;
		} else {
			double sep = (double)ticks - (double)(ticks_first + ticks_last) / 2.0;
			double full_sep = 0.75 * (double)(d->seg_ticks * POPC_CHATTER_LC_SEGMENTS);
			double ratio = a_last / a_first;
			/* (below half a window, no verdict: the ratio as it is) */
			res->lc_sustain = ticks >= res->lc_min_ticks && sep > 0.0
						  ? pow(ratio, full_sep / sep)
						  : ratio;
		}
	}
	const popc_chatter_config *c = &d->cfg;
	const popc_chatter_thresholds *th = &d->thr;
	res->limit_cycle = popc_chatter_lc_checked(res) && res->lc_amplitude_m >= th->lc_amplitude_min_m &&
			   res->lc_frequency_Hz >= th->lc_freq_min_Hz &&
			   res->lc_frequency_Hz <= th->lc_freq_max_Hz &&
			   res->lc_contact >= c->lc_contact_min && res->lc_sustain >= c->lc_sustain_min;
	*r = *res;
}
