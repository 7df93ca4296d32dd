/* A one-way packet channel between the two sides of a teleoperator: the
 * network of the two-port time-domain passivity approach (Ryu, Kwon and
 * Hannaford, IEEE T-RA 20(2), 2004; Artigas, Ryu, Preusche et al., time-
 * varying delay, 2010). Each tick a side sends one packet; the channel holds
 * it for its delay and hands it over at the tick it arrives, or loses it.
 *
 *   - delay: a constant number of ticks, plus a whole number drawn uniformly
 *     in [0, jitter_ticks] for each packet (or walking in that range by +-1
 *     tick a packet: jitter_walk), or a trace of delays in ticks (packet k
 *     takes trace[k mod n]);
 *   - loss: each packet is lost with probability loss;
 *   - order: with in_order, a packet never arrives before one sent earlier
 *     (it waits for it, as over TCP); without, a packet that jitter delays
 *     less than the one before it arrives first (as over UDP);
 *   - the receiver holds the newest packet it got (hold-last): a packet older
 *     than the held one arrives stale and is dropped, so a lost or reordered
 *     packet never takes the receiver back in time.
 * Every draw comes from one splitmix64 stream seeded by seed (random.h): a
 * run is the same given its seed. Memory: one slot per tick of the longest
 * delay, allocated by popc_channel_init; send and receive allocate nothing
 * and take time in proportion to the spread of the delays, not their size. */
#ifndef POPC_CORE_CHANNEL_H
#define POPC_CORE_CHANNEL_H

#include <stdint.h>

#include "popc/util/error.h"

#define POPC_PACKET_VALUES 4
/* the longest delay a channel holds: 100 s at 1 kHz (5.6 MB of slots) */
#define POPC_CHANNEL_MAX_DELAY_TICKS 100000

typedef struct popc_packet {
	long long seq;                    /* the tick it was sent at */
	double value[POPC_PACKET_VALUES]; /* what a side sends: position, velocity, force, ... */
	double energy_J;                  /* the sender's input energy so far (the TDPA's) */
} popc_packet;

typedef struct popc_channel_config {
	int delay_ticks;        /* constant delay, >= 0 */
	int jitter_ticks;       /* plus uniform in [0, jitter_ticks] a packet, >= 0 */
	const int *trace_ticks; /* n_trace > 0: packet k's delay is trace_ticks[k mod n_trace] */
	int n_trace;            /* (copied by init; delay_ticks and jitter_ticks then 0) */
	double loss;            /* probability a packet is lost, in [0, 1) */
	int in_order;           /* 1: first sent, first delivered; 0: reordering */
	uint64_t seed;
	int jitter_walk;        /* 0: the jitter uniform anew a packet; 1: a bounded random
				 * walk, j(k) = min(max(j(k-1) + s, 0), jitter_ticks) with s
				 * uniform in {-1, 0, +1}, j(0) uniform in [0, jitter_ticks] */
} popc_channel_config;

typedef struct popc_channel_stats {
	long long sent, lost, delivered, stale; /* delivered counts the stale ones too */
} popc_channel_stats;

typedef struct popc_channel_slot {
	popc_packet p;
	long long arrive; /* tick */
	int pending;
} popc_channel_slot;

/* A packet's events, for a per-packet log (popc_channel.on_event): every
 * packet is sent once, then lost (at send, or never received in time),
 * delivered (it became the held packet) or stale (it arrived older than the
 * held one), or is still in flight when the run ends. */
typedef enum popc_channel_event {
	POPC_CHANNEL_SENT,
	POPC_CHANNEL_LOST,
	POPC_CHANNEL_DELIVERED,
	POPC_CHANNEL_STALE,
} popc_channel_event;

/* Names in channel logs ("sent", "lost", "delivered", "stale"), index = value. */
extern const char *const popc_channel_event_names[];

/* Called at tick k for packet seq: delay_ticks is the delay drawn (sent;
 * -1 when lost at send), k - seq (delivered, stale), -1 (lost). */
typedef void (*popc_channel_event_fn)(void *user, long long k, long long seq,
				      popc_channel_event ev, long long delay_ticks);

typedef struct popc_channel {
	popc_channel_config c;
	int *trace;              /* owned copy of trace_ticks */
	int min_delay, max_delay;
	popc_channel_slot *slot; /* ring_mask + 1 >= max_delay + 1 (a power of two), packet
				  * seq at seq & ring_mask: no division a tick */
	long long ring_mask;
	uint64_t state;
	long long last_sent;     /* -1 before the first */
	long long last_arrive;   /* in order: the latest arrival scheduled */
	popc_channel_stats stats;
	int walk_ticks;          /* jitter_walk: the last packet's jitter, -1 before it */
	popc_channel_event_fn on_event; /* NULL (init's), or set after init: each event */
	void *event_user;
} popc_channel;

/* Checks c (a refusal names the parameter and its allowed range) and
 * allocates the slots; 0, or a POPC_ERR_*. */
int popc_channel_init(popc_channel *ch, const popc_channel_config *c, popc_error *err);
void popc_channel_free(popc_channel *ch);

/* Sends p at tick k (k > the last send's; p->seq is set to k): 1 when the
 * packet is lost, 0 when it travels. Send at k before receiving at k: a
 * delay of 0 arrives in the same tick. */
int popc_channel_send(popc_channel *ch, long long k, const popc_packet *p);

/* Hands over what arrives at tick k (called every tick, k increasing): each
 * arriving packet newer than *held (held->seq) replaces it, the others are
 * stale. Returns the packets that arrived; *fresh (may be NULL) those that
 * replaced the held one. Before the first arrival *held is what the caller
 * set (seq -1: nothing yet). */
int popc_channel_receive(popc_channel *ch, long long k, popc_packet *held, int *fresh);

/* The packets sent and neither lost nor received yet. */
long long popc_channel_in_flight(const popc_channel *ch);

#endif
