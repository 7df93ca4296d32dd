/* Velocity estimators from quantized positions.
 *
 * FOAW (first-order adaptive windowing, end-fit form) of Janabi-Sharifi,
 * Hayward and Chen, "Discrete-time adaptive windowing for velocity
 * estimation", IEEE T-CST 8(6), 2000: the longest window n <= N such that the
 * straight line through x(k-n) and x(k) passes within +-d of every sample
 * between them; the velocity is that line's slope.
 *
 * When d is a whole number m of encoder counts (the default: d = delta), the
 * band test runs on the integer counts, |n (c_k - c_{k-j}) - j (c_k - c_{k-n})|
 * <= n m, and the slope is (c_k - c_{k-n}) delta / (n T): a sample exactly on
 * the band edge is then inside it at every absolute position, and the same
 * count pattern gives the same velocity wherever it happens. In metres the
 * test would round differently at different positions. */
#ifndef POPC_VELOCITY_H
#define POPC_VELOCITY_H

#define POPC_FOAW_MAX_WINDOW 64

typedef struct popc_foaw {
	int max_window;               /* N */
	double noise_m;               /* d */
	double resolution_m;          /* delta */
	long long noise_counts;       /* m = d / delta when whole (1 .. 2^32), else 0: test in metres */
	double period_s;
	double x[POPC_FOAW_MAX_WINDOW + 1];     /* ring buffer of the last N+1 positions */
	long long c[POPC_FOAW_MAX_WINDOW + 1];  /* and their counts */
	int head, filled;
} popc_foaw;

/* resolution_m: the encoder's delta (> 0), or 0 if positions are not counts
 * (then the band test is in metres). */
void popc_foaw_init(popc_foaw *f, int max_window, double noise_m, double resolution_m,
		    double period_s);

/* Pushes sample k, its count and its position x(k) = count delta (m), and
 * returns the estimated velocity v(k) (m/s); 0 for the first sample. */
double popc_foaw_update(popc_foaw *f, long long count, double x_m);

#endif
