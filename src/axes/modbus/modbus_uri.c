/* Connection URIs of the Modbus axis (modbus_axis.h):
 * tcp:HOST[:PORT] and rtu:DEVICE[:BAUD[:FORMAT]]. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/axes/modbus_axis.h"
#include "popc/util/parse.h"

static int uri_bad(popc_error *err, const char *text, const char *what)
{
	return popc_error_set(err, POPC_ERR_INVALID,
			      "connect URI '%s': %s (expected " POPC_URI_NOTATION ")",
			      text, what);
}

static int parse_tcp(const char *text, const char *p, popc_modbus_uri *u, popc_error *err)
{
	const char *host_end, *port = NULL;
	if (*p == '[') { /* [IPv6]:port */
		const char *close = strchr(p, ']');
		if (!close)
			return uri_bad(err, text, "unclosed '[' in the host");
		if ((size_t)(close - p - 1) >= sizeof u->host || close == p + 1)
			return uri_bad(err, text, "bad host");
		memcpy(u->host, p + 1, (size_t)(close - p - 1));
		u->host[close - p - 1] = '\0';
		host_end = close + 1;
		if (*host_end == ':')
			port = host_end + 1;
		else if (*host_end)
			return uri_bad(err, text, "junk after the host");
	} else {
		host_end = strchr(p, ':');
		size_t n = host_end ? (size_t)(host_end - p) : strlen(p);
		if (n == 0 || n >= sizeof u->host)
			return uri_bad(err, text, "missing or too long host");
		memcpy(u->host, p, n);
		u->host[n] = '\0';
		if (host_end)
			port = host_end + 1;
	}
	/* a bracket belongs around an IPv6 address only: "tcp:[[]" left the
	 * host "[", whose canonical text "tcp:[:502" no longer parses */
	if (strpbrk(u->host, "[]"))
		return uri_bad(err, text, "'[' or ']' inside the host");
	long long v = 502; /* the registered Modbus TCP port */
	if (port) {
		if (popc_parse_ll_text(port, 0, 65535, &v) != 0) /* a number as everywhere: no blanks */
			return uri_bad(err, text, "port must be an integer in [0, 65535] (0: any free port, "
						  "for a server)");
	}
	snprintf(u->port, sizeof u->port, "%lld", v);
	return 0;
}

static int parse_rtu(const char *text, const char *p, popc_modbus_uri *u, popc_error *err)
{
	const char *colon = strchr(p, ':');
	size_t n = colon ? (size_t)(colon - p) : strlen(p);
	if (n == 0 || n >= sizeof u->device)
		return uri_bad(err, text, "missing or too long device");
	memcpy(u->device, p, n);
	u->device[n] = '\0';
	u->baud = 19200;
	u->data_bits = 8;
	u->parity = 'E';
	u->stop_bits = 1;
	if (!colon)
		return 0;
	const char *b = colon + 1;
	const char *end = b + strcspn(b, ":");
	long long baud;
	if (popc_parse_ll_span(b, end, 50, 4000000, 0, &baud) != 0)
		return uri_bad(err, text, "baud must be an integer in [50, 4000000]");
	u->baud = (int)baud;
	if (!*end)
		return 0;
	const char *f = end + 1;
	if (strlen(f) != 3 || f[0] < '5' || f[0] > '8' || !strchr("NEO", f[1]) ||
	    (f[2] != '1' && f[2] != '2'))
		return uri_bad(err, text, "format must be data bits 5-8, parity N/E/O, stop bits 1/2 (8N1)");
	u->data_bits = f[0] - '0';
	u->parity = f[1];
	u->stop_bits = f[2] - '0';
	return 0;
}

int popc_modbus_uri_parse(const char *text, popc_modbus_uri *u, popc_error *err)
{
	memset(u, 0, sizeof *u);
	if (strncmp(text, "tcp:", 4) == 0)
		return parse_tcp(text, text + 4, u, err);
	if (strncmp(text, "rtu:", 4) == 0) {
		u->rtu = 1;
		return parse_rtu(text, text + 4, u, err);
	}
	return uri_bad(err, text, "unknown transport");
}

void popc_modbus_uri_format(const popc_modbus_uri *u, char *buf, size_t cap)
{
	if (u->rtu)
		snprintf(buf, cap, "rtu:%s:%d:%d%c%d", u->device, u->baud, u->data_bits, u->parity,
			 u->stop_bits);
	else if (strchr(u->host, ':'))
		snprintf(buf, cap, "tcp:[%s]:%s", u->host, u->port);
	else
		snprintf(buf, cap, "tcp:%s:%s", u->host, u->port);
}
