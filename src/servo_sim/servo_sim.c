/* popc-servo-sim: a Modbus server (libmodbus, TCP or RTU) that behaves like a
 * servo drive with any register map, around the simulated plant of a scene.
 * Used by the tests and by users to dry-run a register map (docs/MODBUS.md).
 *
 *   popc-servo-sim --map MAPFILE --listen URI --scene SCENE [--lockstep] [faults]
 *
 * One client at a time (a TCP server goes back to accept() when its client
 * leaves). Requests are numbered from 1 over the program's life; the fault
 * options name requests by number. */
#include <errno.h>
#include <getopt.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <modbus.h>

#include "popc_config.h"

#include "drive.h"
#include "frame.h"
#include "popc/axes/modbus_axis.h"
#include "popc/programs/env.h"
#include "popc/scene/data_path.h"
#include "popc/util/clock.h"
#include "popc/util/parse.h"
#include "popc/util/same_file.h"
#include "popc/programs/stdfds.h"
#include "popc/programs/options.h"
#include "popc/programs/usage_hint.h"

static volatile sig_atomic_t stop_requested = 0;

static void on_signal(int sig)
{
	(void)sig;
	stop_requested = 1;
}

static void usage(FILE *f)
{
	fputs("usage: popc-servo-sim --map MAPFILE --listen URI --scene SCENE [options]\n"
	      "\n"
	      "A Modbus server that behaves like a servo drive described by MAPFILE, wrapped\n"
	      "around the simulated plant of SCENE.\n"
	      "URI: " POPC_URI_NOTATION "\n"
	      "(" POPC_URI_DEFAULTS "; FORMAT: data bits, parity N/E/O,\n"
	      "stop bits; PORT 0: any free port). Prints 'popc-servo-sim: listening on URI'\n"
	      "on standard output when ready; stops cleanly on SIGTERM or SIGINT.\n"
	      "\n"
	      "  --lockstep            advance the plant one control period per command\n"
	      "                        written while enabled (deterministic); default: real time;\n"
	      "                        with the map's command.sequence_register, a command that\n"
	      "                        repeats the last sequence value (a retry) does not advance\n"
	      "  --set section.key=V   override a scene key (repeatable)\n"
	      "  --watchdog-ms MS      command watchdog (default: the map's drive.watchdog_ms)\n"
	      "  --record FILE         on exit, write the last writes of command and enable\n"
	      "                        there (oldest first), e.g. 'command 0 [0000 0000]' (the\n"
	      "                        force, then the register's words) and 'enable 0x0000';\n"
	      "                        not onto the map, the scene or its operator table\n"
	      "  --notify-at AT        print 'popc-servo-sim: request N' on stdout at request AT\n"
	      "  --pace-baud           RTU: hold each reply for the wire time of request and\n"
	      "                        reply at the URI's baud plus two 3.5-character gaps\n"
	      "                        (a pseudo-terminal does not pace bytes)\n",
	      f);
	/* two strings: one would pass the 4095 characters C99 promises */
	fputs("fault injection (AT: N, request N from 1; or cC[+K], the request that writes\n"
	      "command C, from 1 (the start's zero force is command 1; a retry that repeats\n"
	      "the sequence value is the same command), or the K-th request after it;\n"
	      "COUNT: how many requests from AT on, default 1; N, C, K and COUNT up to\n"
	      "10^15; MS up to 86400000, a day):\n"
	      "  --drop AT[,COUNT]     apply the request but send no reply\n"
	      "  --delay AT,MS[,COUNT] reply MS milliseconds late; on TCP, when MS is above the\n"
	      "                        map's timeout_ms, also not before the client has closed\n"
	      "                        the connection (it gave up on the reply)\n"
	      "  --duplicate AT[,COUNT] send the reply twice (one write: both arrive together)\n"
	      "  --reorder AT[,COUNT]  hold the reply to AT back and send it right after the\n"
	      "                        reply to the next request (one write)\n"
	      "  --exception AT,CODE[,COUNT]  answer with Modbus exception CODE, apply nothing\n"
	      "  --corrupt-crc AT[,COUNT]     RTU: send the reply with a wrong CRC\n"
	      "  --wrong-unit AT[,COUNT]      reply with the unit id (RTU: slave address) + 1\n"
	      "  --wrong-tid AT[,COUNT]       TCP: reply with the transaction id + 1\n"
	      "  --wrong-protocol AT,ID[,COUNT]  TCP: reply with protocol id ID (1-65535)\n"
	      "  --wrong-length AT[,COUNT]    TCP: reply with the MBAP length field + 1\n"
	      "  --close-after AT      TCP: close the connection after replying to request AT\n"
	      "                        (then accept the next one)\n"
	      "  --exit-after AT       close the link and exit after replying to request AT\n"
	      "  --fault-at AT         set the drive's fault bits at request AT\n"
	      "  --start-faulted       report a fault from the start (it never clears)\n"
	      "  --never-ready         never show the ready bits (an enable that never completes)\n"
	      "  --map-keys            list every register map key with its default and\n"
	      "                        allowed values, and exit (docs/MODBUS.md)\n"
	      "  -h, --help            this help\n"
	      "  --version             print popc-servo-sim's version and exit\n"
	      "\n"
	      "On exit it prints on standard error how many requests it served and how many\n"
	      "received frames were malformed (bad CRC, another slave, a bad MBAP header, an\n"
	      "unknown function): a client must never send one; over RTU also the shortest\n"
	      "silence it measured before a request (a map's rtu_frame_gap_ms kept).\n"
	      "A map's command.mode is the scene's device: force with an impedance scene,\n"
	      "position or velocity (admittance.servo) with an admittance scene, whose\n"
	      "force sensor fills [force_sensor], or around a teleoperation scene's slave\n"
	      "(slave.servo; popc run --axis modbus makes the drive the slave); a position\n"
	      "drive interpolates to each set\n"
	      "point over one period and, while disabled, its set point register reads its\n"
	      "actual position.\n"
	      "A map's position.direction and command.direction = reversed are honoured\n"
	      "(the registers hold minus the position and minus the command); its RTU line\n"
	      "keys rs485, rts and rts_delay_us are not used (the drive's side of the line).\n"
	      "MAPFILE and SCENE may be names of installed files: a name without a '/' that\n"
	      "is not in the working directory is looked up in the data directories'\n"
	      "drives/ and scenes/, as NAME then NAME.ini (POPC_DATA_PATH; popc(1)).\n"
	      "\n"
	      "Exit status: 0 stopped by a signal or --exit-after, 2 usage, 1 failure.\n",
	      f);
}

/* Where a fault hits: request `at`, known from the start (N) or once the
 * request that writes command `cmd` arrives (cC[+K]: that request's number
 * plus `off`). Counting commands, not requests, a fault hits the same tick
 * however many transactions popc retried before it. */
typedef struct trigger {
	long at;        /* request number; 0: not known yet (or no trigger) */
	long cmd, off;  /* cC+K: cmd = C > 0, off = K */
} trigger;

typedef struct fault_range {
	trigger first;
	long count, arg;
} fault_range;

/* The option was given. */
static int is_set(const trigger *t)
{
	return t->at > 0 || t->cmd > 0;
}

static int hits(const trigger *t, long n)
{
	return t->at > 0 && n == t->at;
}

static int in_range(const fault_range *r, long n)
{
	return r->first.at > 0 && n >= r->first.at && n - r->first.at < r->count;
}

/* Request numbers, command numbers, offsets and counts stop at 10^15 (32
 * years of requests at 1 MHz), so at + off, at + count and a request counter
 * never overflow a long; an argument (a delay in ms, a code, a protocol id)
 * stops at a day in ms, so t + MS * 10^6 ns stays far inside an int64. */
#define FAULT_REQUEST_MAX 1000000000000000L
#define FAULT_ARG_MAX 86400000L

/* Request n writes command c (0: none): the triggers on c learn their request. */
static void resolve(trigger *t, long long c, long n)
{
	if (t->cmd > 0 && t->at == 0 && c == t->cmd)
		t->at = n + t->off;
}

/* A whole number in [min, max] filling [s, end) (popc/util/parse.h). */
static int parse_span(const char *s, const char *end, long min, long max, long *out)
{
	long long v;
	if (popc_parse_ll_span(s, end, min, max, 0, &v) != 0)
		return -1;
	*out = (long)v;
	return 0;
}

/* "N" (N >= 1) or "cC" or "cC+K" (C >= 1, K >= 0), all up to
 * FAULT_REQUEST_MAX, filling [s, end). */
static int parse_trigger(const char *s, const char *end, trigger *t)
{
	*t = (trigger){0, 0, 0};
	if (s == end || *s != 'c')
		return parse_span(s, end, 1, FAULT_REQUEST_MAX, &t->at);
	s++;
	const char *plus = memchr(s, '+', (size_t)(end - s));
	if (!plus)
		return parse_span(s, end, 1, FAULT_REQUEST_MAX, &t->cmd);
	/* a sign after the '+' would be a second sign: "c5++3" is refused */
	if (parse_span(s, plus, 1, FAULT_REQUEST_MAX, &t->cmd) || plus[1] == '+' || plus[1] == '-')
		return -1;
	return parse_span(plus + 1, end, 0, FAULT_REQUEST_MAX, &t->off);
}

/* A trigger and nothing else. */
static int parse_at(const char *text, trigger *t)
{
	return parse_trigger(text, text + strlen(text), t);
}

/* "AT[,COUNT]" or, with want_arg, "AT,ARG[,COUNT]": a trigger, then whole
 * numbers as everywhere (popc/util/parse.h), COUNT in [1, FAULT_REQUEST_MAX],
 * ARG in [0, FAULT_ARG_MAX]; a value past the last one, a blank or an empty
 * field is refused, not ignored. */
static int parse_range(const char *text, int want_arg, fault_range *r)
{
	long v[2] = {0, 0};
	int n = 0, max = want_arg ? 2 : 1;
	const char *end = text + strcspn(text, ",");
	if (parse_trigger(text, end, &r->first))
		return -1;
	while (*end) {
		const char *p = end + 1;
		end = p + strcspn(p, ",");
		int is_arg = want_arg && n == 0;
		if (n == max || parse_span(p, end, is_arg ? 0 : 1, is_arg ? FAULT_ARG_MAX : FAULT_REQUEST_MAX,
					   &v[n]) != 0)
			return -1;
		n++;
	}
	if (n < want_arg)
		return -1;
	r->arg = want_arg ? v[0] : 0;
	r->count = n > want_arg ? v[want_arg] : 1;
	return 0;
}

/* A whole number in [min, max] (parse.h). */
static int parse_count(const char *text, long min, long max, long *out)
{
	long long v;
	if (popc_parse_ll_text(text, min, max, &v) != 0)
		return -1;
	*out = (long)v;
	return 0;
}

typedef struct server {
	servo_drive drive;
	modbus_t *ctx;
	popc_modbus_uri uri;
	int listen_fd;
	sigset_t run_mask;        /* the mask during pselect: termination signals deliverable */
	int capture[2];           /* socketpair: replies built here, then held or altered */
	long requests;
	long malformed;           /* received frames that are not a well-formed request */
	fault_range drop, delay, exception, corrupt, duplicate, reorder;
	fault_range wrong_unit, wrong_tid, wrong_protocol, wrong_length;
	uint8_t held[MODBUS_MAX_ADU_LENGTH + 8]; /* --reorder: a reply held back */
	int n_held;
	trigger close_after, exit_after, fault_at, notify_at;
	int pace_baud;
	int exiting;
	/* RTU: the silence before each request, from the end of the last frame
	 * on the line (a request received or a reply sent) to the request's
	 * first byte: what a drive that needs a gap between frames sees. A
	 * reply's end is stamped just before its write (the write puts the
	 * whole frame on the pty at once, after --pace's sleep): a server
	 * preempted after the write would otherwise stamp it late and report a
	 * silence shorter than the client kept (8.98 ms against a kept 10 ms,
	 * seen beside two parallel builds). So the measured silence exceeds the
	 * wire's by at most the write's own duration. */
	int64_t line_busy_ns;      /* 0: no frame yet */
	int64_t silence_min_ns;    /* -1: no request after a frame yet */
	long silences;
} server;

/* Waits until fd is readable, a timeout (ms, -1: none) passes or a
 * termination signal arrives. Returns 1 readable, 0 timeout, -1 signal. */
static int wait_readable(server *sv, int fd, int timeout_ms)
{
	fd_set rd;
	FD_ZERO(&rd);
	if (fd >= 0)
		FD_SET(fd, &rd);
	struct timespec ts = {timeout_ms / 1000, (long)(timeout_ms % 1000) * 1000000};
	int r = pselect(fd + 1, &rd, NULL, NULL, timeout_ms >= 0 ? &ts : NULL, &sv->run_mask);
	if (r < 0)
		return errno == EINTR && stop_requested ? -1 : 0;
	return r > 0 ? 1 : 0;
}

/* Sleeps until an absolute CLOCK_MONOTONIC time, or until a termination signal. */
static void sleep_until(server *sv, int64_t t_ns)
{
	for (;;) {
		int64_t left = t_ns - popc_now_ns();
		if (left <= 0 || stop_requested)
			return;
		struct timespec ts = {(time_t)(left / 1000000000), (long)(left % 1000000000)};
		pselect(0, NULL, NULL, NULL, &ts, &sv->run_mask);
	}
}

/* Wire time of n characters (start bit, data bits, parity, stop bits). */
static int64_t wire_ns(const popc_modbus_uri *u, int n)
{
	int bits = 1 + u->data_bits + (u->parity != 'N') + u->stop_bits;
	return (int64_t)n * bits * 1000000000LL / u->baud;
}

/* The silent interval that ends an RTU frame: 3.5 characters, fixed at
 * 1.75 ms above 19200 baud (Modbus over Serial Line V1.02, 2.5.1.1). */
static int64_t t35_ns(const popc_modbus_uri *u)
{
	return u->baud > 19200 ? 1750000 : wire_ns(u, 7) / 2;
}

/* Builds the reply into the capture socket pair instead of the link. */
static int capture_reply(server *sv, const uint8_t *q, int len, uint8_t *out, int cap)
{
	int real = modbus_get_socket(sv->ctx);
	modbus_set_socket(sv->ctx, sv->capture[0]);
	int n = modbus_reply(sv->ctx, q, len, sv->drive.mb);
	modbus_set_socket(sv->ctx, real);
	if (n <= 0)
		return -1;
	int got = 0;
	while (got < n && got < cap) {
		ssize_t r = read(sv->capture[1], out + got, (size_t)(cap - got));
		if (r <= 0)
			return -1;
		got += (int)r;
	}
	return got;
}

static void send_raw(server *sv, const uint8_t *buf, int n)
{
	int fd = modbus_get_socket(sv->ctx);
	int off = 0;
	sv->line_busy_ns = popc_now_ns(); /* before the write: see line_busy_ns */
	while (off < n) {
		ssize_t w = sv->uri.rtu ? write(fd, buf + off, (size_t)(n - off))
					: send(fd, buf + off, (size_t)(n - off), MSG_NOSIGNAL);
		if (w <= 0) {
			if (w < 0 && errno == EINTR)
				continue;
			return;
		}
		off += (int)w;
	}
}

/* The reply faults that alter or hold the built frame (the others act on
 * whether and when a reply is sent). */
static int reply_altered(const server *sv, long n)
{
	return (sv->uri.rtu && (in_range(&sv->corrupt, n) || sv->pace_baud)) ||
	       in_range(&sv->duplicate, n) || in_range(&sv->reorder, n) || sv->n_held > 0 ||
	       in_range(&sv->wrong_unit, n) || in_range(&sv->wrong_tid, n) ||
	       in_range(&sv->wrong_protocol, n) || in_range(&sv->wrong_length, n);
}

/* Builds the reply to request n, alters it as the fault options ask and
 * sends it (with a held-back one after it) in one write. */
static void send_altered_reply(server *sv, long n, const uint8_t *q, int len, int64_t t_rx)
{
	uint8_t buf[2 * (MODBUS_MAX_ADU_LENGTH + 8)];
	int cap = MODBUS_MAX_ADU_LENGTH + 8;
	int r = capture_reply(sv, q, len, buf, cap);
	if (r <= 0)
		return;
	int tcp = !sv->uri.rtu;
	if (sv->uri.rtu && in_range(&sv->corrupt, n))
		buf[r - 1] ^= 0xA5; /* the CRC's high byte */
	if (in_range(&sv->wrong_unit, n))
		frame_apply_fault(buf, r, tcp, FRAME_WRONG_UNIT, 0);
	if (tcp && in_range(&sv->wrong_tid, n))
		frame_apply_fault(buf, r, tcp, FRAME_WRONG_TID, 0);
	if (tcp && in_range(&sv->wrong_protocol, n))
		frame_apply_fault(buf, r, tcp, FRAME_WRONG_PROTOCOL, sv->wrong_protocol.arg);
	if (tcp && in_range(&sv->wrong_length, n))
		frame_apply_fault(buf, r, tcp, FRAME_WRONG_LENGTH, 0);
	if (in_range(&sv->reorder, n) && sv->n_held == 0) {
		memcpy(sv->held, buf, (size_t)r); /* sent after the next reply */
		sv->n_held = r;
		return;
	}
	int total = r;
	if (in_range(&sv->duplicate, n)) {
		memcpy(buf + r, buf, (size_t)r);
		total += r;
	} else if (sv->n_held > 0) {
		memcpy(buf + r, sv->held, (size_t)sv->n_held);
		total += sv->n_held;
		sv->n_held = 0;
	}
	if (sv->uri.rtu && sv->pace_baud)
		sleep_until(sv, t_rx + wire_ns(&sv->uri, len) + wire_ns(&sv->uri, r) + 2 * t35_ns(&sv->uri));
	send_raw(sv, buf, total);
}

/* --delay: the reply to request n leaves MS ms after the request came. A
 * reply later than the map's timeout_ms is one the client has given up on:
 * on TCP it is held until the client has closed the connection (popc
 * reconnects after a timeout and sends nothing more on the old one), so
 * that the client's own scheduling cannot make it arrive in time; on RTU,
 * where the client drains the line instead, a request that came in the
 * meantime is said (the late reply then follows the client's next request,
 * which is not the case the option was asked for). */
static void hold_late_reply(server *sv, long n, int64_t t_rx)
{
	sleep_until(sv, t_rx + sv->delay.arg * 1000000LL);
	if (sv->delay.arg <= sv->drive.map.timeout_ms)
		return;
	int fd = modbus_get_socket(sv->ctx);
	if (!sv->uri.rtu) {
		wait_readable(sv, fd, -1);
	} else if (wait_readable(sv, fd, 0) == 1) {
		fprintf(stderr, "popc-servo-sim: request %ld: the next request came before this reply, "
				"%ld ms late\n",
			n, sv->delay.arg);
	}
}

/* Handles one received request. Returns 1 to close the connection, 0 to go on. */
static int handle(server *sv, const uint8_t *q, int len, int64_t t_rx)
{
	long n = ++sv->requests;
	long long c = drive_command_of(&sv->drive, q, len, modbus_get_header_length(sv->ctx));
	trigger *all[] = {&sv->notify_at, &sv->fault_at, &sv->close_after, &sv->exit_after,
			  &sv->drop.first,       &sv->delay.first,        &sv->exception.first,
			  &sv->corrupt.first,    &sv->duplicate.first,    &sv->reorder.first,
			  &sv->wrong_unit.first, &sv->wrong_tid.first,    &sv->wrong_protocol.first,
			  &sv->wrong_length.first};
	for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
		resolve(all[i], c, n);
	if (hits(&sv->notify_at, n)) {
		printf("popc-servo-sim: request %ld\n", n);
		fflush(stdout);
	}
	if (hits(&sv->fault_at, n)) {
		fprintf(stderr, "popc-servo-sim: injected drive fault at request %ld\n", n);
		drive_set_fault(&sv->drive, "injected", 0);
	}
	if (in_range(&sv->exception, n)) {
		sv->line_busy_ns = popc_now_ns(); /* before the write: see line_busy_ns */
		modbus_reply_exception(sv->ctx, q, (unsigned)sv->exception.arg);
		return 0;
	}
	drive_tick(&sv->drive, t_rx);
	drive_apply_request(&sv->drive, q, len, modbus_get_header_length(sv->ctx), t_rx);
	if (in_range(&sv->drop, n))
		return 0;
	if (in_range(&sv->delay, n))
		hold_late_reply(sv, n, t_rx);
	if (reply_altered(sv, n)) {
		send_altered_reply(sv, n, q, len, t_rx);
	} else {
		sv->line_busy_ns = popc_now_ns(); /* before the write: see line_busy_ns */
		modbus_reply(sv->ctx, q, len, sv->drive.mb);
	}
	if (sv->exit_after.at > 0 && n >= sv->exit_after.at) {
		sv->exiting = 1;
		return 1;
	}
	return hits(&sv->close_after, n);
}

/* A received frame that is not a well-formed request: counted (the exit
 * report gives the number), the first few said on standard error. */
static void note_malformed(server *sv, const char *why)
{
	if (++sv->malformed <= 5)
		fprintf(stderr, "popc-servo-sim: malformed request (%s)\n", why);
}

/* Serves requests on the open link until it closes or a signal arrives. */
static void serve_link(server *sv)
{
	uint8_t q[MODBUS_MAX_ADU_LENGTH > MODBUS_RTU_MAX_ADU_LENGTH ? MODBUS_MAX_ADU_LENGTH
								    : MODBUS_RTU_MAX_ADU_LENGTH];
	int fd = modbus_get_socket(sv->ctx);
	int tick_ms = sv->drive.watchdog_ms > 0 ? 5 : 100;
	while (!stop_requested && !sv->exiting) {
		int r = wait_readable(sv, fd, tick_ms);
		int64_t t_first = popc_now_ns(); /* the request's first byte is here (r == 1) */
		drive_tick(&sv->drive, t_first);
		if (r < 0)
			return;
		if (r == 0)
			continue;
		errno = 0;
		int len = modbus_receive(sv->ctx, q);
		int64_t t_rx = popc_now_ns();
		if (sv->uri.rtu && sv->line_busy_ns > 0) {
			int64_t silence = t_first - sv->line_busy_ns;
			if (sv->silence_min_ns < 0 || silence < sv->silence_min_ns)
				sv->silence_min_ns = silence;
			sv->silences++;
		}
		sv->line_busy_ns = t_rx;
		if (len < 0) {
			if (!sv->uri.rtu) {
				/* the client left (ECONNRESET: libmodbus' word for an
				 * orderly close too), or the stream broke mid-frame */
				if (errno != ECONNRESET)
					note_malformed(sv, modbus_strerror(errno));
				return; /* next client */
			}
			note_malformed(sv, modbus_strerror(errno)); /* a damaged RTU frame */
			modbus_flush(sv->ctx);
			continue;
		}
		const char *why = "addressed to another slave";
		if (len == 0 || !frame_request_ok(q, len, !sv->uri.rtu, sv->drive.map.slave, &why)) {
			note_malformed(sv, why);
			if (!sv->uri.rtu)
				return; /* a TCP stream out of step cannot be trusted: drop it */
			modbus_flush(sv->ctx);
			continue;
		}
		if (handle(sv, q, len, t_rx))
			return;
	}
}

static void print_ready(server *sv)
{
	char text[POPC_PATH_MAX + 64];
	if (!sv->uri.rtu) {
		struct sockaddr_storage ss;
		socklen_t sl = sizeof ss;
		if (getsockname(sv->listen_fd, (struct sockaddr *)&ss, &sl) == 0) {
			int port = ss.ss_family == AF_INET6 ? ntohs(((struct sockaddr_in6 *)&ss)->sin6_port)
							    : ntohs(((struct sockaddr_in *)&ss)->sin_port);
			snprintf(sv->uri.port, sizeof sv->uri.port, "%d", port);
		}
	}
	popc_modbus_uri_format(&sv->uri, text, sizeof text);
	printf("popc-servo-sim: listening on %s\n", text);
	fflush(stdout);
}

static int run_server(server *sv)
{
	if (sv->uri.rtu) {
		sv->ctx = modbus_new_rtu(sv->uri.device, sv->uri.baud, sv->uri.parity, sv->uri.data_bits,
					 sv->uri.stop_bits);
		if (!sv->ctx || modbus_set_slave(sv->ctx, sv->drive.map.slave) != 0 ||
		    modbus_connect(sv->ctx) != 0) {
			fprintf(stderr, "popc-servo-sim: %s: %s\n", sv->uri.device, modbus_strerror(errno));
			return POPC_EXIT_RUN_FAILED;
		}
		print_ready(sv);
		while (!stop_requested && !sv->exiting)
			serve_link(sv);
		return 0;
	}
	sv->ctx = modbus_new_tcp_pi(sv->uri.host, sv->uri.port);
	if (!sv->ctx) {
		fprintf(stderr, "popc-servo-sim: %s\n", modbus_strerror(errno));
		return POPC_EXIT_RUN_FAILED;
	}
	sv->listen_fd = modbus_tcp_pi_listen(sv->ctx, 1);
	if (sv->listen_fd < 0) {
		fprintf(stderr, "popc-servo-sim: listen on %s:%s: %s\n", sv->uri.host, sv->uri.port,
			modbus_strerror(errno));
		return POPC_EXIT_RUN_FAILED;
	}
	print_ready(sv);
	while (!stop_requested && !sv->exiting) {
		int r = wait_readable(sv, sv->listen_fd, sv->drive.watchdog_ms > 0 ? 5 : 100);
		drive_tick(&sv->drive, popc_now_ns());
		if (r <= 0)
			continue;
		int s = sv->listen_fd;
		if (modbus_tcp_pi_accept(sv->ctx, &s) < 0)
			continue;
		int one = 1;
		setsockopt(modbus_get_socket(sv->ctx), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
		serve_link(sv);
		modbus_close(sv->ctx);
	}
	close(sv->listen_fd);
	return 0;
}

enum { OPT_MAP = 256, OPT_LISTEN, OPT_SCENE, OPT_LOCKSTEP, OPT_SET, OPT_WATCHDOG, OPT_RECORD,
       OPT_NOTIFY, OPT_PACE, OPT_DROP, OPT_DELAY, OPT_EXCEPTION, OPT_CORRUPT, OPT_CLOSE,
       OPT_EXIT, OPT_FAULT_AT, OPT_START_FAULTED, OPT_NEVER_READY, OPT_MAP_KEYS, OPT_DUPLICATE,
       OPT_REORDER, OPT_WRONG_UNIT, OPT_WRONG_TID, OPT_WRONG_PROTOCOL, OPT_WRONG_LENGTH };

static const popc_option sim_options[] = {
	{"map", 0, OPT_MAP, "MAP"},
	{"listen", 0, OPT_LISTEN, "URI"},
	{"scene", 0, OPT_SCENE, "SCENE"},
	{"lockstep", 0, OPT_LOCKSTEP, NULL},
	{"set", 0, OPT_SET, "KEY=VALUE"},
	{"watchdog-ms", 0, OPT_WATCHDOG, "MS"},
	{"record", 0, OPT_RECORD, "FILE"},
	{"notify-at", 0, OPT_NOTIFY, "N"},
	{"pace-baud", 0, OPT_PACE, NULL},
	{"drop", 0, OPT_DROP, "SPEC"},
	{"delay", 0, OPT_DELAY, "SPEC"},
	{"exception", 0, OPT_EXCEPTION, "SPEC"},
	{"corrupt-crc", 0, OPT_CORRUPT, "SPEC"},
	{"close-after", 0, OPT_CLOSE, "SPEC"},
	{"exit-after", 0, OPT_EXIT, "SPEC"},
	{"fault-at", 0, OPT_FAULT_AT, "SPEC"},
	{"start-faulted", 0, OPT_START_FAULTED, NULL},
	{"never-ready", 0, OPT_NEVER_READY, NULL},
	{"map-keys", 0, OPT_MAP_KEYS, NULL},
	{"duplicate", 0, OPT_DUPLICATE, "SPEC"},
	{"reorder", 0, OPT_REORDER, "SPEC"},
	{"wrong-unit", 0, OPT_WRONG_UNIT, "SPEC"},
	{"wrong-tid", 0, OPT_WRONG_TID, "SPEC"},
	{"wrong-protocol", 0, OPT_WRONG_PROTOCOL, "SPEC"},
	{"wrong-length", 0, OPT_WRONG_LENGTH, "SPEC"},
	{"help", 'h', 'h', NULL},
	{"version", 0, 'V', NULL},
	POPC_OPTION_END,
};
static const popc_option *const sim_opts[] = {sim_options, NULL};

int main(int argc, char **argv)
{
	if (popc_stdfds_make_safe() != 0)
		return POPC_EXIT_RUN_FAILED; /* no /dev/null: a socket could land on a closed 0-2 */
	if (argc == 2 && strcmp(argv[1], "--complete") == 0) {
		/* hidden: the bash completion and tests/cli/test_options_agree.sh
		 * read the option table (options.h) */
		popc_options_complete(stdout, "", sim_opts);
		return fflush(stdout) == 0 && !ferror(stdout) ? POPC_EXIT_OK : POPC_EXIT_RUN_FAILED;
	}
	struct option opts[64];
	char shorts[128];
	if (popc_options_getopt(sim_opts, opts, 64, shorts, 128) != 0)
		abort(); /* the arrays hold the table: a programming error */
	static server sv;
	const char *map_path = NULL, *listen = NULL, *scene_path = NULL, *record_path = NULL;
	const char *sets[64];
	int n_sets = 0, lockstep = 0, start_faulted = 0, never_ready = 0, c;
	long watchdog = -1;
	static char prog[] = "popc-servo-sim";
	argv[0] = prog; /* getopt's messages name argv[0], not the path it was run by */
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		int bad = 0;
		switch (c) {
		case OPT_MAP: map_path = optarg; break;
		case OPT_LISTEN: listen = optarg; break;
		case OPT_SCENE: scene_path = optarg; break;
		case OPT_LOCKSTEP: lockstep = 1; break;
		case OPT_SET:
			if (n_sets == 64)
				bad = 1;
			else
				sets[n_sets++] = optarg;
			break;
		case OPT_WATCHDOG: bad = parse_count(optarg, 0, 600000, &watchdog); break;
		case OPT_RECORD: record_path = optarg; break;
		case OPT_NOTIFY: bad = parse_at(optarg, &sv.notify_at); break;
		case OPT_PACE: sv.pace_baud = 1; break;
		case OPT_DROP: bad = parse_range(optarg, 0, &sv.drop); break;
		case OPT_DELAY: bad = parse_range(optarg, 1, &sv.delay); break;
		case OPT_EXCEPTION:
			bad = parse_range(optarg, 1, &sv.exception) || sv.exception.arg < 1 ||
			      sv.exception.arg > 255;
			break;
		case OPT_CORRUPT: bad = parse_range(optarg, 0, &sv.corrupt); break;
		case OPT_CLOSE: bad = parse_at(optarg, &sv.close_after); break;
		case OPT_EXIT: bad = parse_at(optarg, &sv.exit_after); break;
		case OPT_FAULT_AT: bad = parse_at(optarg, &sv.fault_at); break;
		case OPT_START_FAULTED: start_faulted = 1; break;
		case OPT_NEVER_READY: never_ready = 1; break;
		case OPT_MAP_KEYS: popc_register_map_print_keys(stdout); return 0;
		case OPT_DUPLICATE: bad = parse_range(optarg, 0, &sv.duplicate); break;
		case OPT_REORDER: bad = parse_range(optarg, 0, &sv.reorder); break;
		case OPT_WRONG_UNIT: bad = parse_range(optarg, 0, &sv.wrong_unit); break;
		case OPT_WRONG_TID: bad = parse_range(optarg, 0, &sv.wrong_tid); break;
		case OPT_WRONG_PROTOCOL:
			bad = parse_range(optarg, 1, &sv.wrong_protocol) || sv.wrong_protocol.arg < 1 ||
			      sv.wrong_protocol.arg > 65535;
			break;
		case OPT_WRONG_LENGTH: bad = parse_range(optarg, 0, &sv.wrong_length); break;
		case 'h': usage(stdout); return 0;
		case 'V': printf("popc-servo-sim %s\n", POPC_VERSION); return 0;
		default: popc_option_hint("popc-servo-sim", opts, argc, argv); return POPC_EXIT_USAGE;
		}
		if (bad) {
			fprintf(stderr, "popc-servo-sim: bad value '%s' for --%s\n", optarg,
				opts[c - OPT_MAP].name);
			return POPC_EXIT_USAGE;
		}
	}
	if (optind != argc || !map_path || !listen || !scene_path) {
		fprintf(stderr, "popc-servo-sim: %s\n",
			optind != argc ? "unexpected argument" : "--map, --listen and --scene are required");
		popc_help_hint("popc-servo-sim", "options");
		return POPC_EXIT_USAGE;
	}
	popc_error err;
	popc_register_map map;
	popc_scene scene;
	/* a bare map name not in the working directory: an installed drive map
	 * (data_path.h), as popc run --map finds it */
	char map_found[POPC_PATH_MAX];
	int st = popc_data_find(POPC_DATA_DRIVES, map_path, NULL, popc_env_data_path(), map_found,
				sizeof map_found, &err);
	if (st == 1)
		map_path = map_found;
	if (st >= 0)
		st = popc_register_map_load(&map, map_path, &err);
	if (!st) {
		st = popc_env_scene_defaults(&scene, &err);
		if (!st)
			st = popc_scene_load(&scene, scene_path, &err);
		for (int i = 0; !st && i < n_sets; i++)
			st = popc_scene_set_assignment(&scene, sets[i], &err);
		if (!st)
			st = popc_scene_validate(&scene, &err);
		/* the drive's command mode must be the scene's device (popc run's
		 * own rule): a force drive around an impedance plant, a position
		 * or velocity drive around the admittance-type device */
		if (!st)
			st = popc_register_map_fits_scene(&map, &scene, &err);
	}
	if (!st)
		st = popc_modbus_uri_parse(listen, &sv.uri, &err);
	if (!st && sv.uri.rtu && is_set(&sv.close_after))
		st = popc_error_set(&err, POPC_ERR_INVALID, "--close-after needs a TCP link");
	if (!st && !sv.uri.rtu && (is_set(&sv.corrupt.first) || sv.pace_baud))
		st = popc_error_set(&err, POPC_ERR_INVALID, "--corrupt-crc and --pace-baud need an RTU link");
	if (!st && sv.uri.rtu && (is_set(&sv.wrong_tid.first) || is_set(&sv.wrong_protocol.first) ||
				   is_set(&sv.wrong_length.first)))
		st = popc_error_set(&err, POPC_ERR_INVALID,
				    "--wrong-tid, --wrong-protocol and --wrong-length need a TCP link (RTU "
				    "frames have no MBAP header)");
	if (st) {
		fprintf(stderr, "popc-servo-sim: %s\n", err.msg);
		return st == POPC_ERR_INVALID || st == POPC_ERR_IO ? POPC_EXIT_USAGE : POPC_EXIT_RUN_FAILED;
	}
	/* --record truncates its file when it opens it (below): never one of
	 * the inputs, which it would empty (popc_same_file: a link or another
	 * spelling counts), as popc run's and popc-analyze's outputs */
	const struct {
		const char *what, *path;
	} inputs[] = {
		{"the register map (--map)", map_path},
		{"the scene (--scene)", scene_path},
		{"the operator table (operator.table)",
		 scene.intent == POPC_INTENT_TABLE ? scene.op_table : NULL},
	};
	for (size_t i = 0; record_path && i < sizeof inputs / sizeof inputs[0]; i++)
		if (popc_same_file(record_path, inputs[i].path)) {
			fprintf(stderr,
				"popc-servo-sim: --record %s is %s %s: refusing to overwrite an input "
				"(choose another --record)\n",
				record_path, inputs[i].what, inputs[i].path);
			return POPC_EXIT_USAGE;
		}
	/* the record file is opened now, so that a path that cannot be written
	 * is bad usage before the drive serves anyone, not found at exit */
	FILE *record = NULL;
	if (record_path && !(record = fopen(record_path, "w"))) {
		fprintf(stderr, "popc-servo-sim: --record %s: cannot open for writing: %s\n",
			record_path, strerror(errno));
		return POPC_EXIT_USAGE;
	}
	if (watchdog >= 0)
		map.watchdog_ms = (int)watchdog;
	if ((st = drive_init(&sv.drive, &map, &scene, lockstep, &err))) {
		fprintf(stderr, "popc-servo-sim: %s\n", err.msg);
		return POPC_EXIT_RUN_FAILED;
	}
	sv.drive.never_ready = never_ready;
	if (start_faulted)
		drive_set_fault(&sv.drive, "start-faulted", 1);
	if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv.capture) != 0) {
		perror("popc-servo-sim: socketpair");
		return POPC_EXIT_RUN_FAILED;
	}
	/* termination signals are blocked except inside pselect: no lost wake-up */
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	sigaction(SIGTERM, &sa, NULL);
	sigaction(SIGINT, &sa, NULL);
	signal(SIGPIPE, SIG_IGN);
	sigset_t block;
	sigemptyset(&block);
	sigaddset(&block, SIGTERM);
	sigaddset(&block, SIGINT);
	sigprocmask(SIG_BLOCK, &block, &sv.run_mask);
	sigdelset(&sv.run_mask, SIGTERM);
	sigdelset(&sv.run_mask, SIGINT);

	sv.silence_min_ns = -1;
	int rc = run_server(&sv);
	char repeats[96] = "", silence[128] = "";
	if (sv.uri.rtu && sv.silences > 0)
		snprintf(silence, sizeof silence, "; shortest silence before a request %.3f ms (%ld requests)",
			 1e-6 * (double)sv.silence_min_ns, sv.silences);
	if (map.cmd.seq_reg >= 0)
		snprintf(repeats, sizeof repeats, " (%lld repeated the sequence value: retries)",
			 sv.drive.seq_repeats);
	fprintf(stderr,
		"popc-servo-sim: stopped after %ld requests (%ld malformed), %lld commands%s, %lld "
		"periods%s%s%s\n",
		sv.requests, sv.malformed, sv.drive.commands, repeats, sv.drive.k, sv.drive.fault ? "; fault: " : "",
		sv.drive.fault ? sv.drive.fault_why : "", silence);
	if (record) {
		drive_write_record(&sv.drive, record);
		if (fclose(record) != 0) {
			fprintf(stderr, "popc-servo-sim: %s: cannot write the record\n", record_path);
			rc = POPC_EXIT_RUN_FAILED;
		}
	}
	if (sv.ctx) {
		modbus_close(sv.ctx);
		modbus_free(sv.ctx);
	}
	close(sv.capture[0]);
	close(sv.capture[1]);
	drive_free(&sv.drive);
	return rc;
}
