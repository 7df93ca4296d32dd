/* Connection URIs of the Modbus axis (modbus_axis.h):
 * tcp:HOST[:PORT] and rtu:DEVICE[:BAUD[:FORMAT]]. */
#include <arpa/inet.h>
#include <netinet/in.h>
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

/* An IPv4 address: four decimal numbers 0-255 without leading zeros (the
 * C library reads "010" as octal 8). Returns NULL or what is wrong. */
static const char *ipv4_wrong(const char *h)
{
	int parts = 0;
	for (const char *p = h;; p++) {
		const char *q = p;
		int v = 0;
		while (*q >= '0' && *q <= '9' && q - p < 4)
			v = 10 * v + (*q++ - '0');
		if (q == p || q - p > 3 || v > 255)
			return "an IPv4 address is four numbers 0-255";
		if (*p == '0' && q - p > 1)
			return "an IPv4 number with a leading zero (it would read as octal)";
		parts++;
		p = q;
		if (!*p)
			break;
		if (*p != '.')
			return "an IPv4 address is four numbers 0-255";
	}
	return parts == 4 ? NULL : "an IPv4 address is four numbers 0-255";
}

/* A host name (RFC 1123): labels of 1-63 letters, digits and '-', not
 * starting or ending with '-', joined by '.', 253 characters at most. */
static const char *name_wrong(const char *h)
{
	if (strlen(h) > 253)
		return "a host name has at most 253 characters";
	for (const char *p = h;; p++) {
		size_t n = strspn(p, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-");
		if (n == 0 || n > 63 || p[0] == '-' || p[n - 1] == '-' || (p[n] && p[n] != '.'))
			return "a host is an IPv4 address (four numbers 0-255), an IPv6 address in "
			       "brackets, or a host name (letters, digits, '-', labels joined by '.')";
		p += n;
		if (!*p)
			return NULL;
	}
}

/* An IPv6 address (the text inside the brackets), with an optional zone
 * "%if" (a link-local address' interface). */
static const char *ipv6_wrong(const char *h)
{
	char addr[64];
	size_t n = strcspn(h, "%");
	if (n >= sizeof addr)
		return "not an IPv6 address";
	memcpy(addr, h, n);
	addr[n] = '\0';
	struct in6_addr a6;
	if (inet_pton(AF_INET6, addr, &a6) != 1)
		return "not an IPv6 address";
	if (h[n] && (h[n + 1] == '\0' ||
		     strspn(h + n + 1, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") !=
			     strlen(h + n + 1)))
		return "an IPv6 zone is '%' and an interface name";
	return NULL;
}

static int parse_tcp(const char *text, const char *p, popc_modbus_uri *u, popc_error *err)
{
	const char *host_end, *port = NULL;
	char why[320];
	const char *wrong;
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
		wrong = ipv6_wrong(u->host);
	} else {
		host_end = strchr(p, ':');
		size_t n = host_end ? (size_t)(host_end - p) : strlen(p);
		if (n == 0 || n >= sizeof u->host)
			return uri_bad(err, text, "missing or too long host");
		memcpy(u->host, p, n);
		u->host[n] = '\0';
		if (host_end)
			port = host_end + 1;
		/* only digits and dots: meant as an IPv4 address (a name's last
		 * label is never all digits), so 999.999.999.999 is refused here
		 * rather than looked up and refused by the network */
		wrong = strspn(u->host, "0123456789.") == n ? ipv4_wrong(u->host) : name_wrong(u->host);
	}
	if (wrong) {
		snprintf(why, sizeof why, "host '%.*s': %s", 40, u->host, wrong);
		return uri_bad(err, text, why);
	}
	long long v = 502; /* the registered Modbus TCP port */
	if (port) {
		/* decimal digits only: no sign, exponent or fraction ("+1", "5e2"
		 * were read as ports), and in [0, 65535] */
		size_t digits = strspn(port, "0123456789");
		if (digits == 0 || port[digits] || popc_parse_ll_text(port, 0, 65535, &v) != 0)
			return uri_bad(err, text, "port must be decimal digits, 1-65535 (0: any free port, "
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
	/* digits only, as the port: "+9600" read as 9600 (the number grammar
	 * takes a sign), and " 9600" or "9600.0" are no baud a line is set to */
	size_t digits = strspn(b, "0123456789");
	if (digits == 0 || b + digits != end || popc_parse_ll_span(b, end, 50, 4000000, 0, &baud) != 0)
		return uri_bad(err, text, "baud must be decimal digits, an integer in [50, 4000000]");
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
