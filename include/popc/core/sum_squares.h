/* A sum of squares that neither overflows nor underflows for any finite
 * input: three accumulators by magnitude (Blue's algorithm, ACM TOMS 4(1),
 * 1978, with power-of-two scales, so that scaling is exact). The RMS of the
 * PC force over a log (popc_metrics, the chatter detector) is then finite and
 * accurate for forces near 1e308 or 1e-300, where a plain sum of f^2 gave inf
 * or 0.
 *
 * Values in [2^-300, 2^300] are squared as they are into mid, so sums and RMS
 * of ordinary forces are bit for bit those of a plain sum (sum += f * f in the
 * same order); mid holds at most 2^62 squares of at most 2^600. Larger values
 * go to big scaled by 2^-600, smaller ones to small scaled by 2^600. */
#ifndef POPC_CORE_SUM_SQUARES_H
#define POPC_CORE_SUM_SQUARES_H

#include <math.h>

typedef struct popc_sum_squares {
	double mid;   /* sum v^2 for 2^-300 <= |v| <= 2^300 */
	double big;   /* sum (v 2^-600)^2 for |v| > 2^300 */
	double small; /* sum (v 2^600)^2 for 0 < |v| < 2^-300 */
} popc_sum_squares;

static inline void popc_sum_squares_add(popc_sum_squares *s, double v)
{
	const double a = fabs(v);
	if (a <= 0x1p300) {
		if (a >= 0x1p-300)
			s->mid += v * v;
		else if (a > 0.0)
			s->small += (a * 0x1p600) * (a * 0x1p600);
	} else {
		s->big += (a * 0x1p-600) * (a * 0x1p-600);
	}
}

/* s += t (the sums of two stretches of ticks). */
static inline void popc_sum_squares_merge(popc_sum_squares *s, const popc_sum_squares *t)
{
	s->mid += t->mid;
	s->big += t->big;
	s->small += t->small;
}

/* sqrt(sum / n), n > 0. The smaller scale is brought to the larger one in
 * two steps of 2^-600 (2^-1200 is no double); what underflows there is below
 * the larger sum's rounding (a relative 2^-400 or less: the larger sum is at
 * least 2^-600 in its own units). */
static inline double popc_sum_squares_rms(const popc_sum_squares *s, double n)
{
	if (s->big > 0.0)
		return sqrt((s->big + s->mid * 0x1p-600 * 0x1p-600) / n) * 0x1p600;
	if (s->mid > 0.0)
		return sqrt((s->mid + s->small * 0x1p-600 * 0x1p-600) / n);
	return sqrt(s->small / n) * 0x1p-600;
}

#endif
