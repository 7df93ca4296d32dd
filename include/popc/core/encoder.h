/* Encoder quantization, the paper's rule (Sec. IV-A): x_meas = delta floor(x / delta).
 * Positions travel as integer counts; the measured position in metres is
 * count * delta, computed in one place so that every program agrees bitwise. */
#ifndef POPC_ENCODER_H
#define POPC_ENCODER_H

#include <math.h>

/* POPC_FLOOR_CLONES: on a function whose hot path computes floor(), two
 * copies of it, one for CPUs with SSE4.1, where floor is one roundsd
 * instruction, and one for the x86-64 baseline, where it is a sequence of
 * about 20 (callgrind: popc_encoder_count's line costs 21 instructions a
 * tick in the sim axis' sample). The dynamic linker picks one when the program loads (GCC's and
 * clang's target_clones, an ifunc), so the default build still runs on every
 * x86-64 CPU. floor() is exact in both, and -ffp-contract=off keeps every
 * other operation as written, so both copies give the same bits
 * (tests/bitwise, tests/behaviour). Empty where the compiler or the platform
 * lacks ifuncs (meson.build's POPC_HAVE_TARGET_CLONES) or the build already
 * targets SSE4.1. */
#if defined(POPC_HAVE_TARGET_CLONES) && POPC_HAVE_TARGET_CLONES && defined(__x86_64__) && \
	!defined(__SSE4_1__)
#define POPC_FLOOR_CLONES __attribute__((target_clones("sse4.1", "default")))
#else
#define POPC_FLOOR_CLONES
#endif

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
