/* Velocity estimators from quantized positions.
 *
 * FOAW (first-order adaptive windowing, end-fit form) of Janabi-Sharifi,
 * Hayward and Chen, "Discrete-time adaptive windowing for velocity
 * estimation", IEEE T-CST 8(6), 2000: the longest window n <= N such that the
 * straight line through x(k-n) and x(k) passes within +-d of every sample
 * between them; the velocity is that line's slope. */
#ifndef POPC_VELOCITY_H
#define POPC_VELOCITY_H

#define POPC_FOAW_MAX_WINDOW 64

typedef struct popc_foaw {
	int max_window;               /* N */
	double noise_m;               /* d */
	double period_s;
	double x[POPC_FOAW_MAX_WINDOW + 1]; /* ring buffer of the last N+1 positions */
	int head, filled;
} popc_foaw;

void popc_foaw_init(popc_foaw *f, int max_window, double noise_m, double period_s);

/* Pushes x(k) and returns the estimated velocity v(k) (m/s); 0 for the first sample. */
double popc_foaw_update(popc_foaw *f, double x_m);

#endif
