/* The teleoperator's packet channel (core/channel.h): a constant delay
 * arrives on its tick; with jitter every packet that is not lost arrives
 * exactly once, within its delay range, and the held packet never goes back
 * in time (reordered ones arrive stale); in order, none is stale and
 * arrivals keep their order; losses hold the last packet; the same seed
 * gives the same run and another seed another; a trace gives its delays;
 * a bad configuration is refused naming the parameter. Counting only: no
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
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
