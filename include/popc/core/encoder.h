/* Encoder quantization, the paper's rule (Sec. IV-A): x_meas = delta floor(x / delta).
 * Positions travel as integer counts; the measured position in metres is
 * count * delta, computed in one place so that every program agrees bitwise. */
#ifndef POPC_ENCODER_H
#define POPC_ENCODER_H

#include <math.h>

/* Count of the quantization cell holding x. Returns 0 and sets *ok = 0 when
 * x / delta is not finite or |count| reaches 2^53: beyond it neighbouring
 * counts share a double, so count * delta (the measured position) and the
 * count logged as a number would no longer be exact. */
#define POPC_ENCODER_COUNT_LIMIT 9007199254740992.0 /* 2^53 */
static inline long long popc_encoder_count(double x_m, double delta_m, int *ok)
{
	double c = floor(x_m / delta_m);
	if (!(c > -POPC_ENCODER_COUNT_LIMIT && c < POPC_ENCODER_COUNT_LIMIT)) { /* false for NaN */
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
