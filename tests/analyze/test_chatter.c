/* The streaming chatter and limit-cycle detector (popc/chatter.h) on
 * synthetic tick streams whose answer is known by construction. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "popc/core/chatter.h"
#include "popc/core/metrics.h"
#include "popc/core/sum_squares.h"

#define T_S 1e-3
#define DELTA_M 1e-5

static const double two_pi = 6.283185307179586;

static popc_environment wall(void)
{
	popc_environment e = {POPC_ENV_WALL, 1000.0, 0.0, 0.0};
	return e;
}

static void start(popc_chatter *d, popc_chatter_config *cfg)
{
	popc_chatter_config_defaults(cfg);
	cfg->resolution_m = DELTA_M;
	popc_environment env = wall();
	popc_error err;
	assert_int_equal(popc_chatter_init(d, cfg, T_S, &env, &err), 0);
}

/* A tick at step k with the position quantized as the encoder would. */
static void add(popc_chatter *d, long long k, double x_m, double f_pc_N)
{
	popc_tick t = {0};
	t.t_s = (double)k * T_S;
	t.count = (long long)floor(x_m / DELTA_M);
	t.x_m = (double)t.count * DELTA_M;
	t.f_pc_N = f_pc_N;
	popc_chatter_add(d, &t);
}

static void quiet_contact_is_not_flagged(void **state)
{
	(void)state;
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	for (long long k = 0; k < 5000; k++)
		add(&d, k, 1e-3, 0.0);
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	assert_int_equal(r.n_intervals, 0);
	assert_true(r.chatter_s == 0.0);
	assert_int_equal(r.limit_cycle, 0);
}

/* PC force switching +-5 N every tick with the position dithering one count,
 * from 1 s to 2 s: one interval covering that second (to a window's length). */
static void chatter_burst_is_one_interval(void **state)
{
	(void)state;
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	for (long long k = 0; k < 3000; k++) {
		int burst = k >= 1000 && k < 2000;
		double x = 1e-3 + (burst && (k & 1) ? DELTA_M : 0.0) + 0.5 * DELTA_M;
		add(&d, k, x, burst ? ((k & 1) ? 5.0 : -5.0) : 0.0);
	}
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	assert_int_equal(r.n_intervals, 1);
	assert_true(r.intervals[0].start_s >= 0.9 && r.intervals[0].start_s <= 1.01);
	assert_true(r.intervals[0].end_s >= 1.99 && r.intervals[0].end_s <= 2.1);
	assert_true(fabs(r.chatter_s - 1.0) < 0.11);
	assert_true(fabs(r.intervals[0].pc_rms_max_N - 5.0) < 1e-9);
	assert_int_equal(r.limit_cycle, 0);
}

/* The same switching without contact (x < 0: in free space) is not chatter. */
static void no_contact_no_chatter(void **state)
{
	(void)state;
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	for (long long k = 0; k < 2000; k++)
		add(&d, k, -1e-3 + ((k & 1) ? DELTA_M : 0.0), (k & 1) ? 5.0 : -5.0);
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	assert_int_equal(r.n_intervals, 0);
}

/* Small PC force (0.1 N RMS, like improved) switching fast is not flagged. */
static void small_pc_force_not_flagged(void **state)
{
	(void)state;
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	for (long long k = 0; k < 2000; k++)
		add(&d, k, 1e-3 + ((k & 1) ? DELTA_M : 0.0), (k & 1) ? 0.1 : -0.1);
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	assert_int_equal(r.n_intervals, 0);
	assert_true(fabs(r.max_pc_rms_N - 0.1) < 1e-12);
}

/* Bursts beyond the stored intervals are still counted and timed. */
static void intervals_are_bounded(void **state)
{
	(void)state;
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	const int bursts = POPC_CHATTER_MAX_INTERVALS + 8;
	for (long long k = 0; k < (long long)bursts * 400; k++) {
		int burst = k % 400 < 200;
		double x = 1e-3 + 0.5 * DELTA_M + (burst && (k & 1) ? DELTA_M : 0.0);
		add(&d, k, x, burst ? ((k & 1) ? 5.0 : -5.0) : 0.0);
	}
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	assert_int_equal(r.n_intervals, bursts);
	assert_int_equal(r.n_stored, POPC_CHATTER_MAX_INTERVALS);
	assert_true(r.chatter_s > 0.2 * bursts * 0.9);
}

static popc_chatter_result sine(double amp_m, double freq_Hz, double tau_s, double seconds)
{
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	long long n = (long long)(seconds / T_S);
	for (long long k = 0; k <= n; k++) {
		double t = (double)k * T_S;
		double a = tau_s > 0 ? amp_m * exp(-t / tau_s) : amp_m;
		add(&d, k, 1e-3 + a * sin(two_pi * freq_Hz * t), 0.0);
	}
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	return r;
}

/* The paper scene's limit cycle: 9 Hz, +-1.5 mm around 1 mm (in and out of contact). */
static void sustained_oscillation_is_a_limit_cycle(void **state)
{
	(void)state;
	popc_chatter_result r = sine(1.5e-3, 9.0, 0.0, 5.0);
	assert_int_equal(r.limit_cycle, 1);
	assert_true(fabs(r.lc_amplitude_m - 1.5e-3) < 0.1e-3);
	assert_true(fabs(r.lc_frequency_Hz - 9.0) < 0.5);
	assert_true(r.lc_contact > 0.6 && r.lc_contact < 0.9);
	assert_true(r.lc_sustain > 0.9 && r.lc_sustain < 1.1);
	assert_true(fabs(r.lc_span_s - 2.0) < 0.01);
	assert_int_equal(r.n_intervals, 0);
}

static void decaying_tiny_or_fast_oscillation_is_not(void **state)
{
	(void)state;
	/* decays with tau = 1 s: still 1.5 mm e^-3 ~ 75 um at 3 s, but fading */
	popc_chatter_result r = sine(1.5e-3 * exp(3.0), 9.0, 1.0, 5.0);
	assert_true(r.lc_sustain < 0.5);
	assert_int_equal(r.limit_cycle, 0);
	/* sustained, 3 counts: below the 4-count amplitude threshold (20 counts,
	 * below the 50 of before, is a limit cycle now: test_chatter_synthetic.sh) */
	r = sine(3 * DELTA_M, 9.0, 0.0, 5.0);
	assert_int_equal(r.limit_cycle, 0);
	r = sine(20 * DELTA_M, 9.0, 0.0, 5.0);
	assert_true(r.lc_sustain > 0.8);
	assert_int_equal(r.limit_cycle, 1);
	/* sustained, large, but 125 Hz: 8 samples a cycle, above lc_freq_share
	 * 0.1 of 1 kHz */
	r = sine(1.5e-3, 125.0, 0.0, 5.0);
	assert_int_equal(r.limit_cycle, 0);
	/* too short a log to judge (0.5 s of a 2 s window): not checked, so its
	 * limit_cycle = 0 is no "no limit cycle" */
	r = sine(1.5e-3, 9.0, 0.0, 0.5);
	assert_int_equal(r.limit_cycle, 0);
	assert_false(popc_chatter_lc_checked(&r));
}

/* The limit cycle needs half its window (4 of 8 segments: 1000 ticks of 1 ms
 * for the default 2 s). A shorter log is not checked, whatever it holds: here
 * the paper scene's 9 Hz, +-1.5 mm limit cycle, flagged from 1000 ticks on. */
static void short_log_limit_cycle_not_checked(void **state)
{
	(void)state;
	static const struct {
		long long ticks;
		int checked;
	} cases[] = {{0, 0}, {1, 0}, {100, 0}, {999, 0}, {1000, 1}, {1250, 1}, {2500, 1}, {5000, 1}};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_chatter d;
		popc_chatter_config cfg;
		start(&d, &cfg);
		for (long long k = 0; k < cases[i].ticks; k++)
			add(&d, k, 1e-3 + 1.5e-3 * sin(two_pi * 9.0 * (double)k * T_S), 0.0);
		popc_chatter_result r;
		popc_chatter_finish(&d, &r);
		assert_int_equal(r.lc_min_ticks, 1000);
		/* the window holds 8 segments of 250 ticks at most */
		assert_int_equal(r.lc_ticks, cases[i].ticks < 2000 ? cases[i].ticks : 2000 + cases[i].ticks % 250);
		assert_int_equal(popc_chatter_lc_checked(&r), cases[i].checked);
		assert_int_equal(r.limit_cycle, cases[i].checked);
	}
	/* a zeroed result (a caller that never ran the detector) is not checked */
	popc_chatter_result z = {0};
	assert_false(popc_chatter_lc_checked(&z));
	assert_false(popc_chatter_checked(&z));
	/* another window: half of it in whole segments, round(0.3 s / 8 / T) = 38 */
	popc_chatter d;
	popc_chatter_config cfg;
	popc_chatter_config_defaults(&cfg);
	cfg.lc_window_s = 0.3;
	popc_environment env = wall();
	popc_error err;
	assert_int_equal(popc_chatter_init(&d, &cfg, T_S, &env, &err), 0);
	for (long long k = 0; k < 151; k++)
		add(&d, k, 1e-3, 0.0);
	popc_chatter_result r;
	popc_chatter_finish(&d, &r);
	assert_int_equal(r.lc_min_ticks, 152);
	assert_false(popc_chatter_lc_checked(&r));
}

/* The verdict does not depend on where the log ends within a 250-tick segment
 * of the window: the paper scene's 9 Hz, +-1.5 mm limit cycle is flagged at
 * every length from 1000 ticks (half the window) to past the first slide of a
 * full window, the lengths one tick either side of a segment boundary and one
 * tick into a new segment (1001, 1251, ..., 2001) included. The sustain
 * compares quarters counted in ticks: a quarter counted in segments made a
 * 1001-tick log compare its last tick alone with the first quarter (no turning
 * point: sustain 0, no limit cycle; 72 of these lengths missed). Sustain of
 * this steady sine, measured at every length: 1.00 to 1.31 (above 1: the first
 * quarter's first swing starts at the log's first sample, mid-swing, and a
 * 1 s log's ratio is squared to the full window's 1.5 s); 0.8 to 1.5 allowed. */
static void limit_cycle_wherever_the_log_ends(void **state)
{
	(void)state;
	const long long first = 1000, last = 2300;
	popc_chatter_config cfg;
	popc_chatter_config_defaults(&cfg);
	cfg.resolution_m = DELTA_M;
	popc_environment env = wall();
	popc_error err;
	for (long long n = first; n <= last; n++) {
		popc_chatter d;
		assert_int_equal(popc_chatter_init(&d, &cfg, T_S, &env, &err), 0);
		for (long long k = 0; k < n; k++)
			add(&d, k, 1e-3 + 1.5e-3 * sin(two_pi * 9.0 * (double)k * T_S), 0.0);
		popc_chatter_result r;
		popc_chatter_finish(&d, &r);
		if (!r.limit_cycle || r.lc_sustain < 0.8 || r.lc_sustain > 1.5)
			fail_msg("%lld ticks: limit_cycle %d, sustain %g (amplitude %g m, %g Hz)", n,
				 r.limit_cycle, r.lc_sustain, r.lc_amplitude_m, r.lc_frequency_Hz);
	}
}

/* The seed's scene before contact (data/scenes/fig3.ini): at rest in free
 * space at -10 mm until 0.5 s, an approach at 50 mm/s reaching the wall at
 * 0.7 s, then (here) a steady 9 Hz, +-1.5 mm oscillation about the wall. While
 * the window's first quarter is at rest the oscillation began inside the
 * window and is not shown to persist: sustain 0, no limit cycle (it was
 * flagged: a first quarter without turning points counted as "started from
 * rest, not decaying", so every approach and bounce of a 1-2 s log was a limit
 * cycle). Once the window lies on the oscillation (3.5 s of log: the last 2 s)
 * it is flagged. */
static void approach_from_rest_is_not_a_limit_cycle(void **state)
{
	(void)state;
	popc_chatter_config cfg;
	popc_chatter_config_defaults(&cfg);
	cfg.resolution_m = DELTA_M;
	popc_environment env = wall();
	popc_error err;
	static const long long lengths[] = {1000, 1001, 1249, 1250, 1251, 1500, 1750, 1999, 2000, 3500};
	for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
		popc_chatter d;
		assert_int_equal(popc_chatter_init(&d, &cfg, T_S, &env, &err), 0);
		for (long long k = 0; k < lengths[i]; k++) {
			double t = (double)k * T_S;
			double x = t < 0.5 ? -10e-3 : t < 0.7 ? -10e-3 + 0.05 * (t - 0.5)
							 : 1.5e-3 * sin(two_pi * 9.0 * (t - 0.7));
			add(&d, k, x, 0.0);
		}
		popc_chatter_result r;
		popc_chatter_finish(&d, &r);
		assert_true(popc_chatter_lc_checked(&r));
		int whole = lengths[i] == 3500;
		if (r.limit_cycle != whole)
			fail_msg("%lld ticks: limit_cycle %d (amplitude %g m, %g Hz, contact %g, sustain %g)",
				 lengths[i], r.limit_cycle, r.lc_amplitude_m, r.lc_frequency_Hz,
				 r.lc_contact, r.lc_sustain);
		if (!whole) {
			/* the other criteria pass: only the sustain decides */
			assert_true(r.lc_amplitude_m >= 50 * DELTA_M);
			assert_true(r.lc_frequency_Hz >= 1.0 && r.lc_contact >= 0.1);
			assert_true(r.lc_sustain == 0.0);
		} else {
			assert_true(fabs(r.lc_amplitude_m - 1.5e-3) < 0.1e-3);
		}
	}
}

/* A contact bounce decaying with a time constant of 1.5 s (ref-energy's and
 * improved's decay in 1.0-1.2 s: faster) is no limit cycle at any length. Its
 * amplitude ratio between the quarters of a 1 s log (0.75 s apart) is
 * e^-0.5 = 0.61, which passed the 0.5 threshold set for the 1.5 s of a full
 * window, over which it is e^-1 = 0.37; scaled to 1.5 s every length gives
 * about that (measured 0.36 to 0.39 over 1000-2500 ticks; 0.45 allowed). The
 * log starts at a crest, a true turning point, so that its first swing is a
 * whole one; the amplitude stays above its threshold (at least 1.2 mm), so the
 * sustain alone decides. */
static void decaying_bounce_is_not_a_limit_cycle_at_any_length(void **state)
{
	(void)state;
	popc_chatter_config cfg;
	popc_chatter_config_defaults(&cfg);
	cfg.resolution_m = DELTA_M;
	popc_environment env = wall();
	popc_error err;
	for (long long n = 1000; n <= 2500; n++) {
		popc_chatter d;
		assert_int_equal(popc_chatter_init(&d, &cfg, T_S, &env, &err), 0);
		for (long long k = 0; k < n; k++) {
			double t = (double)k * T_S;
			add(&d, k, 1e-3 + 3e-3 * exp(-t / 1.5) * cos(two_pi * 9.0 * t), 0.0);
		}
		popc_chatter_result r;
		popc_chatter_finish(&d, &r);
		if (r.limit_cycle || r.lc_amplitude_m < 50 * DELTA_M || r.lc_sustain > 0.45)
			fail_msg("%lld ticks: limit_cycle %d, amplitude %g m, sustain %g", n,
				 r.limit_cycle, r.lc_amplitude_m, r.lc_sustain);
	}
}

/* A log shorter than one window is not checked: windows == 0 (the caller says
 * "not checked", never "no chatter"); one tick more than a window less one
 * gives the first window. Chattering input, so a checked window flags. */
static void short_log_is_not_checked(void **state)
{
	(void)state;
	static const struct {
		long long ticks, windows;
	} cases[] = {{0, 0}, {1, 0}, {99, 0}, {100, 1}, {110, 2}, {119, 2}};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_chatter d;
		popc_chatter_config cfg;
		start(&d, &cfg);
		for (long long k = 0; k < cases[i].ticks; k++)
			add(&d, k, 1e-3 + (double)(k % 2) * DELTA_M, k % 2 ? 5.0 : -5.0);
		popc_chatter_result r;
		popc_chatter_finish(&d, &r);
		/* 100 ms of 1 ms ticks: ten sub-blocks of ten ticks */
		assert_int_equal(r.window_ticks, 100);
		assert_int_equal(r.windows, cases[i].windows);
		assert_int_equal(popc_chatter_checked(&r), cases[i].windows > 0);
		assert_int_equal(r.n_intervals, cases[i].windows > 0);
	}
}

static void config_set_and_init_errors(void **state)
{
	(void)state;
	popc_chatter_config cfg;
	popc_chatter_config_defaults(&cfg);
	popc_error err;
	assert_int_equal(popc_chatter_config_set(&cfg, "pc_rms_share", "0.3", &err), 0);
	assert_true(cfg.pc_rms_share == 0.3);
	assert_int_equal(popc_chatter_config_set(&cfg, "lc_amplitude", "20", &err), 0);
	assert_true(cfg.lc_amplitude_min_counts == 20.0);
	static const char *const bad[][2] = {
		{"nope", "1"}, {"pc_rms_share", "-1"}, {"pc_rms_share", "1x"}, {"window", "0"},
		{"contact", "1.5"}, {"lc_freq_share", "nan"}, {"pc_rms_share", ""},
		/* the absolute names of before: refused, naming the relative one */
		{"pc_rms", "0.5"}, {"lc_freq_max", "50"}, {"resolution", "1e-5"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
		assert_int_equal(popc_chatter_config_set(&cfg, bad[i][0], bad[i][1], &err),
				 POPC_ERR_INVALID);
	popc_chatter d;
	popc_environment env = wall();
	assert_int_equal(popc_chatter_init(&d, &cfg, 0.0, &env, &err), POPC_ERR_INVALID);
	/* the scene's PC bound: finite and not negative */
	cfg.pc_bound_N = -1.0;
	assert_int_equal(popc_chatter_init(&d, &cfg, T_S, &env, &err), POPC_ERR_INVALID);
}

/* The detector's messages name its own parameters (popc_chatter_config's
 * fields, the period), never a program's option or a scene key: popc-analyze
 * names those (ana_chatter_name_options; tests/analyze/test_chatter.sh). */
static void messages_name_the_detector_parameters(void **state)
{
	(void)state;
	popc_chatter_config cfg;
	popc_chatter_config_defaults(&cfg);
	popc_error err;
	assert_int_equal(popc_chatter_config_set(&cfg, "resolution", "1e-5", &err),
			 POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "use resolution_m (the scene's, not a threshold)"));
	assert_int_equal(popc_chatter_config_set(&cfg, "pc_rms", "1", &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "a share of pc_bound_N"));
	cfg.resolution_m = 1e-5;
	cfg.pc_bound_N = 5.0;
	popc_chatter d;
	popc_environment env = wall();
	/* the 0.1 s window at T = 1e-15 s: 1e14 ticks, above 1e12 per sub-block */
	assert_int_equal(popc_chatter_init(&d, &cfg, 1e-15, &env, &err), POPC_ERR_INVALID);
	assert_non_null(strstr(err.msg, "give shorter windows (window_s, lc_window_s) or the "
					"log's true period (period_s)"));
	static const char *const not_here[] = {"--", "run.", "encoder.", "controller."};
	for (size_t i = 0; i < sizeof not_here / sizeof not_here[0]; i++)
		assert_null(strstr(err.msg, not_here[i]));
}

/* The RMS accumulation (popc/core/sum_squares.h): bit for bit a plain sum of
 * squares for ordinary values, finite and accurate (within n eps / 2 of a
 * sum of n squares) from 1e-320 to 1.7e308, where a plain sum overflows or
 * underflows; the metrics and the detector use it. */
static void sum_squares_edges(void **state)
{
	(void)state;
	popc_sum_squares q = {0.0, 0.0, 0.0};
	double plain = 0.0;
	uint64_t r = 0x9E3779B97F4A7C15ull;
	const int n = 10000;
	for (int i = 0; i < n; i++) {
		r ^= r << 13;
		r ^= r >> 7;
		r ^= r << 17;
		double v = ((double)(r >> 11) * 0x1p-53 - 0.5) * pow(10.0, (double)(i % 20) - 10.0);
		popc_sum_squares_add(&q, v);
		plain += v * v;
	}
	const double a = popc_sum_squares_rms(&q, n), b = sqrt(plain / n);
	assert_memory_equal(&a, &b, sizeof a);
	const double edges[] = {1.7976931348623157e308, 1e308, 1e200, 1e-200, 1e-300, 1e-320};
	for (size_t k = 0; k < sizeof edges / sizeof edges[0]; k++) {
		popc_sum_squares e = {0.0, 0.0, 0.0};
		for (int i = 0; i < 3000; i++)
			popc_sum_squares_add(&e, i % 2 ? edges[k] : -edges[k]);
		const double rms = popc_sum_squares_rms(&e, 3000.0);
		/* a subnormal value has fewer digits: 1e-320 is 1e-320 within 2e-4 */
		const double tol = edges[k] < 2.3e-308 ? 2e-4 : 4e-13;
		if (!(fabs(rms / edges[k] - 1.0) <= tol))
			fail_msg("rms of +-%g: %.17g", edges[k], rms);
	}
	/* one huge value among ordinary ones: both scales count */
	popc_sum_squares m = {0.0, 0.0, 0.0};
	popc_sum_squares_add(&m, 1e300);
	popc_sum_squares_add(&m, 3.0);
	popc_sum_squares_add(&m, 1e-310);
	assert_true(fabs(popc_sum_squares_rms(&m, 3.0) / (1e300 / sqrt(3.0)) - 1.0) < 1e-15);
	/* through the metrics and the detector */
	popc_metrics met;
	popc_environment env = wall();
	popc_metrics_init(&met, &env, T_S, 0.0);
	popc_chatter d;
	popc_chatter_config cfg;
	start(&d, &cfg);
	for (int k = 0; k < 3000; k++) {
		popc_tick t;
		memset(&t, 0, sizeof t);
		t.t_s = k * T_S;
		t.x_m = (k % 4 < 2 ? 0.0 : DELTA_M) + 0.001;
		t.count = (long long)llround(t.x_m / DELTA_M);
		t.f_pc_N = k % 2 ? 1e308 : -1e308;
		popc_metrics_add(&met, &t);
		popc_chatter_add(&d, &t);
	}
	popc_chatter_result res;
	popc_chatter_finish(&d, &res);
	const double values[] = {popc_metrics_pc_rms(&met.all), popc_metrics_pc_rms(&met.late),
				 res.max_pc_rms_N, res.lc_pc_rms_N};
	for (size_t k = 0; k < sizeof values / sizeof values[0]; k++)
		if (!(fabs(values[k] / 1e308 - 1.0) < 4e-13))
			fail_msg("RMS %zu of +-1e308 N: %.17g", k, values[k]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(quiet_contact_is_not_flagged),
		cmocka_unit_test(chatter_burst_is_one_interval),
		cmocka_unit_test(no_contact_no_chatter),
		cmocka_unit_test(small_pc_force_not_flagged),
		cmocka_unit_test(intervals_are_bounded),
		cmocka_unit_test(sustained_oscillation_is_a_limit_cycle),
		cmocka_unit_test(decaying_tiny_or_fast_oscillation_is_not),
		cmocka_unit_test(short_log_is_not_checked),
		cmocka_unit_test(short_log_limit_cycle_not_checked),
		cmocka_unit_test(limit_cycle_wherever_the_log_ends),
		cmocka_unit_test(approach_from_rest_is_not_a_limit_cycle),
		cmocka_unit_test(decaying_bounce_is_not_a_limit_cycle_at_any_length),
		cmocka_unit_test(config_set_and_init_errors),
		cmocka_unit_test(messages_name_the_detector_parameters),
		cmocka_unit_test(sum_squares_edges),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
