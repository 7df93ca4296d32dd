/* The teleoperator's packet channel (channel.h has the model). */
#include "popc/core/channel.h"

#include <stdlib.h>
#include <string.h>

#include "popc/core/random.h"

const char *const popc_channel_event_names[] = {"sent", "lost", "delivered", "stale", NULL};

static void emit(popc_channel *ch, long long k, long long seq, popc_channel_event ev,
		 long long delay)
{
	if (ch->on_event)
		ch->on_event(ch->event_user, k, seq, ev, delay);
}

/* jitter_walk's next jitter: the first uniform in [0, J], then +-1 or 0
 * (one draw in {0, 1, 2}), held within [0, J] */
static uint32_t walk_step(popc_channel *ch)
{
	const int J = ch->c.jitter_ticks;
	if (ch->walk_ticks < 0) {
		ch->walk_ticks = (int)popc_uniform_int(&ch->state, (uint32_t)J);
		return (uint32_t)ch->walk_ticks;
	}
	int j = ch->walk_ticks + (int)popc_uniform_int(&ch->state, 2u) - 1;
	ch->walk_ticks = j < 0 ? 0 : j > J ? J : j;
	return (uint32_t)ch->walk_ticks;
}

/* the delay (ticks) packet seq takes, given its jitter draw */
static int delay_of(const popc_channel *ch, long long seq, uint32_t jitter_draw)
{
	if (ch->c.n_trace > 0)
		return ch->trace[seq % ch->c.n_trace];
	return ch->c.delay_ticks + (int)jitter_draw;
}

int popc_channel_init(popc_channel *ch, const popc_channel_config *c, popc_error *err)
{
	memset(ch, 0, sizeof *ch);
	const int max = POPC_CHANNEL_MAX_DELAY_TICKS;
	if (c->n_trace < 0 || (c->n_trace > 0 && !c->trace_ticks))
		return popc_error_set(err, POPC_ERR_INVALID, "channel: a trace of %d delays", c->n_trace);
	if (c->n_trace > 0 && (c->delay_ticks != 0 || c->jitter_ticks != 0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "channel: a delay trace and a delay of %d + jitter %d ticks: "
				      "give one of them",
				      c->delay_ticks, c->jitter_ticks);
	if (c->delay_ticks < 0 || c->delay_ticks > max)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "channel: delay of %d ticks, expected 0 to %d", c->delay_ticks,
				      max);
	if (c->jitter_ticks < 0 || c->jitter_ticks > max - c->delay_ticks)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "channel: jitter of %d ticks, expected 0 to %d (the delay plus "
				      "its jitter at most %d)",
				      c->jitter_ticks, max - c->delay_ticks, max);
	if (!(c->loss >= 0.0 && c->loss < 1.0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "channel: loss %g, expected a probability in [0, 1)", c->loss);
	int lo = c->delay_ticks, hi = c->delay_ticks + c->jitter_ticks;
	for (int i = 0; i < c->n_trace; i++) {
		const int d = c->trace_ticks[i];
		if (d < 0 || d > max)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "channel: trace entry %d: a delay of %d ticks, expected 0 "
					      "to %d",
					      i + 1, d, max);
		lo = i == 0 || d < lo ? d : lo;
		hi = i == 0 || d > hi ? d : hi;
	}
	ch->c = *c;
	ch->min_delay = lo;
	ch->max_delay = hi;
	ch->state = c->seed;
	ch->last_sent = -1;
	ch->last_arrive = -1;
	ch->walk_ticks = -1;
	/* a power of two at least hi + 1 slots: a slot is reused max_delay + 1
	 * or more ticks after its packet was sent, when that one has arrived */
	long long n_slots = 1;
	while (n_slots < (long long)hi + 1)
		n_slots *= 2;
	ch->ring_mask = n_slots - 1;
	ch->slot = calloc((size_t)n_slots, sizeof *ch->slot);
	if (c->n_trace > 0)
		ch->trace = malloc((size_t)c->n_trace * sizeof *ch->trace);
	if (!ch->slot || (c->n_trace > 0 && !ch->trace)) {
		popc_channel_free(ch);
		return popc_error_set(err, POPC_ERR_NOMEM, "channel: out of memory for %d slots",
				      hi + 1);
	}
	if (c->n_trace > 0)
		memcpy(ch->trace, c->trace_ticks, (size_t)c->n_trace * sizeof *ch->trace);
	ch->c.trace_ticks = ch->trace;
	return 0;
}

void popc_channel_free(popc_channel *ch)
{
	free(ch->slot);
	free(ch->trace);
	ch->slot = NULL;
	ch->trace = NULL;
}

int popc_channel_send(popc_channel *ch, long long k, const popc_packet *p)
{
	/* the draws of every packet, lost or not: loss, then jitter (a draw
	 * only for what the channel has: a lossless constant channel draws none) */
	const int lost = ch->c.loss > 0.0 && popc_uniform(&ch->state) < ch->c.loss;
	const uint32_t jitter =
		ch->c.jitter_ticks <= 0 ? 0
		: ch->c.jitter_walk    ? walk_step(ch)
				       : popc_uniform_int(&ch->state, (uint32_t)ch->c.jitter_ticks);
	ch->last_sent = k;
	ch->stats.sent++;
	popc_channel_slot *s = &ch->slot[k & ch->ring_mask];
	if (s->pending) { /* not received in time: receive was not called every tick */
		ch->stats.lost++;
		emit(ch, k, s->p.seq, POPC_CHANNEL_LOST, -1);
	}
	s->pending = 0;
	if (lost) {
		ch->stats.lost++;
		emit(ch, k, k, POPC_CHANNEL_SENT, -1);
		emit(ch, k, k, POPC_CHANNEL_LOST, -1);
		return 1;
	}
	long long arrive = k + delay_of(ch, k, jitter);
	/* in order, a packet waits for the one before it; that one was sent
	 * earlier with a delay of at most max_delay, so this still arrives by
	 * k + max_delay and its slot is free until then */
	if (ch->c.in_order && arrive < ch->last_arrive)
		arrive = ch->last_arrive;
	ch->last_arrive = arrive;
	s->p = *p;
	s->p.seq = k;
	s->arrive = arrive;
	s->pending = 1;
	emit(ch, k, k, POPC_CHANNEL_SENT, arrive - k);
	return 0;
}

int popc_channel_receive(popc_channel *ch, long long k, popc_packet *held, int *fresh)
{
	int arrived = 0, newer = 0;
	/* what arrives at k was sent in [k - max_delay, k - min_delay] (the
	 * in-order wait postpones, within max_delay: send): in seq order */
	long long first = k - ch->max_delay, last = k - ch->min_delay;
	if (first < 0)
		first = 0;
	if (last > ch->last_sent)
		last = ch->last_sent;
	for (long long seq = first; seq <= last; seq++) {
		popc_channel_slot *s = &ch->slot[seq & ch->ring_mask];
		if (!s->pending || s->p.seq != seq || s->arrive > k)
			continue;
		s->pending = 0;
		arrived++;
		ch->stats.delivered++;
		if (s->p.seq > held->seq) {
			*held = s->p;
			newer++;
			emit(ch, k, seq, POPC_CHANNEL_DELIVERED, k - seq);
		} else {
			ch->stats.stale++;
			emit(ch, k, seq, POPC_CHANNEL_STALE, k - seq);
		}
	}
	if (fresh)
		*fresh = newer;
	return arrived;
}

long long popc_channel_in_flight(const popc_channel *ch)
{
	long long n = 0;
	for (long long i = 0; ch->slot && i <= ch->ring_mask; i++)
		n += ch->slot[i].pending != 0;
	return n;
}
