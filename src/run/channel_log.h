/* A teleoperation run's channel log (popc run --channel-log FILE;
 * docs/TELEOPERATION.md, "The channel log"): one row per packet event,
 *
 *   tick,direction,seq,event,delay_ticks
 *
 * tick the tick of the event, direction forward (master to slave) or
 * backward, seq the tick the packet was sent at, event sent, lost,
 * delivered (it became the held packet) or stale (it arrived older than the
 * held one), delay_ticks the delay drawn (sent; -1 when lost at send) or
 * tick - seq (delivered, stale; -1 lost). Below a header of '#' lines (the
 * resolved scene, so that the file says which run it is) and above two
 * trailing lines, "# forward_in_flight = N" and "# backward_in_flight = N":
 * the packets still travelling when the run ended. Per direction, sent =
 * delivered + stale + lost + in flight. Private to the run layer. */
#ifndef POPC_RUN_CHANNEL_LOG_H
#define POPC_RUN_CHANNEL_LOG_H

#include <stdio.h>

#include "popc/core/channel.h"
#include "popc/scene/scene.h"

typedef struct popc_channel_log_dir {
	FILE *f;          /* NULL: no channel log */
	const char *name; /* "forward" or "backward" */
} popc_channel_log_dir;

void popc_channel_log_header(FILE *f, const popc_scene *s);
/* popc_channel_event_fn, user a popc_channel_log_dir */
void popc_channel_log_event(void *user, long long k, long long seq, popc_channel_event ev,
			    long long delay_ticks);
void popc_channel_log_in_flight(FILE *f, const char *name, long long n);

#endif
