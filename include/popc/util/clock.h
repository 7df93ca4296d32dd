/* The one clock of popc's programs: CLOCK_MONOTONIC, which no clock setting
 * or NTP step moves, for wall times of runs, progress, benchmarks and the
 * Modbus axis's absolute deadlines (clock_nanosleep on the same clock id).
 * Inline: the axis reads it several times a period. */
#ifndef POPC_UTIL_CLOCK_H
#define POPC_UTIL_CLOCK_H

#include <stdint.h>
#include <time.h>

/* The clock id behind popc_now_ns and popc_now_s, for clock_nanosleep. */
#define POPC_CLOCK_ID CLOCK_MONOTONIC

/* Nanoseconds since an arbitrary start (boot), exact. */
static inline int64_t popc_now_ns(void)
{
	struct timespec ts;
	clock_gettime(POPC_CLOCK_ID, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* Seconds since the same start, as a double (finer than 1 ns for the first
 * 2^23 s, 97 days, of uptime: a double's step there is 2^-30 s). */
static inline double popc_now_s(void)
{
	struct timespec ts;
	clock_gettime(POPC_CLOCK_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds this thread has run (CLOCK_THREAD_CPUTIME_ID): the clock of
 * the compute benchmarks, which then measure the work and not the time the
 * scheduler gave to other processes on a shared machine. */
static inline double popc_thread_cpu_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
