/* The core's one pseudo-random generator: a force sensor's noise
 * (admittance.h) and a channel's delays and losses (channel.h) draw from it,
 * so a run is the same given its seeds, on every machine and compiler.
 *
 * splitmix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number
 * generators", OOPSLA 2014): a 64-bit state stepped by the golden-ratio
 * increment and mixed; every seed, 0 included, is a good start. Integer
 * arithmetic only: bit for bit the same everywhere. */
#ifndef POPC_CORE_RANDOM_H
#define POPC_CORE_RANDOM_H

#include <stdint.h>

static inline uint64_t popc_splitmix64(uint64_t *state)
{
	uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	return z ^ (z >> 31);
}

/* uniform in (0, 1]: 53 bits, never 0 (a logarithm may take it) */
static inline double popc_uniform_open0(uint64_t *state)
{
	return ((double)(popc_splitmix64(state) >> 11) + 1.0) * 0x1.0p-53;
}

/* uniform in [0, 1): 53 bits */
static inline double popc_uniform(uint64_t *state)
{
	return (double)(popc_splitmix64(state) >> 11) * 0x1.0p-53;
}

/* a whole number uniform in [0, n] (n < 2^32), without modulo bias: the
 * high 32 bits of a draw times n + 1 (Lemire's multiply-shift; its bias,
 * below (n + 1) / 2^32, is below any count a run makes) */
static inline uint32_t popc_uniform_int(uint64_t *state, uint32_t n)
{
	return (uint32_t)(((popc_splitmix64(state) >> 32) * ((uint64_t)n + 1u)) >> 32);
}

#endif
