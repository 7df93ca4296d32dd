/* The Modbus axis: a servo drive over Modbus TCP or RTU (libmodbus), described
 * by a register map file (register_map.h), with the safety supervisor built in.
 *
 * What the axis does on every tick (docs/MODBUS.md, "What a tick does"):
 * - pacing: absolute deadlines on CLOCK_MONOTONIC (clock_nanosleep with
 *   TIMER_ABSTIME) at run.rate; the measured period dt and the Modbus
 *   transaction time rtt go to the log; overruns are counted, and a tick late
 *   by whole periods skips those grid points instead of bursting to catch up;
 * - with fc23 = yes the command of tick k and the position of tick k+1 travel
 *   in one FC23 transaction at the deadline of tick k+1 (cyclic process data:
 *   the command reaches the drive one period after it was computed); without
 *   it the command is written (FC06/FC16) at once and the position read
 *   (FC03/FC04) at the next deadline;
 * - safety, always on: the command is clamped to the map's limit_N; a
 *   position outside soft_min_m..soft_max_m, a fault bit, or a lost ready bit
 *   stops the run (POPC_ERR_SAFETY, exit 3); a failed transaction is retried,
 *   never answered with an old position, and max_failures failures in a row
 *   stop the run (POPC_ERR_COMM, exit 4); a signal (the stop flag) ends the
 *   retries (POPC_ERR_INTERRUPTED, exit 5); start() refuses a drive that
 *   reports a fault; stop() writes zero force and then the disable word, on
 *   every way out.
 * - link hygiene: error recovery MODBUS_ERROR_RECOVERY_NONE; after a timeout
 *   an RTU line is drained until quiet (RTU has no transaction id, a late reply
 *   would pass for the next one) and a TCP link is reconnected (so a late reply
 *   can never be read as the answer to a later request). */
#ifndef POPC_MODBUS_AXIS_H
#define POPC_MODBUS_AXIS_H

#include <signal.h>
#include <stdio.h>

#include "popc/axes/axis.h"
#include "popc/util/error.h"
#include "popc/scene/scene.h"

/* A connection URI: tcp:HOST[:PORT] (PORT 502 by default; HOST may be an
 * IPv6 address in brackets) or rtu:DEVICE[:BAUD[:FORMAT]] with FORMAT like
 * 8N1 or 8E1 (default 19200 baud, 8E1: the Modbus serial line default,
 * Modbus over Serial Line V1.02 section 2.5.1). */
typedef struct popc_modbus_uri {
	int rtu;
	char host[256];
	char port[16];
	char device[POPC_PATH_MAX];
	int baud;
	char parity;        /* 'N', 'E' or 'O' */
	int data_bits, stop_bits;
} popc_modbus_uri;

int popc_modbus_uri_parse(const char *text, popc_modbus_uri *u, popc_error *err);

/* Canonical text of a URI (the readiness line and logs use it). */
void popc_modbus_uri_format(const popc_modbus_uri *u, char *buf, size_t cap);

typedef struct popc_modbus_options {
	int pace;           /* 1 (default): absolute deadlines at run.rate; 0: free-run, each
			       tick as soon as the last one is done (lockstep dry runs) */
	int realtime;       /* 1: try SCHED_FIFO (rt_priority) and mlockall; 0 (default): don't */
	int rt_priority;    /* SCHED_FIFO priority, 1..99 (default 50) */
	FILE *notes;        /* where notes go (real-time granted or not, reconnects); may be NULL */
	/* set by a signal handler (the runner's stop flag; NULL: none). libmodbus
	 * calls are not interrupted by signals, so the axis looks at the flag
	 * itself: between the attempts of a failing transaction (it gives up with
	 * POPC_ERR_INTERRUPTED instead of retrying up to max_failures times), in
	 * start() before enabling and while it waits for the ready bits; and once
	 * it is set, stop() makes one attempt per write (zero force, disable)
	 * instead of retrying. */
	volatile sig_atomic_t *stop_flag;
} popc_modbus_options;

void popc_modbus_options_defaults(popc_modbus_options *o);

/* Creates the axis from the scene's axis.map and axis.connect. Loads and
 * checks the map and the URI; does not connect (start() does). The caller
 * owns the axis and frees it with popc_axis_destroy. */
int popc_modbus_axis_create(popc_axis **out, const popc_scene *s, const popc_modbus_options *o,
			    popc_error *err);

#endif
