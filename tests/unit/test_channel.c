/* The teleoperator's packet channel (core/channel.h): a constant delay
 * arrives on its tick; with jitter every packet that is not lost arrives
 * exactly once, within its delay range, and the held packet never goes back
 * in time (reordered ones arrive stale); in order, none is stale and
 * arrivals keep their order; losses hold the last packet; the same seed
 * gives the same run and another seed another; a trace gives its delays;
 * a bad configuration is refused naming the parameter; every packet's
 * events (sent, then lost, delivered, stale or in flight) add up, and a
 * random walk of jitter steps by one tick at most. Counting only: no
 * clock. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/core/channel.h"

/* every packet carries its send tick in value[0] and energy 2 k */
static popc_packet packet_at(long long k)
{
	popc_packet p;
	memset(&p, 0, sizeof p);
	p.value[0] = (double)k;
	p.energy_J = 2.0 * (double)k;
	return p;
}

static popc_channel open_channel(popc_channel_config c)
{
	popc_channel ch;
	popc_error err;
	assert_int_equal(popc_channel_init(&ch, &c, &err), 0);
	return ch;
}

static void test_constant_delay(void **state)
{
	(void)state;
	for (int d = 0; d <= 5; d++) {
		popc_channel_config c = {.delay_ticks = d};
		popc_channel ch = open_channel(c);
		popc_packet held = {.seq = -1};
		for (long long k = 0; k < 50; k++) {
			assert_int_equal(popc_channel_send(&ch, k, &(popc_packet){.value = {(double)k}}), 0);
			int fresh = -1;
			const int n = popc_channel_receive(&ch, k, &held, &fresh);
			assert_int_equal(n, k >= d ? 1 : 0);
			assert_int_equal(fresh, n);
			assert_int_equal(held.seq, k >= d ? k - d : -1);
			if (k >= d)
				assert_true(held.value[0] == (double)(k - d));
		}
		assert_int_equal(ch.stats.sent, 50);
		assert_int_equal(ch.stats.delivered, 50 - d);
		assert_int_equal(ch.stats.lost + ch.stats.stale, 0);
		popc_channel_free(&ch);
	}
}

/* one run of n ticks: arrival tick of each packet that became the held one
 * (-1: lost, stale or not yet; in order, every packet up to the held one has
 * arrived by then, so all of them are given the tick), and the held packet's
 * seq after each tick */
static void run(popc_channel *ch, long long n, long long *arrive, long long *held_seq)
{
	const int in_order = ch->c.in_order;
	popc_packet held = {.seq = -1};
	for (long long k = 0; k < n; k++) {
		arrive[k] = -1;
		popc_packet p = packet_at(k);
		popc_channel_send(ch, k, &p);
		const long long before = held.seq;
		popc_channel_receive(ch, k, &held, NULL);
		/* hold-last: never back in time; the held packet is one that was sent */
		assert_true(held.seq >= before);
		assert_true(held.seq <= k);
		if (held.seq >= 0) {
			assert_true(held.value[0] == (double)held.seq);
			assert_true(held.energy_J == 2.0 * (double)held.seq);
		}
		if (held.seq > before)
			for (long long j = in_order ? before + 1 : held.seq; j <= held.seq; j++)
				arrive[j] = k;
		held_seq[k] = held.seq;
	}
}

static void test_jitter_reorders_but_never_back_in_time(void **state)
{
	(void)state;
	enum { N = 20000 };
	static long long arrive[N], held_seq[N];
	popc_channel_config c = {.delay_ticks = 3, .jitter_ticks = 7, .seed = 42};
	popc_channel ch = open_channel(c);
	run(&ch, N, arrive, held_seq);
	/* every packet arrives once (fresh or stale), none is lost */
	assert_int_equal(ch.stats.lost, 0);
	assert_true(ch.stats.delivered >= N - 10 && ch.stats.delivered <= N);
	/* reordering happened: some arrived behind a newer one */
	assert_true(ch.stats.stale > N / 10);
	for (long long k = 0; k < N - 10; k++)
		if (arrive[k] >= 0)
			assert_true(arrive[k] - k >= 3 && arrive[k] - k <= 10);
	popc_channel_free(&ch);
}

static void test_in_order_never_stale(void **state)
{
	(void)state;
	enum { N = 20000 };
	static long long arrive[N], held_seq[N];
	popc_channel_config c = {.delay_ticks = 2, .jitter_ticks = 9, .in_order = 1, .seed = 7};
	popc_channel ch = open_channel(c);
	run(&ch, N, arrive, held_seq);
	assert_int_equal(ch.stats.stale, 0);
	assert_int_equal(ch.stats.lost, 0);
	/* every packet arrives fresh, in the order sent, within the longest delay */
	long long prev = -1;
	for (long long k = 0; k < N - 11; k++) {
		assert_true(arrive[k] >= 0);
		assert_true(arrive[k] >= prev);
		assert_true(arrive[k] - k >= 2 && arrive[k] - k <= 11);
		prev = arrive[k];
	}
	popc_channel_free(&ch);
}

static void test_loss_holds_last(void **state)
{
	(void)state;
	enum { N = 40000 };
	popc_channel_config c = {.delay_ticks = 1, .loss = 0.3, .seed = 2026};
	popc_channel ch = open_channel(c);
	popc_packet held = {.seq = -1};
	long long gaps = 0;
	for (long long k = 0; k < N; k++) {
		popc_packet p = packet_at(k);
		popc_channel_send(&ch, k, &p);
		const long long before = held.seq;
		int fresh = 0;
		popc_channel_receive(&ch, k, &held, &fresh);
		if (k >= 1 && !fresh) {
			/* the packet of k - 1 was lost: the one before is held */
			assert_int_equal(held.seq, before);
			gaps++;
		}
	}
	assert_int_equal(ch.stats.sent, N);
	/* each packet lost or delivered, but the last one when it is in flight */
	const long long accounted = ch.stats.delivered + ch.stats.lost;
	assert_true(accounted == N || accounted == N - 1);
	assert_int_equal(ch.stats.stale, 0);
	/* 0.3 of 40000: 12000, binomial sd 92; 5 sd either way */
	assert_true(ch.stats.lost > 12000 - 460 && ch.stats.lost < 12000 + 460);
	assert_true(gaps >= ch.stats.lost - 1 && gaps <= ch.stats.lost);
	popc_channel_free(&ch);
}

static void test_seeded(void **state)
{
	(void)state;
	enum { N = 5000 };
	static long long a1[N], h1[N], a2[N], h2[N], a3[N], h3[N];
	popc_channel_config c = {.delay_ticks = 5, .jitter_ticks = 20, .loss = 0.1, .seed = 99};
	popc_channel ch = open_channel(c);
	run(&ch, N, a1, h1);
	popc_channel_free(&ch);
	ch = open_channel(c);
	run(&ch, N, a2, h2);
	popc_channel_free(&ch);
	assert_memory_equal(a1, a2, sizeof a1);
	assert_memory_equal(h1, h2, sizeof h1);
	c.seed = 100;
	ch = open_channel(c);
	run(&ch, N, a3, h3);
	popc_channel_free(&ch);
	assert_memory_not_equal(a1, a3, sizeof a1);
}

static void test_trace(void **state)
{
	(void)state;
	static const int trace[] = {4, 0, 2, 7};
	popc_channel_config c = {.trace_ticks = trace, .n_trace = 4};
	popc_channel ch = open_channel(c);
	enum { N = 400 };
	static long long arrive[N], held_seq[N];
	/* a copy is kept: the caller's array may go */
	run(&ch, N, arrive, held_seq);
	for (long long k = 0; k < N - 8; k++) {
		if (arrive[k] >= 0) {
			assert_int_equal(arrive[k] - k, trace[k % 4]);
		} else {
			/* stale: a later packet arrived first (k = 4j + 3 waits 7 ticks) */
			assert_int_equal(k % 4 == 3 || k % 4 == 0, 1);
		}
	}
	assert_true(ch.stats.stale > 0);
	popc_channel_free(&ch);
}

static void test_refusals(void **state)
{
	(void)state;
	static const int bad_trace[] = {3, -1};
	static const struct {
		popc_channel_config c;
		const char *msg;
	} cases[] = {
		{{.delay_ticks = -1}, "channel: delay of -1 ticks, expected 0 to 100000"},
		{{.delay_ticks = 100001}, "channel: delay of 100001 ticks, expected 0 to 100000"},
		{{.delay_ticks = 99990, .jitter_ticks = 11}, "channel: jitter of 11 ticks, expected 0 to 10"},
		{{.jitter_ticks = -2}, "channel: jitter of -2 ticks"},
		{{.loss = 1.0}, "channel: loss 1, expected a probability in [0, 1)"},
		{{.loss = -0.1}, "channel: loss -0.1, expected a probability in [0, 1)"},
		{{.loss = (double)NAN}, "channel: loss nan, expected a probability in [0, 1)"},
		{{.trace_ticks = bad_trace, .n_trace = 2}, "channel: trace entry 2: a delay of -1 ticks"},
		{{.trace_ticks = bad_trace, .n_trace = 1, .delay_ticks = 1}, "give one of them"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_channel ch;
		popc_error err;
		err.msg[0] = '\0';
		assert_int_equal(popc_channel_init(&ch, &cases[i].c, &err), POPC_ERR_INVALID);
		if (!strstr(err.msg, cases[i].msg))
			fail_msg("case %zu: '%s' lacks '%s'", i, err.msg, cases[i].msg);
	}
}

/* the events a channel reports (on_event), counted */
typedef struct event_count {
	long long n[4];
	long long last_sent_seq, bad_order;
	int last_delay, max_step, min_delay, max_delay;
} event_count;

static void count_event(void *user, long long k, long long seq, popc_channel_event ev,
			long long delay)
{
	event_count *c = user;
	c->n[ev]++;
	if (ev == POPC_CHANNEL_SENT) {
		if (seq != k || seq != c->last_sent_seq + 1)
			c->bad_order++;
		c->last_sent_seq = seq;
		if (delay >= 0) {
			if (c->last_delay >= 0 && abs((int)delay - c->last_delay) > c->max_step)
				c->max_step = abs((int)delay - c->last_delay);
			c->min_delay = delay < c->min_delay ? (int)delay : c->min_delay;
			c->max_delay = delay > c->max_delay ? (int)delay : c->max_delay;
		}
		c->last_delay = (int)delay; /* -1 after a loss: the next step is not counted */
	}
	if ((ev == POPC_CHANNEL_DELIVERED || ev == POPC_CHANNEL_STALE) && delay != k - seq)
		c->bad_order++;
}

/* Every packet is sent once and then lost, delivered, stale, or still in
 * flight; the counts match the channel's stats; a random walk of jitter moves
 * by at most one tick between consecutive packets and covers its range */
static void test_events_and_walk(void **state)
{
	(void)state;
	const struct {
		popc_channel_config c;
		int walk_lo, walk_hi; /* walk: the delays it must reach (0, 0: not a walk) */
	} cases[] = {
		{{.delay_ticks = 5, .jitter_ticks = 9, .loss = 0.2, .seed = 3}, 0, 0},
		{{.delay_ticks = 5, .jitter_ticks = 9, .loss = 0.2, .in_order = 1, .seed = 4}, 0, 0},
		{{.delay_ticks = 40, .jitter_ticks = 12, .seed = 5, .jitter_walk = 1}, 40, 52},
		{{.delay_ticks = 2, .jitter_ticks = 3, .loss = 0.1, .seed = 6, .jitter_walk = 1}, 2, 5},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_channel ch = open_channel(cases[i].c);
		event_count c = {.last_sent_seq = -1, .last_delay = -1, .min_delay = 1 << 30};
		ch.on_event = count_event;
		ch.event_user = &c;
		popc_packet held = {.seq = -1};
		const long long n = 20000;
		for (long long k = 0; k < n; k++) {
			popc_packet p = packet_at(k);
			popc_channel_send(&ch, k, &p);
			popc_channel_receive(&ch, k, &held, NULL);
		}
		const long long in_flight = popc_channel_in_flight(&ch);
		assert_int_equal(c.n[POPC_CHANNEL_SENT], n);
		assert_int_equal(c.n[POPC_CHANNEL_SENT], c.n[POPC_CHANNEL_DELIVERED] +
								 c.n[POPC_CHANNEL_STALE] +
								 c.n[POPC_CHANNEL_LOST] + in_flight);
		assert_int_equal(c.n[POPC_CHANNEL_LOST], ch.stats.lost);
		assert_int_equal(c.n[POPC_CHANNEL_STALE], ch.stats.stale);
		assert_int_equal(c.n[POPC_CHANNEL_DELIVERED] + c.n[POPC_CHANNEL_STALE],
				 ch.stats.delivered);
		assert_int_equal(c.bad_order, 0);
		assert_true(in_flight <= ch.max_delay + 1);
		if (cases[i].walk_hi) {
			assert_int_equal(c.max_step, 1);
			assert_int_equal(c.min_delay, cases[i].walk_lo);
			assert_int_equal(c.max_delay, cases[i].walk_hi);
		}
		popc_channel_free(&ch);
	}
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_constant_delay),
		cmocka_unit_test(test_jitter_reorders_but_never_back_in_time),
		cmocka_unit_test(test_in_order_never_stale),
		cmocka_unit_test(test_loss_holds_last),
		cmocka_unit_test(test_seeded),
		cmocka_unit_test(test_trace),
		cmocka_unit_test(test_refusals),
		cmocka_unit_test(test_events_and_walk),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
