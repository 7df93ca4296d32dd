/* Constant-memory latency statistics for the Modbus axis: a log-linear
 * histogram (HDR style) of nanosecond durations, 128 sub-buckets per octave,
 * so a percentile is known within 1/128 (0.8 %) of its value whatever the run
 * length; count, mean and max are exact. Private to the library. */
#ifndef POPC_MODBUS_STATS_H
#define POPC_MODBUS_STATS_H

#include <stdint.h>

#define POPC_HIST_SUB_BITS 7
#define POPC_HIST_SUB (1 << POPC_HIST_SUB_BITS)
/* octaves up to 2^40 ns (about 18 minutes); longer values land in the top bucket */
#define POPC_HIST_MAX_MSB 40
#define POPC_HIST_BUCKETS ((POPC_HIST_MAX_MSB - POPC_HIST_SUB_BITS + 1) * POPC_HIST_SUB + POPC_HIST_SUB)

typedef struct popc_histogram {
	uint64_t bucket[POPC_HIST_BUCKETS];
	uint64_t n;
	int64_t max_ns;
	double sum_ns;
} popc_histogram;

void popc_histogram_init(popc_histogram *h);
void popc_histogram_add(popc_histogram *h, int64_t ns);

/* The q-quantile (0 < q <= 1) in seconds: the upper edge of the bucket that
 * holds it, capped at the exact maximum; 0 when empty. */
double popc_histogram_quantile_s(const popc_histogram *h, double q);
double popc_histogram_mean_s(const popc_histogram *h);
double popc_histogram_max_s(const popc_histogram *h);

#endif
