/* A teleoperation channel's delays in seconds and from a trace file
 * (forward.delay_s, .jitter_s, .trace; docs/TELEOPERATION.md, "Delays in
 * seconds and from a trace"): the scene's keys to the whole ticks the channel
 * (core/channel.h) counts in.
 *
 * Seconds to ticks: d_s x run.rate ticks, taken when it is within
 * POPC_WHOLE_TICK_TOLERANCE of a whole number (0.1 s at 1 kHz is
 * 100.00000000000001 in doubles: 100), refused otherwise, the message naming
 * the two nearest delays that are whole ticks.
 *
 * A trace file is text: '#' comments and blank lines anywhere, then a header
 * line naming the unit, `delay_ticks` or `delay_s`, then one delay a line,
 * packet k taking line k mod n (the trace repeats). delay_ticks: a whole
 * number in [0, POPC_CHANNEL_MAX_DELAY_TICKS]; delay_s: a number that is
 * whole ticks by the rule above and in that range. At most
 * POPC_DELAY_TRACE_MAX_LINES delays. CRLF or LF. */
#ifndef POPC_SCENE_DELAY_TRACE_H
#define POPC_SCENE_DELAY_TRACE_H

#include <stdint.h>

#include "popc/core/channel.h"
#include "popc/scene/scene.h"
#include "popc/util/error.h"

#define POPC_WHOLE_TICK_TOLERANCE 1e-6
#define POPC_DELAY_TRACE_MAX_LINES 10000000

/* seconds x rate_Hz as whole ticks in *ticks: 0, or -1 when it is not within
 * the tolerance of a whole number or beyond POPC_CHANNEL_MAX_DELAY_TICKS
 * (*ticks then the nearest whole number, rounded down, for messages) */
int popc_seconds_to_ticks(double seconds, double rate_Hz, long long *ticks);

typedef struct popc_delay_trace {
	int n;
	int *ticks;     /* n delays, owned */
	uint64_t fnv1a; /* FNV-1a 64 of the file's bytes, for the log header */
} popc_delay_trace;

/* Reads a trace file (the format above) at rate_Hz. A file that cannot be
 * opened or read, lacks the header, holds no delay or a bad one is
 * POPC_ERR_INVALID naming the file, the line and the allowed range. */
int popc_delay_trace_load(const char *path, double rate_Hz, popc_delay_trace *out,
			  popc_error *err);
void popc_delay_trace_free(popc_delay_trace *t);

/* One direction's delay and jitter in ticks, from the tick keys or the
 * seconds keys (name: "forward" or "backward"): 0, or POPC_ERR_INVALID naming
 * the keys when both are given or seconds are no whole ticks. */
int popc_scene_channel_ticks(const popc_scene *s, const popc_scene_channel *dir, const char *name,
			     int *delay_ticks, int *jitter_ticks, popc_error *err);

#endif
