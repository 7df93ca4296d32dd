/* Encoder quantization, the paper's rule (Sec. IV-A): x_meas = delta floor(x / delta).
 * Positions travel as integer counts; the measured position in metres is
 * count * delta, computed in one place so that every program agrees bitwise. */
#ifndef POPC_ENCODER_H
#define POPC_ENCODER_H

#include <math.h>

/* Count of the quantization cell holding x. Returns 0 and sets *ok = 0 when
 * x / delta is not finite or does not fit a 62-bit count. */
static inline long long popc_encoder_count(double x_m, double delta_m, int *ok)
{
	double c = floor(x_m / delta_m);
	if (!(c > -4.0e18 && c < 4.0e18)) { /* also false for NaN */
		*ok = 0;
		return 0;
	}
	*ok = 1;
	return (long long)c;
}

static inline double popc_encoder_position(long long count, double delta_m)
{
	return (double)count * delta_m;
}

#endif
