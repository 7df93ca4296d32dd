/* Log-linear latency histogram (modbus_stats.h). */
#include "modbus_stats.h"

#include <string.h>

void popc_histogram_init(popc_histogram *h)
{
	memset(h, 0, sizeof *h);
}

static int msb64(uint64_t v)
{
	int m = 0;
	while (v >>= 1)
		m++;
	return m;
}

/* v < 2^(SUB_BITS+1): one bucket per nanosecond; above, octave o = msb - SUB_BITS
 * keeps the top SUB_BITS+1 bits: index o * SUB + (v >> o), contiguous. */
static int bucket_of(uint64_t v)
{
	if (v < 2 * POPC_HIST_SUB)
		return (int)v;
	int m = msb64(v);
	if (m > POPC_HIST_MAX_MSB)
		return POPC_HIST_BUCKETS - 1;
	int o = m - POPC_HIST_SUB_BITS;
	return o * POPC_HIST_SUB + (int)(v >> o);
}

/* Largest value that falls into bucket i. */
static uint64_t bucket_upper(int i)
{
	if (i < 2 * POPC_HIST_SUB)
		return (uint64_t)i;
	int o = i / POPC_HIST_SUB - 1;
	uint64_t top = (uint64_t)(i - o * POPC_HIST_SUB);
	return ((top + 1) << o) - 1;
}

void popc_histogram_add(popc_histogram *h, int64_t ns)
{
	uint64_t v = ns < 0 ? 0 : (uint64_t)ns;
	h->bucket[bucket_of(v)]++;
	h->n++;
	h->sum_ns += (double)v;
	if ((int64_t)v > h->max_ns)
		h->max_ns = (int64_t)v;
}

double popc_histogram_quantile_s(const popc_histogram *h, double q)
{
	if (h->n == 0)
		return 0.0;
	/* rank of the q-quantile, nearest-rank definition */
	double r = q * (double)h->n;
	uint64_t rank = (uint64_t)r;
	if ((double)rank < r)
		rank++;
	if (rank < 1)
		rank = 1;
	uint64_t cum = 0;
	for (int i = 0; i < POPC_HIST_BUCKETS; i++) {
		cum += h->bucket[i];
		if (cum >= rank) {
			uint64_t up = bucket_upper(i);
			if (up > (uint64_t)h->max_ns)
				up = (uint64_t)h->max_ns;
			return 1e-9 * (double)up;
		}
	}
	return 1e-9 * (double)h->max_ns;
}

double popc_histogram_mean_s(const popc_histogram *h)
{
	return h->n ? 1e-9 * h->sum_ns / (double)h->n : 0.0;
}

double popc_histogram_max_s(const popc_histogram *h)
{
	return 1e-9 * (double)h->max_ns;
}
