/* The Modbus axis (modbus_axis.h): a servo drive through libmodbus, with its
 * register map, pacing on absolute deadlines and the safety supervisor. */
#include "popc/axes/modbus_axis.h"

#include <errno.h>
#include <math.h>
#include <modbus.h>
#include <sched.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <time.h>

#include "../axis_kind.h"
#include "modbus_stats.h"
#include "popc/core/admittance.h"
#include "popc/core/admittance_plant.h"
#include "popc/core/encoder.h"
#include "popc/log/log.h"
#include "popc/axes/register_map.h"
#include "popc/util/clock.h"

/* Span of one block read that covers both position and status; a longer
 * span reads them separately. FC03/FC04 allow 125 registers (Modbus
 * Application Protocol V1.1b3, 6.3), FC23 reads 125 too (6.17). */
#define BLOCK_MAX 32

typedef struct mb_axis {
	popc_register_map map;
	popc_modbus_uri uri;
	char uri_text[POPC_PATH_MAX + 32];
	popc_modbus_options opt;
	modbus_t *ctx;
	int connected;

	double delta_m;
	int passthrough;           /* drive counts are scene counts */
	int64_t period_ns;
	double period_s;

	/* an admittance-type device (command.mode = position or velocity,
	 * docs/MODBUS.md, "Command modes"): the servo's set point goes out, the
	 * hand's force comes in from [force_sensor] */
	int servo;
	double x_cmd_m;            /* the position command the servo tracks from this tick
				      (position mode: the last target sent; velocity mode: the
				      velocities' integral, as the simulated device keeps it) */
	double last_x_m;           /* the last measured position (the safe stop holds it) */
	int have_x;
	popc_force_sensor fsens;   /* re-quantizes a reading to admittance.force_resolution */
	int fs_passthrough;        /* the sensor's units are the scene's force counts */
	int fs_off;                /* the sensor's offset in the block read, -1: read on its own */

	/* the block read every tick: position (and status when close to it; and
	 * the sequence register, at echo_off, -1: not in the block) */
	popc_reg_table blk_table;
	int blk_reg, blk_n;
	int status_in_block;
	int echo_off;

	/* the block every command write covers: the command words at cmd_off and,
	 * with a sequence register, its value at seq_off (-1: none) */
	int cmd_first, cmd_n, cmd_off, seq_off;
	uint16_t seq;              /* the sequence value of the next new command */
	uint16_t seq_written;      /* the sequence value of the last command encoded */
	int seq_any;               /* a command was encoded: seq_written is this run's */
	uint16_t tid;              /* TCP: the transaction id of the last request sent */
	int64_t line_busy_ns;      /* RTU: when the line was last seen busy (a frame sent or received) */
	char op_why[POPC_ERROR_MSG_MAX]; /* why the last attempt failed */

	/* pacing */
	int64_t next_deadline_ns;
	int64_t last_sample_ns;
	int have_sample;

	/* supervisor state */
	int enabled;               /* the link was opened: stop() must zero and disable */
	int stopping;              /* inside stop(): after a signal, one attempt per write */
	int failures_in_row;
	int last_errno;
	double last_cmd_N;

	/* statistics */
	popc_histogram dt_hist, rtt_hist;
	long long exchanges, overruns, skipped_periods, failures, reconnects, clamps;
	long long gap_requests, gap_waits; /* RTU frame gap: requests sent after one, waits it took */
	int64_t gap_min_ns;        /* the shortest silence measured before a request, -1: none */
	int rt_fifo, rt_locked;
	char rt_note[256];
} mb_axis;

/* "popc: modbus: <what> <detail>" on the notes stream. */
static void note(mb_axis *a, const char *what, const char *detail)
{
	if (a->opt.notes)
		fprintf(a->opt.notes, "popc: modbus: %s %s\n", what, detail);
}

/* A signal asked the run to stop (the runner's flag, set by the handler). */
static int interrupted(const mb_axis *a)
{
	return a->opt.stop_flag && *a->opt.stop_flag;
}

/* ---- link ----------------------------------------------------------------- */

static void set_timeouts(mb_axis *a)
{
	uint32_t ms = (uint32_t)a->map.timeout_ms;
	modbus_set_response_timeout(a->ctx, ms / 1000, (ms % 1000) * 1000);
	/* between two bytes of one frame: the same bound (a pty or a USB adapter
	 * delivers a frame in pieces; a real line needs 1.5 characters) */
	modbus_set_byte_timeout(a->ctx, ms / 1000, (ms % 1000) * 1000);
}

/* The RTU line's mode, after the port is open (the ioctls need it): RS-485
 * (libmodbus' modbus_rtu_set_serial_mode, TIOCSRS485) and RTS control
 * (modbus_rtu_set_rts, which sets the line with TIOCMSET and ignores a
 * failure; so popc first asks TIOCMGET whether the port has modem lines at
 * all). A pseudo-terminal has neither: both fail with ENOTTY. A port that
 * cannot do what the map asks is refused (exit 2) before any frame is sent:
 * an RS-485 transceiver never enabled would put nothing on the bus. */
static int serial_line_setup(mb_axis *a, popc_error *err)
{
	const popc_register_map *m = &a->map;
	if (m->rs485 && modbus_rtu_set_serial_mode(a->ctx, MODBUS_RTU_RS485) != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: drive.rs485 = yes: %s cannot be put in RS-485 mode (TIOCSRS485: "
				      "%s%s); set rs485 = no for an RS-232 port or a USB adapter that "
				      "switches its transmitter itself",
				      m->path, a->uri.device, modbus_strerror(errno),
				      errno == ENOTTY ? ": not a serial port with RS-485 support, e.g. a "
							"pseudo-terminal" : "");
	if (m->rts) {
		int lines;
		if (ioctl(modbus_get_socket(a->ctx), TIOCMGET, &lines) != 0)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: drive.rts = %s: the RTS line of %s cannot be set (TIOCMGET: "
					      "%s%s); set rts = none",
					      m->path, m->rts == 1 ? "up" : "down", a->uri.device, strerror(errno),
					      errno == ENOTTY || errno == EINVAL
						      ? ": a port without modem lines, e.g. a pseudo-terminal"
						      : "");
		int mode = m->rts == 1 ? MODBUS_RTU_RTS_UP : MODBUS_RTU_RTS_DOWN;
		if (modbus_rtu_set_rts(a->ctx, mode) != 0 ||
		    (m->rts_delay_us >= 0 && modbus_rtu_set_rts_delay(a->ctx, m->rts_delay_us) != 0))
			return popc_error_set(err, POPC_ERR_INVALID, "%s: drive.rts: %s: %s", m->path,
					      a->uri.device, modbus_strerror(errno));
	}
	return 0;
}

static int link_open(mb_axis *a, popc_error *err)
{
	if (!a->ctx) {
		if (a->uri.rtu)
			a->ctx = modbus_new_rtu(a->uri.device, a->uri.baud, a->uri.parity, a->uri.data_bits,
						a->uri.stop_bits);
		else
			a->ctx = modbus_new_tcp_pi(a->uri.host, a->uri.port);
		if (!a->ctx)
			return popc_error_set(err, POPC_ERR_COMM, "%s: cannot create the Modbus context: %s",
					      a->uri_text, modbus_strerror(errno));
		/* LINK recovery can retry forever and doubles every timeout (docs/MODBUS.md) */
		modbus_set_error_recovery(a->ctx, MODBUS_ERROR_RECOVERY_NONE);
		modbus_set_slave(a->ctx, a->map.slave);
		set_timeouts(a);
	}
	if (a->connected)
		return 0;
	if (modbus_connect(a->ctx) != 0)
		return popc_error_set(err, POPC_ERR_COMM, "%s: cannot connect: %s", a->uri_text,
				      modbus_strerror(errno));
	if (a->uri.rtu) {
		int st = serial_line_setup(a, err);
		if (st) {
			modbus_close(a->ctx);
			return st;
		}
		/* what was on the line before is unknown: the first request keeps
		 * the gap too, counted from the port's opening */
		a->line_busy_ns = popc_now_ns();
	}
	a->connected = 1;
	return 0;
}

static void link_close(mb_axis *a)
{
	if (a->ctx && a->connected)
		modbus_close(a->ctx);
	a->connected = 0;
}

/* RTU has no transaction id: after a failure, discard whatever arrives until
 * the line has been quiet for one response timeout (bounded: 4 timeouts), so
 * that a late reply is not taken for the answer to the next request. */
static void rtu_drain(mb_axis *a)
{
	int fd = modbus_get_socket(a->ctx);
	modbus_flush(a->ctx);
	if (fd < 0)
		return;
	for (int round = 0; round < 4; round++) {
		fd_set rd;
		FD_ZERO(&rd);
		FD_SET(fd, &rd);
		struct timeval tv = {a->map.timeout_ms / 1000, (a->map.timeout_ms % 1000) * 1000};
		int r = select(fd + 1, &rd, NULL, NULL, &tv);
		if (r == 0)
			return;
		if (r < 0 && errno != EINTR)
			return;
		modbus_flush(a->ctx);
		a->line_busy_ns = popc_now_ns();
	}
}

/* After a failed transaction: make the link usable for the next attempt. */
static void recover(mb_axis *a, int e)
{
	if (e >= EMBXILFUN && e <= EMBXGTAR)
		return; /* an exception reply: the link and the framing are fine */
	if (a->uri.rtu) {
		rtu_drain(a);
		return;
	}
	/* TCP: a timeout may leave a late reply in the stream, and a reset or a
	 * broken socket is gone for good; a new connection is clean either way */
	link_close(a);
	popc_error ignored;
	if (link_open(a, &ignored) == 0) {
		a->reconnects++;
		note(a, "reconnected to", a->uri_text);
	}
}

/* Exceptions that mean the map does not fit the drive: retrying cannot help. */
static int is_config_exception(int e)
{
	return e == EMBXILFUN || e == EMBXILADD || e == EMBXILVAL;
}

enum { OP_READ_BLOCK, OP_READ_STATUS, OP_WRITE_CMD, OP_WRITE_AND_READ, OP_WRITE_ENABLE,
       OP_READ_SENSOR, OP_READ_CMD };

typedef struct mb_op {
	int kind;
	const uint16_t *words;  /* command words, or the enable word */
	uint16_t *dest;         /* read destination */
} mb_op;

/* ---- frames ---------------------------------------------------------------
 *
 * popc builds every request PDU itself, sends it (RTU: through
 * modbus_send_raw_request, which adds the slave address and the CRC; TCP:
 * with its own MBAP header, so that the transaction id is popc's), takes the
 * reply with modbus_receive_confirmation (framing, RTU CRC) and checks the
 * reply against its request itself: libmodbus 3.1.6 accepts a TCP reply
 * with a wrong unit id, a wrong MBAP length field or a protocol id with one
 * non-zero byte (tests/modbus/frames.sh shows each), and nothing in an RTU
 * reply tells which request it answers. Checked: TCP transaction id,
 * protocol id 0, length field, unit id; RTU slave address; the function
 * code (or its exception), a read's byte count, a write's echoed address,
 * quantity or value; and, when the block read covers the sequence
 * register, that it holds the sequence value of the last command written,
 * which ties a position to its own request (a stale or duplicated reply
 * carries an older value). A reply that fails a check is a failed
 * transaction like a timeout. */

#define MBAP_LEN 7 /* transaction id, protocol id, length, unit id */

static int put16(uint8_t *p, int v)
{
	p[0] = (uint8_t)(v >> 8);
	p[1] = (uint8_t)v;
	return 2;
}

static int get16(const uint8_t *p)
{
	return p[0] << 8 | p[1];
}

/* The command registers' write part of an FC16 or FC23 request: first
 * address, quantity, byte count, the words (Modbus Application Protocol
 * V1.1b3, 6.12 and 6.17); returns its length. */
static int put_command_block(const mb_axis *a, const mb_op *op, uint8_t *p)
{
	int n = put16(p, a->cmd_first);
	n += put16(p + n, a->cmd_n);
	p[n++] = (uint8_t)(2 * a->cmd_n);
	for (int i = 0; i < a->cmd_n; i++)
		n += put16(p + n, op->words[i]);
	return n;
}

/* The request PDU of op (function code first); returns its length. */
static int build_pdu(const mb_axis *a, const mb_op *op, uint8_t *pdu)
{
	const popc_register_map *m = &a->map;
	int n = 0;
	switch (op->kind) {
	case OP_READ_BLOCK:
	case OP_READ_STATUS: {
		int block = op->kind == OP_READ_BLOCK;
		popc_reg_table t = block ? a->blk_table : m->status.table;
		pdu[n++] = t == POPC_TABLE_HOLDING ? MODBUS_FC_READ_HOLDING_REGISTERS
						   : MODBUS_FC_READ_INPUT_REGISTERS;
		n += put16(pdu + n, block ? a->blk_reg : m->status.reg);
		n += put16(pdu + n, block ? a->blk_n : 1);
		break;
	}
	case OP_READ_SENSOR:
		pdu[n++] = m->sensor.table == POPC_TABLE_HOLDING ? MODBUS_FC_READ_HOLDING_REGISTERS
								  : MODBUS_FC_READ_INPUT_REGISTERS;
		n += put16(pdu + n, m->sensor.reg);
		n += put16(pdu + n, popc_reg_type_words(m->sensor.type));
		break;
	case OP_READ_CMD: /* the position set point, read back at start (mb_start) */
		pdu[n++] = MODBUS_FC_READ_HOLDING_REGISTERS;
		n += put16(pdu + n, m->cmd.reg);
		n += put16(pdu + n, popc_reg_type_words(m->cmd.type));
		break;
	case OP_WRITE_CMD:
		if (a->cmd_n == 1) {
			pdu[n++] = MODBUS_FC_WRITE_SINGLE_REGISTER;
			n += put16(pdu + n, a->cmd_first);
			n += put16(pdu + n, op->words[0]);
			break;
		}
		pdu[n++] = MODBUS_FC_WRITE_MULTIPLE_REGISTERS;
		n += put_command_block(a, op, pdu + n);
		break;
	case OP_WRITE_AND_READ:
		pdu[n++] = MODBUS_FC_WRITE_AND_READ_REGISTERS;
		n += put16(pdu + n, a->blk_reg);
		n += put16(pdu + n, a->blk_n);
		n += put_command_block(a, op, pdu + n);
		break;
	case OP_WRITE_ENABLE:
		if (m->enable.table == POPC_TABLE_COIL) {
			pdu[n++] = MODBUS_FC_WRITE_SINGLE_COIL;
			n += put16(pdu + n, m->enable.reg);
			n += put16(pdu + n, op->words[0] ? 0xFF00 : 0x0000);
		} else {
			pdu[n++] = MODBUS_FC_WRITE_SINGLE_REGISTER;
			n += put16(pdu + n, m->enable.reg);
			n += put16(pdu + n, op->words[0]);
		}
		break;
	}
	return n;
}

/* A failed attempt: errno e, and the reason in a->op_why. */
static int attempt_failed(mb_axis *a, int e, const char *fmt, ...)
#if defined(__GNUC__)
	__attribute__((format(printf, 3, 4)))
#endif
	;
static int attempt_failed(mb_axis *a, int e, const char *fmt, ...)
{
	if (fmt) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(a->op_why, sizeof a->op_why, fmt, ap);
		va_end(ap);
	} else {
		snprintf(a->op_why, sizeof a->op_why, "%s", modbus_strerror(e));
	}
	errno = e;
	return -1;
}

/* Sends the request PDU: RTU through libmodbus, TCP with popc's MBAP header
 * and the next transaction id. */
static int send_request(mb_axis *a, const uint8_t *pdu, int n)
{
	uint8_t adu[MBAP_LEN + MODBUS_MAX_PDU_LENGTH];
	if (a->uri.rtu) {
		adu[0] = (uint8_t)a->map.slave;
		memcpy(adu + 1, pdu, (size_t)n);
		return modbus_send_raw_request(a->ctx, adu, n + 1) < 0 ? attempt_failed(a, errno, NULL) : 0;
	}
	a->tid++;
	put16(adu, a->tid);
	put16(adu + 2, 0);          /* protocol id: Modbus */
	put16(adu + 4, n + 1);      /* the unit id and the PDU follow */
	adu[6] = (uint8_t)a->map.slave;
	memcpy(adu + MBAP_LEN, pdu, (size_t)n);
	int fd = modbus_get_socket(a->ctx);
	for (int off = 0; off < MBAP_LEN + n;) {
		ssize_t w = send(fd, adu + off, (size_t)(MBAP_LEN + n - off), MSG_NOSIGNAL);
		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0)
			return attempt_failed(a, w < 0 ? errno : ECONNRESET, NULL);
		off += (int)w;
	}
	return 0;
}

/* Checks the reply rsp (len bytes as received) against the request PDU and
 * copies a read's registers to op->dest. */
static int check_reply(mb_axis *a, const mb_op *op, const uint8_t *req, const uint8_t *rsp, int len)
{
	int hl = a->uri.rtu ? 1 : MBAP_LEN, tail = a->uri.rtu ? 2 : 0; /* RTU: the CRC */
	if (len <= 0) /* RTU: libmodbus returns 0 for a frame addressed to another slave */
		return attempt_failed(a, EMBBADSLAVE, "reply from slave %d, not %d",
				      len == 0 ? rsp[0] : -1, a->map.slave);
	if (len < hl + 2 + tail)
		return attempt_failed(a, EMBBADDATA, "reply of %d bytes is too short", len);
	if (a->uri.rtu) {
		if (rsp[0] != a->map.slave)
			return attempt_failed(a, EMBBADSLAVE, "reply from slave %d, not %d", rsp[0],
					      a->map.slave);
	} else {
		if (get16(rsp) != a->tid)
			return attempt_failed(a, EMBBADDATA,
					      "reply with transaction id %d to the request with %d "
					      "(a reply to another request)",
					      get16(rsp), a->tid);
		if (get16(rsp + 2) != 0)
			return attempt_failed(a, EMBBADDATA, "reply with protocol id %d, not 0 (Modbus)",
					      get16(rsp + 2));
		if (get16(rsp + 4) != len - 6)
			return attempt_failed(a, EMBBADDATA,
					      "reply's MBAP length field says %d bytes, %d followed",
					      get16(rsp + 4), len - 6);
		if (rsp[6] != a->map.slave)
			return attempt_failed(a, EMBBADSLAVE, "reply from unit id %d, not %d", rsp[6],
					      a->map.slave);
	}
	const uint8_t *p = rsp + hl;
	int n = len - hl - tail, fc = req[0];
	if (p[0] == (fc | 0x80)) {
		int code = p[1];
		if (n != 2)
			return attempt_failed(a, EMBBADEXC, NULL);
		return attempt_failed(a, code > 0 && code < MODBUS_EXCEPTION_MAX ? MODBUS_ENOBASE + code
										  : EMBBADEXC,
				      NULL);
	}
	if (p[0] != fc)
		return attempt_failed(a, EMBBADDATA,
				      "reply with function code 0x%02x to a request with 0x%02x", p[0], fc);
	switch (fc) {
	case MODBUS_FC_READ_HOLDING_REGISTERS:
	case MODBUS_FC_READ_INPUT_REGISTERS:
	case MODBUS_FC_WRITE_AND_READ_REGISTERS: {
		int want = 2 * get16(req + 3);
		if (p[1] != want || n != 2 + want)
			return attempt_failed(a, EMBBADDATA,
					      "reply with %d data bytes (byte count %d) to a read of %d",
					      n - 2, p[1], want);
		for (int i = 0; i < want / 2; i++)
			op->dest[i] = (uint16_t)get16(p + 2 + 2 * i);
		/* (a servo-mode start reads the block before its first
		 * command: the register then holds a previous session's value) */
		if ((op->kind == OP_READ_BLOCK || op->kind == OP_WRITE_AND_READ) && a->echo_off >= 0 &&
		    a->seq_any &&
		    op->dest[a->echo_off] != a->seq_written)
			return attempt_failed(a, EMBBADDATA,
					      "reply's sequence register %d holds %u, the last command "
					      "written carried %u (a reply to another request, or a drive "
					      "that does not keep the value written)",
					      a->map.cmd.seq_reg, op->dest[a->echo_off], a->seq_written);
		return 0;
	}
	case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
		/* the echo: starting address and quantity */
		if (n != 5 || memcmp(p + 1, req + 1, 4) != 0)
			return attempt_failed(a, EMBBADDATA,
					      "reply does not echo the write's address and quantity");
		return 0;
	default: /* FC05, FC06: the echo is the request */
		if (n != 5 || memcmp(p + 1, req + 1, 4) != 0)
			return attempt_failed(a, EMBBADDATA,
					      "reply does not echo the write's address and value");
		return 0;
	}
}

/* RTU: keeps the map's rtu_frame_gap_ms of silence between the last frame
 * on the line (a reply received, a request sent, a drain) and the next
 * request (the first one: from the port's opening), on top of the 3.5
 * characters libmodbus keeps. Measured on the
 * monotonic clock from the moment popc last saw the line busy, which is at
 * or after the frame's end: the silence on the wire is at least the gap. */
static void keep_frame_gap(mb_axis *a)
{
	int64_t gap_ns = (int64_t)a->map.rtu_frame_gap_ms * 1000000;
	if (!a->uri.rtu || gap_ns <= 0)
		return;
	int64_t until = a->line_busy_ns + gap_ns, now = popc_now_ns();
	if (now < until) {
		a->gap_waits++;
		struct timespec ts = {(time_t)(until / 1000000000), (long)(until % 1000000000)};
		/* kept after a signal too (at most 1 s): a drive may ignore a frame
		 * that comes early, and the safe stop's zero force must arrive */
		while (clock_nanosleep(POPC_CLOCK_ID, TIMER_ABSTIME, &ts, NULL) == EINTR)
			;
		now = popc_now_ns();
	}
	int64_t silence = now - a->line_busy_ns;
	if (a->gap_min_ns < 0 || silence < a->gap_min_ns)
		a->gap_min_ns = silence;
	a->gap_requests++;
}

/* One attempt: flush whatever the line or the stream holds (a late or a
 * duplicated reply to an earlier request), send, receive, check. */
static int do_op(mb_axis *a, const mb_op *op)
{
	uint8_t req[MODBUS_MAX_PDU_LENGTH], rsp[MODBUS_MAX_ADU_LENGTH];
	int n = build_pdu(a, op, req);
	keep_frame_gap(a);
	modbus_flush(a->ctx); /* after the gap: a stray reply that came during it goes too */
	int sent = send_request(a, req, n);
	a->line_busy_ns = popc_now_ns();
	if (sent != 0)
		return -1;
	int len = modbus_receive_confirmation(a->ctx, rsp);
	int e = errno;
	a->line_busy_ns = popc_now_ns(); /* the reply's end, or the timeout's */
	if (len < 0)
		return attempt_failed(a, e, NULL);
	return check_reply(a, op, req, rsp, len);
}

static const char *op_name(int kind)
{
	switch (kind) {
	case OP_READ_BLOCK: return "position read";
	case OP_READ_STATUS: return "status read";
	case OP_WRITE_CMD: return "command write";
	case OP_WRITE_AND_READ: return "command write + position read (FC23)";
	case OP_READ_SENSOR: return "force sensor read";
	case OP_READ_CMD: return "position command read";
	default: return "enable write";
	}
}

/* One transaction, retried until it succeeds or max_failures transactions in
 * a row have failed. A failed read is never replaced by an older value.
 *
 * Signals do not interrupt libmodbus (it resumes its select() after EINTR),
 * so the stop flag is looked at after every failed attempt: a signal ends
 * the retries at once (POPC_ERR_INTERRUPTED) instead of after up to
 * max_failures timeouts, and inside stop() a signal leaves one attempt per
 * write. The link is repaired after every failure, the last one included, so
 * that whatever comes next (stop()'s zero force) starts on a clean link. */
static int transact(mb_axis *a, const mb_op *op, popc_error *err)
{
	for (;;) {
		popc_error link_err;
		int st = a->connected ? 0 : link_open(a, &link_err);
		if (!st && do_op(a, op) == 0) {
			a->failures_in_row = 0;
			return 0;
		}
		int e = st ? ECONNREFUSED : errno;
		a->last_errno = e;
		a->failures++;
		a->failures_in_row++;
		if (!st && is_config_exception(e))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: the drive at %s rejected the %s: %s (check the register map%s)",
					      a->map.path, a->uri_text, op_name(op->kind), modbus_strerror(e),
					      op->kind == OP_WRITE_AND_READ ? "; a drive without FC23 needs fc23 = no"
									    : "");
		const char *why = st ? link_err.msg : a->op_why;
		char last[POPC_ERROR_MSG_MAX];
		snprintf(last, sizeof last, "%s", why); /* recover() may reuse errno's text */
		if (a->connected)
			recover(a, e);
		if (a->failures_in_row >= a->map.max_failures)
			return popc_error_set(err, POPC_ERR_COMM,
					      "%s: %d failed transactions in a row (last: %s: %s)", a->uri_text,
					      a->failures_in_row, op_name(op->kind), last);
		if (interrupted(a) && a->stopping)
			return popc_error_set(err, POPC_ERR_COMM,
					      "%s: %s failed (%s); not retried after a signal", a->uri_text,
					      op_name(op->kind), last);
		if (interrupted(a))
			return popc_error_set(err, POPC_ERR_INTERRUPTED,
					      "interrupted by a signal while retrying the %s (%s: %d failed "
					      "attempt%s, last: %s)",
					      op_name(op->kind), a->uri_text, a->failures_in_row,
					      a->failures_in_row == 1 ? "" : "s", last);
	}
}

/* ---- conversions and supervision ------------------------------------------ */

static int check_status(mb_axis *a, uint16_t status, int want_ready, popc_error *err)
{
	const popc_register_map *m = &a->map;
	if (status & m->status.fault_mask)
		return popc_error_set(err, POPC_ERR_SAFETY,
				      "drive fault: status 0x%04x has fault bits 0x%04x (fault_mask 0x%04x)",
				      status, status & m->status.fault_mask, m->status.fault_mask);
	if (want_ready && (status & m->status.ready_mask) != m->status.ready_mask)
		return popc_error_set(err, POPC_ERR_SAFETY,
				      "drive not ready: status 0x%04x lacks ready bits 0x%04x", status,
				      m->status.ready_mask & (uint16_t)~status);
	return 0;
}

/* The position in the block's words -> count, with the soft limits. */
static int decode_position(mb_axis *a, const uint16_t *blk, long long *count_out, popc_error *err)
{
	const popc_register_map *m = &a->map;
	double raw = popc_reg_decode(blk + (m->pos.reg - a->blk_reg), m->pos.type, m->pos.order);
	if (m->pos.reversed)
		raw = -raw; /* exact: an int32's -2^31 becomes 2^31, still exact in a double */
	long long count;
	if (a->passthrough && m->pos.type != POPC_REG_FLOAT32 && m->pos.type != POPC_REG_FLOAT64) {
		count = (long long)raw;
	} else {
		int ok;
		count = popc_encoder_count(raw / m->pos.counts_per_m, a->delta_m, &ok);
		if (!ok || !isfinite(raw))
			return popc_error_set(err, POPC_ERR_SAFETY, "position value %g is not a position",
					      raw);
	}
	double x_m = popc_encoder_position(count, a->delta_m);
	if (x_m < m->pos.soft_min_m || x_m > m->pos.soft_max_m)
		return popc_error_set(err, POPC_ERR_SAFETY,
				      "position %g m is outside the soft limits [%g, %g] m (%s)", x_m,
				      m->pos.soft_min_m, m->pos.soft_max_m, m->path);
	*count_out = count;
	return 0;
}

/* The force sensor's words -> the count of admittance.force_resolution (the
 * scene's sensor: the drive's own counts pass through unchanged when its
 * unit is the resolution, else the reading is re-quantized, as positions
 * are). A value that is not a finite force is a safety stop: no NaN reaches
 * the controller or the log. */
static int decode_force(mb_axis *a, const uint16_t *words, long long *count_out, popc_error *err)
{
	const popc_register_map *m = &a->map;
	double raw = popc_reg_decode(words, m->sensor.type, m->sensor.order);
	if (m->sensor.reversed)
		raw = -raw;
	if (a->fs_passthrough && m->sensor.type != POPC_REG_FLOAT32 && m->sensor.type != POPC_REG_FLOAT64) {
		*count_out = (long long)raw;
		return 0;
	}
	double f = raw * m->sensor.newton_per_unit;
	if (!isfinite(f))
		return popc_error_set(err, POPC_ERR_SAFETY,
				      "force sensor value %g is not a force (%s, [force_sensor] register %d)",
				      raw, m->path, m->sensor.reg);
	*count_out = popc_force_sensor_read(&a->fsens, f);
	return 0;
}

/* Block words (and the sensor's, when read on their own) -> sample, with
 * the safety checks. */
static int decode_sample(mb_axis *a, const uint16_t *blk, uint16_t status, const uint16_t *sens,
			 popc_axis_sample *out, popc_error *err)
{
	int st = check_status(a, status, 1, err);
	long long count = 0;
	if (!st)
		st = decode_position(a, blk, &count, err);
	if (st)
		return st;
	out->count = count;
	out->x_true_m = (double)NAN;
	a->last_x_m = popc_encoder_position(count, a->delta_m);
	a->have_x = 1;
	if (a->servo) {
		if ((st = decode_force(a, a->fs_off >= 0 ? blk + a->fs_off : sens, &out->force_count, err)))
			return st;
		out->x_cmd_m = a->x_cmd_m;
	}
	return 0;
}

/* What the block read did not cover: the status and the force sensor,
 * each in a read of its own when it lies outside the block. */
static int read_rest(mb_axis *a, const uint16_t *blk, uint16_t *status, uint16_t *sens,
		     popc_error *err)
{
	int st;
	if (a->status_in_block) {
		*status = blk[a->map.status.reg - a->blk_reg];
	} else {
		mb_op sop = {.kind = OP_READ_STATUS, .dest = status};
		if ((st = transact(a, &sop, err)))
			return st;
	}
	if (a->servo && a->fs_off < 0) {
		mb_op fop = {.kind = OP_READ_SENSOR, .dest = sens};
		if ((st = transact(a, &fop, err)))
			return st;
	}
	return 0;
}

/* Reads position, status (and force); fills blk, *status and sens. */
static int read_state(mb_axis *a, uint16_t *blk, uint16_t *status, uint16_t *sens, popc_error *err)
{
	mb_op op = {.kind = OP_READ_BLOCK, .dest = blk};
	int st = transact(a, &op, err);
	if (st)
		return st;
	return read_rest(a, blk, status, sens, err);
}

/* A new command: the words of one command write (the block of
 * popc_register_map_command_block). The command register holds the force on
 * the device. The runner's f_c is the force into the virtual environment and
 * the device receives -f_c (README, "The plant"), so exchange() passes -f_c (an
 * exact negation: a lockstep server negates it back bit for bit) and
 * start/stop pass +0. With a sequence register, each new command carries the
 * next sequence value; a retry resends these same words, so the drive sees
 * the same value again and knows it for a retry. */
/* v within [lo, hi]; a clamp is counted for the summary. */
static double clamp_count(mb_axis *a, double v, double lo, double hi)
{
	if (v > hi) {
		a->clamps++;
		return hi;
	}
	if (v < lo) {
		a->clamps++;
		return lo;
	}
	return v;
}

/* A servo-mode drive's set point as a command value in popc's units: a
 * velocity (m/s) clamped to limit_m_per_s, or a position (m) clamped to the
 * soft limits; NaN never reaches the drive (zero velocity, or the position
 * last measured). Returns the value the register will carry. */
static double servo_value(mb_axis *a, double v)
{
	const popc_register_map *m = &a->map;
	if (m->cmd.mode == POPC_CMD_VELOCITY)
		return clamp_count(a, v == v ? v : 0.0, -m->cmd.limit_m_per_s, m->cmd.limit_m_per_s);
	return clamp_count(a, v == v ? v : a->last_x_m, m->pos.soft_min_m, m->pos.soft_max_m);
}

static void encode_command(mb_axis *a, double f_N, uint16_t *words)
{
	const popc_register_map *m = &a->map;
	if (a->seq_off >= 0) {
		a->seq_written = a->seq;
		a->seq_any = 1;
		words[a->seq_off] = a->seq++; /* uint16_t: wraps modulo 65536 */
	}
	double f = f_N, units;
	if (a->servo) {
		/* f_N is already servo_value's: a velocity or a position */
		a->last_cmd_N = f;
		units = m->cmd.mode == POPC_CMD_VELOCITY ? f / m->cmd.m_per_s_per_unit
							 : f * m->cmd.counts_per_m;
	} else {
		if (!(f == f))
			f = 0.0; /* NaN never reaches the drive */
		f = clamp_count(a, f, -m->cmd.limit_N, m->cmd.limit_N);
		a->last_cmd_N = f;
		/* reversed: an exact negation, which popc-servo-sim undoes bit
		 * for bit (the clamp is symmetric, so it holds either way) */
		units = f / m->cmd.newton_per_unit;
	}
	if (m->cmd.reversed)
		units = -units;
	/* a zero force goes out as +0.0: negating 0 (start and stop with a
	 * reversed command, exchange's -f_c of a zero f_c) gives -0.0, which a
	 * float register would carry as 8000 0000, and a drive's firmware
	 * should never have to know that -0.0 is zero */
	if (units == 0.0)
		units = 0.0;
	popc_reg_encode(units, m->cmd.type, m->cmd.order, words + a->cmd_off);
}

/* Sleeps until the next deadline on the absolute grid. A deadline already
 * passed is an overrun; grid points passed by a whole period are skipped
 * rather than run back to back. */
static void wait_deadline(mb_axis *a)
{
	if (!a->opt.pace)
		return;
	a->next_deadline_ns += a->period_ns;
	int64_t now = popc_now_ns();
	if (now > a->next_deadline_ns) {
		a->overruns++;
		while (a->next_deadline_ns + a->period_ns <= now) {
			a->next_deadline_ns += a->period_ns;
			a->skipped_periods++;
		}
		return;
	}
	struct timespec ts = {(time_t)(a->next_deadline_ns / 1000000000),
			      (long)(a->next_deadline_ns % 1000000000)};
	/* EINTR: a signal; the runner polls its flag after this tick, so the rest
	 * of the period is not slept when the flag is set */
	while (clock_nanosleep(POPC_CLOCK_ID, TIMER_ABSTIME, &ts, NULL) == EINTR && !interrupted(a))
		;
}

static void stamp(mb_axis *a, int64_t t_read_ns, int64_t rtt_ns, popc_axis_sample *out)
{
	out->dt_s = a->have_sample ? 1e-9 * (double)(t_read_ns - a->last_sample_ns) : 0.0;
	out->rtt_s = 1e-9 * (double)rtt_ns;
	if (a->have_sample)
		popc_histogram_add(&a->dt_hist, t_read_ns - a->last_sample_ns);
	popc_histogram_add(&a->rtt_hist, rtt_ns);
	a->last_sample_ns = t_read_ns;
	a->have_sample = 1;
}

/* ---- axis operations ------------------------------------------------------ */

static void realtime_on(mb_axis *a)
{
	if (!a->opt.realtime) {
		snprintf(a->rt_note, sizeof a->rt_note, "not requested (normal scheduling)");
		return;
	}
	char fifo[96], lock[96];
	if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
		a->rt_locked = 1;
		snprintf(lock, sizeof lock, "memory locked");
	} else {
		snprintf(lock, sizeof lock, "mlockall not permitted (%s)", strerror(errno));
	}
	struct sched_param sp = {.sched_priority = a->opt.rt_priority};
	if (sched_setscheduler(0, SCHED_FIFO, &sp) == 0) {
		a->rt_fifo = 1;
		snprintf(fifo, sizeof fifo, "SCHED_FIFO priority %d", a->opt.rt_priority);
	} else {
		snprintf(fifo, sizeof fifo, "SCHED_FIFO not permitted (%s): normal scheduling", strerror(errno));
	}
	snprintf(a->rt_note, sizeof a->rt_note, "%s, %s", fifo, lock);
	note(a, "real-time:", a->rt_note);
}

static void realtime_off(mb_axis *a)
{
	if (a->rt_fifo) {
		struct sched_param sp = {.sched_priority = 0};
		sched_setscheduler(0, SCHED_OTHER, &sp);
		a->rt_fifo = 0;
	}
	if (a->rt_locked) {
		munlockall();
		a->rt_locked = 0;
	}
}

/* The set point a servo-mode drive is enabled with, and the safe stop's:
 * zero velocity, or the position where the drive stands. In position mode
 * start() reads the position and the command register back (FC03): a drive
 * whose set point follows its actual position while disabled (CiA 402
 * drives do; popc-servo-sim does) gives its position to the last bit, and
 * the position command then continues from exactly there, as the simulated
 * device's does from its initial position. A read-back more than one
 * encoder count from the measured position (a drive that keeps an old set
 * point) is not used: the measured position is held instead, so that the
 * enable never moves the axis by more than a count. */
static int servo_hold(mb_axis *a, popc_error *err)
{
	const popc_register_map *m = &a->map;
	uint16_t blk[BLOCK_MAX], words[4];
	long long count;
	mb_op op = {.kind = OP_READ_BLOCK, .dest = blk};
	int st = transact(a, &op, err);
	if (!st)
		st = decode_position(a, blk, &count, err);
	if (st)
		return st;
	double x = popc_encoder_position(count, a->delta_m);
	a->last_x_m = x;
	a->have_x = 1;
	/* velocity mode: the drive has no position set point; popc's x_cmd (the
	 * log's) integrates the velocities from the measured position */
	a->x_cmd_m = x;
	if (m->cmd.mode == POPC_CMD_VELOCITY)
		return 0;
	mb_op rop = {.kind = OP_READ_CMD, .dest = words};
	if ((st = transact(a, &rop, err)))
		return st;
	double units = popc_reg_decode(words, m->cmd.type, m->cmd.order);
	double x_rb = (m->cmd.reversed ? -units : units) / m->cmd.counts_per_m;
	if (isfinite(x_rb) && fabs(x_rb - x) <= a->delta_m)
		a->x_cmd_m = x_rb;
	return 0;
}

static int mb_start(popc_axis *ax, popc_error *err)
{
	mb_axis *a = ax->priv;
	const popc_register_map *m = &a->map;
	int st = link_open(a, err);
	if (st)
		return st;
	a->enabled = 1; /* from here on, stop() writes zero force and the disable word */
	/* a servo-mode drive: where it stands, first (a faulted drive too: the
	 * safe stop holds that position) */
	if (a->servo && (st = servo_hold(a, err)))
		return st;
	/* no start while the drive reports a fault */
	uint16_t status;
	mb_op sop = {.kind = OP_READ_STATUS, .dest = &status};
	if ((st = transact(a, &sop, err)))
		return st;
	if ((st = check_status(a, status, 0, err))) {
		char msg[POPC_ERROR_MSG_MAX];
		snprintf(msg, sizeof msg, "%s", err ? err->msg : "");
		return popc_error_set(err, st, "%s; popc does not start a drive that reports a fault", msg);
	}
	uint16_t zero[POPC_MAP_CMD_BLOCK_MAX];
	encode_command(a, a->servo ? servo_value(a, a->x_cmd_m) : 0.0, zero);
	mb_op cop = {.kind = OP_WRITE_CMD, .words = zero};
	if ((st = transact(a, &cop, err)))
		return st;
	if (interrupted(a))
		return popc_error_set(err, POPC_ERR_INTERRUPTED, "interrupted by a signal before enabling");
	for (int i = 0; i < m->enable.n_on; i++) {
		mb_op eop = {.kind = OP_WRITE_ENABLE, .words = &m->enable.on[i]};
		if ((st = transact(a, &eop, err)))
			return st;
	}
	int64_t t_enable = popc_now_ns(), until = t_enable + (int64_t)m->enable_timeout_ms * 1000000;
	for (;;) {
		if ((st = transact(a, &sop, err)))
			return st;
		if (status & m->status.fault_mask)
			return check_status(a, status, 0, err);
		if ((status & m->status.ready_mask) == m->status.ready_mask)
			break;
		/* enable_timeout_ms may be up to a minute: a signal must not wait for it */
		if (interrupted(a))
			return popc_error_set(err, POPC_ERR_INTERRUPTED,
					      "interrupted by a signal while waiting for the ready bits "
					      "(status 0x%04x, ready_mask 0x%04x, %.0f ms after enable)",
					      status, m->status.ready_mask, 1e-6 * (double)(popc_now_ns() - t_enable));
		if (popc_now_ns() > until)
			return popc_error_set(err, POPC_ERR_SAFETY,
					      "drive not ready %d ms after enable: status 0x%04x, ready_mask 0x%04x",
					      m->enable_timeout_ms, status, m->status.ready_mask);
		/* poll every 2 ms, not back to back: a drive's bus is not ours alone */
		struct timespec pause = {0, 2000000};
		nanosleep(&pause, NULL);
	}
	realtime_on(a);
	return 0;
}

static int mb_sample(popc_axis *ax, popc_axis_sample *out, popc_error *err)
{
	mb_axis *a = ax->priv;
	uint16_t blk[BLOCK_MAX], status = 0, sens[4] = {0};
	int64_t t = popc_now_ns();
	a->next_deadline_ns = t; /* the grid starts at the first sample */
	int st = read_state(a, blk, &status, sens, err);
	if (st)
		return st;
	stamp(a, t, popc_now_ns() - t, out);
	return decode_sample(a, blk, status, sens, out, err);
}

/* exchange()'s command for the drive: a force mode's -f_c (the device
 * receives -f_c), or a servo's set point for the velocity command v_c held
 * over the period: v_c itself, or the position command at the period's end,
 * x_c(k+1) = x_c(k) + v_c T (the simulated device's own sum, to the bit;
 * the drive interpolates towards it, docs/MODBUS.md, "Command modes"). */
static void encode_exchange(mb_axis *a, double cmd, uint16_t *words)
{
	if (!a->servo) {
		encode_command(a, -cmd, words);
		return;
	}
	if (a->map.cmd.mode == POPC_CMD_VELOCITY) {
		double v = servo_value(a, cmd);
		a->x_cmd_m += v * a->period_s;
		encode_command(a, v, words);
		return;
	}
	a->x_cmd_m = servo_value(a, a->x_cmd_m + (cmd == cmd ? cmd : 0.0) * a->period_s);
	encode_command(a, a->x_cmd_m, words);
}

static int mb_exchange(popc_axis *ax, double f_c_N, popc_axis_sample *next, popc_error *err)
{
	mb_axis *a = ax->priv;
	uint16_t words[POPC_MAP_CMD_BLOCK_MAX], blk[BLOCK_MAX], status = 0, sens[4] = {0};
	encode_exchange(a, f_c_N, words);
	int st;
	int64_t rtt = 0, t;
	a->exchanges++;
	if (a->map.fc23) {
		wait_deadline(a);
		t = popc_now_ns();
		mb_op op = {.kind = OP_WRITE_AND_READ, .words = words, .dest = blk};
		if ((st = transact(a, &op, err)) || (st = read_rest(a, blk, &status, sens, err)))
			return st;
		rtt = popc_now_ns() - t;
	} else {
		int64_t tw = popc_now_ns();
		mb_op op = {.kind = OP_WRITE_CMD, .words = words};
		if ((st = transact(a, &op, err)))
			return st;
		rtt = popc_now_ns() - tw;
		wait_deadline(a);
		t = popc_now_ns();
		if ((st = read_state(a, blk, &status, sens, err)))
			return st;
		rtt += popc_now_ns() - t;
	}
	stamp(a, t, rtt, next);
	return decode_sample(a, blk, status, sens, next, err);
}

/* Zero force (a servo-mode drive: zero velocity, or the position last
 * measured, held), then disable: each attempted even when the other failed; after
 * a signal (before or during stop) one attempt each, not max_failures. A
 * safe stop that is not confirmed is said on the notes stream as well: the
 * runner keeps its own reason for the exit code and the log's stop line. */
static int mb_stop(popc_axis *ax, popc_error *err)
{
	mb_axis *a = ax->priv;
	const popc_register_map *m = &a->map;
	realtime_off(a);
	if (!a->enabled)
		return 0;
	a->stopping = 1;
	a->failures_in_row = 0;
	uint16_t zero[POPC_MAP_CMD_BLOCK_MAX];
	/* position mode: hold where the drive was last measured. Before any
	 * position was read (the link failed at once) popc has none to hold,
	 * and any other set point could move the axis: the disable word only. */
	int hold = !(m->cmd.mode == POPC_CMD_POSITION && !a->have_x);
	if (hold)
		encode_command(a,
			       !a->servo ? 0.0
			       : m->cmd.mode == POPC_CMD_VELOCITY ? servo_value(a, 0.0)
								  : servo_value(a, a->last_x_m),
			       zero);
	mb_op cop = {.kind = OP_WRITE_CMD, .words = zero};
	popc_error e1, e2;
	int st1 = hold ? transact(a, &cop, &e1) : 0;
	a->failures_in_row = 0;
	mb_op eop = {.kind = OP_WRITE_ENABLE, .words = &m->enable.off};
	int st2 = transact(a, &eop, &e2);
	a->enabled = 0;
	a->stopping = 0;
	if (st1 || st2) {
		char msg[2 * POPC_ERROR_MSG_MAX + 64];
		const char *what = !a->servo ? "zero force"
				   : m->cmd.mode == POPC_CMD_VELOCITY ? "zero velocity" : "position hold";
		snprintf(msg, sizeof msg, "%s%s%s%s%s%s", st1 ? what : "", st1 ? " not confirmed: " : "",
			 st1 ? e1.msg : "", st1 && st2 ? "; " : "", st2 ? "disable not confirmed: " : "",
			 st2 ? e2.msg : "");
		note(a, "safe stop incomplete:", msg);
		return popc_error_set(err, POPC_ERR_COMM, "%s", msg); /* the runner names it */
	}
	return 0;
}

static void mb_report(popc_axis *ax, FILE *human, char *csv_names, char *csv_values, size_t cap)
{
	mb_axis *a = ax->priv;
	const popc_histogram *d = &a->dt_hist, *r = &a->rtt_hist;
	double T = 1e-9 * (double)a->period_ns;
	if (human) {
		char seq[64] = "";
		if (a->map.cmd.seq_reg >= 0)
			snprintf(seq, sizeof seq, ", command sequence in register %d", a->map.cmd.seq_reg);
		fprintf(human, "  modbus: %s, map %s (%s), %s%s\n", a->uri_text, a->map.path, a->map.name,
			a->map.fc23 ? "FC23 write+read" : "FC16 write, FC03/04 read", seq);
		fprintf(human,
			"  period dt: target %.6g ms, mean %.6g ms, p50 %.6g ms, p99 %.6g ms, p99.9 %.6g ms, "
			"max %.6g ms; overruns %lld (skipped periods %lld)%s\n",
			1e3 * T, 1e3 * popc_histogram_mean_s(d), 1e3 * popc_histogram_quantile_s(d, 0.5),
			1e3 * popc_histogram_quantile_s(d, 0.99), 1e3 * popc_histogram_quantile_s(d, 0.999),
			1e3 * popc_histogram_max_s(d), a->overruns, a->skipped_periods,
			a->opt.pace ? "" : " (free-run: no deadlines)");
		fprintf(human,
			"  latency rtt: mean %.6g ms, p50 %.6g ms, p99 %.6g ms, p99.9 %.6g ms, max %.6g ms "
			"over %llu samples\n",
			1e3 * popc_histogram_mean_s(r), 1e3 * popc_histogram_quantile_s(r, 0.5),
			1e3 * popc_histogram_quantile_s(r, 0.99), 1e3 * popc_histogram_quantile_s(r, 0.999),
			1e3 * popc_histogram_max_s(r), (unsigned long long)r->n);
		char clamp[96];
		if (a->map.cmd.mode == POPC_CMD_FORCE)
			snprintf(clamp, sizeof clamp, "force clamped %lld times at %g N", a->clamps,
				 a->map.cmd.limit_N);
		else if (a->map.cmd.mode == POPC_CMD_VELOCITY)
			snprintf(clamp, sizeof clamp, "velocity clamped %lld times at %g m/s", a->clamps,
				 a->map.cmd.limit_m_per_s);
		else
			snprintf(clamp, sizeof clamp, "position command clamped %lld times to the soft limits",
				 a->clamps);
		fprintf(human, "  link: %lld failed transactions, %lld reconnects; %s; real-time: %s\n",
			a->failures, a->reconnects, clamp, a->rt_note[0] ? a->rt_note : "not started");
		if (a->uri.rtu && a->map.rtu_frame_gap_ms > 0)
			fprintf(human,
				"  rtu frame gap: %d ms kept before %lld requests (%lld waited for it); "
				"shortest silence before a request %.6g ms\n",
				a->map.rtu_frame_gap_ms, a->gap_requests, a->gap_waits,
				a->gap_min_ns < 0 ? 0.0 : 1e-6 * (double)a->gap_min_ns);
		if (a->map.pos.reversed || a->map.cmd.reversed)
			fprintf(human, "  direction: position %s, command %s\n",
				a->map.pos.reversed ? "reversed" : "normal",
				a->map.cmd.reversed ? "reversed" : "normal");
	}
	if (csv_names && csv_values && cap) {
		double v[10] = {popc_histogram_quantile_s(d, 0.5), popc_histogram_quantile_s(d, 0.99),
				popc_histogram_quantile_s(d, 0.999), popc_histogram_max_s(d),
				popc_histogram_quantile_s(r, 0.5), popc_histogram_quantile_s(r, 0.99),
				popc_histogram_quantile_s(r, 0.999), popc_histogram_max_s(r),
				(double)a->overruns, (double)a->failures};
		static const char *const names[10] = {"dt_p50_s", "dt_p99_s", "dt_p999_s", "dt_max_s",
						     "rtt_p50_s", "rtt_p99_s", "rtt_p999_s", "rtt_max_s",
						     "overruns", "failed_transactions"};
		for (int i = 0; i < 10; i++) {
			size_t ln = strlen(csv_names), lv = strlen(csv_values);
			snprintf(csv_names + ln, cap - ln, ",%s", names[i]);
			snprintf(csv_values + lv, cap - lv, ",%.9g", v[i]);
		}
	}
}

static void mb_destroy(popc_axis *ax)
{
	mb_axis *a = ax->priv;
	realtime_off(a);
	if (a->ctx) {
		link_close(a);
		modbus_free(a->ctx);
	}
	free(a);
	free(ax);
}

static const popc_axis_ops modbus_ops = {
	.name = "modbus",
	.log_columns = POPC_LOG_COL_TIMING,
	.start = mb_start,
	.sample = mb_sample,
	.exchange = mb_exchange,
	.stop = mb_stop,
	.destroy = mb_destroy,
	.integrator_error_m = NULL, /* a drive integrates no model */
	.report = mb_report,
	.set_shadow = NULL,
};

/* The same axis driving an admittance-type device (command.mode = position
 * or velocity): exchange() takes the velocity command v_c and a sample
 * carries the force sensor's count and the position command. */
static const popc_axis_ops modbus_admittance_ops = {
	.name = "modbus",
	.log_columns = POPC_LOG_COL_TIMING | POPC_LOG_COL_ADMITTANCE,
	.start = mb_start,
	.sample = mb_sample,
	.exchange = mb_exchange,
	.stop = mb_stop,
	.destroy = mb_destroy,
	.integrator_error_m = NULL,
	.report = mb_report,
	.set_shadow = NULL,
};

void popc_modbus_options_defaults(popc_modbus_options *o)
{
	o->pace = 1;
	o->realtime = 0;
	o->rt_priority = 50;
	o->notes = NULL;
	o->stop_flag = NULL;
}

int popc_modbus_axis_create(popc_axis **out, const popc_scene *s, const popc_modbus_options *o,
			    popc_error *err)
{
	*out = NULL;
	if (!s->axis_map[0] || !s->axis_connect[0])
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: the modbus axis needs axis.map and axis.connect (--map, --connect)",
				      s->source[0] ? s->source : "scene");
	popc_axis *ax = calloc(1, sizeof *ax);
	mb_axis *a = calloc(1, sizeof *a);
	if (!ax || !a) {
		free(ax);
		free(a);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	if (o)
		a->opt = *o;
	else
		popc_modbus_options_defaults(&a->opt);
	if (a->opt.rt_priority < 1 || a->opt.rt_priority > 99)
		a->opt.rt_priority = 50;
	int st = popc_register_map_load(&a->map, s->axis_map, err);
	if (!st)
		st = popc_register_map_fits_scene(&a->map, s, err);
	if (!st)
		st = popc_modbus_uri_parse(s->axis_connect, &a->uri, err);
	/* port 0 is a server's "any free port": a drive is not found there */
	if (!st && !a->uri.rtu && strcmp(a->uri.port, "0") == 0)
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "connect URI '%s': port 0 is for a server (any free port); give the "
				    "drive's port, 1-65535",
				    s->axis_connect);
	if (st) {
		free(a);
		free(ax);
		return st;
	}
	popc_modbus_uri_format(&a->uri, a->uri_text, sizeof a->uri_text);
	if (!a->uri.rtu && strcmp(a->uri.port, "0") == 0) {
		free(a);
		free(ax);
		return popc_error_set(err, POPC_ERR_INVALID, "axis.connect = %s: port 0 is not a server port",
				      s->axis_connect);
	}
	a->delta_m = s->enc_resolution_m;
	a->passthrough = popc_register_map_counts_are_scene_counts(&a->map, a->delta_m);
	if (!a->passthrough && a->opt.notes)
		fprintf(a->opt.notes,
			"popc: modbus: the drive's resolution 1/counts_per_m = %g m is not encoder.resolution = "
			"%g m: positions are re-quantized to encoder.resolution (set it to %g to see the "
			"drive's own counts)\n",
			1.0 / a->map.pos.counts_per_m, a->delta_m, 1.0 / a->map.pos.counts_per_m);
	a->period_ns = (int64_t)llround(1e9 * popc_scene_period_s(s));
	if (a->period_ns < 1)
		a->period_ns = 1;
	a->period_s = popc_scene_period_s(s);
	const popc_register_map *m = &a->map;
	int npos = popc_reg_type_words(m->pos.type);
	a->blk_table = m->pos.table;
	a->blk_reg = m->pos.reg;
	a->blk_n = npos;
	if (m->status.table == m->pos.table) {
		int lo = m->status.reg < m->pos.reg ? m->status.reg : m->pos.reg;
		int hi = m->status.reg + 1 > m->pos.reg + npos ? m->status.reg + 1 : m->pos.reg + npos;
		if (hi - lo <= BLOCK_MAX) {
			a->blk_reg = lo;
			a->blk_n = hi - lo;
			a->status_in_block = 1;
		}
	}
	/* a servo-mode drive's force sensor, in the same read when it lies in
	 * the block's table within reach (one FC23 per tick for the shipped
	 * servo maps), else in a read of its own */
	a->servo = m->cmd.mode != POPC_CMD_FORCE;
	a->fs_off = -1;
	int fs_in_block = 0;
	if (a->servo && m->sensor.table == a->blk_table) {
		int nfs = popc_reg_type_words(m->sensor.type);
		int lo = m->sensor.reg < a->blk_reg ? m->sensor.reg : a->blk_reg;
		int hi = m->sensor.reg + nfs > a->blk_reg + a->blk_n ? m->sensor.reg + nfs
								     : a->blk_reg + a->blk_n;
		if (hi - lo <= BLOCK_MAX) {
			a->blk_reg = lo;
			a->blk_n = hi - lo;
			fs_in_block = 1;
		}
	}
	if (a->servo) {
		/* the scene's force sensor, without noise: a drive's noise is in
		 * its reading already ([admittance]'s, or a teleoperation
		 * slave's: popc_register_map_scene_servo) */
		popc_servo_kind kind;
		double res_N;
		const char *key;
		int tele = s->tele_arch != POPC_TELEOP_OFF;
		popc_register_map_scene_servo(s, &kind, &res_N, &key);
		popc_force_sensor_init(&a->fsens, res_N, 0.0, 0);
		a->fs_passthrough = popc_register_map_sensor_is_scene_counts(m, res_N);
		if (!a->fs_passthrough && a->opt.notes)
			fprintf(a->opt.notes,
				"popc: modbus: the force sensor's unit newton_per_unit = %g N is not "
				"%s = %g N: readings are re-quantized to %s\n",
				m->sensor.newton_per_unit,
				tele ? "slave.force_resolution" : "admittance.force_resolution", res_N,
				tele ? "slave.force_resolution" : "admittance.force_resolution");
	}
	/* a sequence register within reach of the block is read back with the
	 * position: the drive holds the value last written, which ties each
	 * reply to its request (check_reply) */
	a->echo_off = -1;
	if (m->cmd.seq_reg >= 0 && a->blk_table == POPC_TABLE_HOLDING) {
		int lo = m->cmd.seq_reg < a->blk_reg ? m->cmd.seq_reg : a->blk_reg;
		int hi = m->cmd.seq_reg + 1 > a->blk_reg + a->blk_n ? m->cmd.seq_reg + 1
								     : a->blk_reg + a->blk_n;
		if (hi - lo <= BLOCK_MAX) {
			a->blk_reg = lo;
			a->blk_n = hi - lo;
			a->echo_off = m->cmd.seq_reg - lo;
		}
	}
	if (fs_in_block)
		a->fs_off = m->sensor.reg - a->blk_reg;
	a->cmd_n = popc_register_map_command_block(m, &a->cmd_first);
	a->cmd_off = m->cmd.reg - a->cmd_first;
	a->seq_off = m->cmd.seq_reg < 0 ? -1 : m->cmd.seq_reg - a->cmd_first;
	a->gap_min_ns = -1;
	if (!a->uri.rtu && a->opt.notes &&
	    (m->rtu_frame_gap_ms > 0 || m->rs485 || m->rts || m->rts_delay_us >= 0))
		fprintf(a->opt.notes,
			"popc: modbus: %s: the map's RTU line keys (rtu_frame_gap_ms, rs485, rts, "
			"rts_delay_us) are ignored over TCP\n",
			m->path);
	popc_histogram_init(&a->dt_hist);
	popc_histogram_init(&a->rtt_hist);
	ax->ops = a->servo ? &modbus_admittance_ops : &modbus_ops;
	ax->priv = a;
	ax->force_limit_N = a->servo ? 0.0 : a->map.cmd.limit_N;
	*out = ax;
	return 0;
}

/* The factory's Modbus kind (axis.c): the program's options as this axis'. */
static int modbus_kind_create(popc_axis **out, const popc_scene *s,
			      const popc_axis_create_options *opt, popc_error *err)
{
	popc_modbus_options o;
	popc_modbus_options_defaults(&o);
	o.pace = !opt->free_run;
	o.realtime = opt->realtime;
	o.notes = opt->notes;
	o.stop_flag = opt->stop_flag;
	return popc_modbus_axis_create(out, s, &o, err);
}

const popc_axis_kind popc_axis_kind_modbus = {"modbus", 0, modbus_kind_create};
