/* Connect URI harness (modbus_axis.h): every accepted URI formats to a
 * canonical text that parses back to the same URI and the same text; every
 * refusal quotes the URI. */
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "popc/axes/modbus_axis.h"

int popc_fuzz_modbus_uri(const uint8_t *data, size_t size)
{
	if (size > 4096 || memchr(data, '\0', size))
		return 0; /* a command-line argument: NUL-free, bounded */
	char *text = malloc(size + 1);
	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = '\0';
	popc_modbus_uri u, v;
	popc_error err;
	if (popc_modbus_uri_parse(text, &u, &err) != 0) {
		if (strncmp(err.msg, "connect URI '", 13) != 0)
			popc_fuzz_fail(data, size, "refusal without the URI: %s", err.msg);
		free(text);
		return 0;
	}
	if (u.rtu ? !u.device[0] || u.baud < 50 || u.baud > 4000000 || u.data_bits < 5 ||
			    u.data_bits > 8 || !strchr("NEO", u.parity) || u.parity == '\0' ||
			    (u.stop_bits != 1 && u.stop_bits != 2)
		  : !u.host[0] || !u.port[0])
		popc_fuzz_fail(data, size, "accepted an incomplete URI");
	/* a TCP port is decimal digits in [0, 65535], a host holds no blank,
	 * control character or bracket (issue 28: "+1", "host name") */
	if (!u.rtu && (strspn(u.port, "0123456789") != strlen(u.port) || strlen(u.port) > 5 ||
		       atol(u.port) > 65535 || strpbrk(u.host, " \t\r\n\v\f[]")))
		popc_fuzz_fail(data, size, "accepted host '%s' port '%s'", u.host, u.port);
	char canon[2 * POPC_PATH_MAX], again[2 * POPC_PATH_MAX];
	popc_modbus_uri_format(&u, canon, sizeof canon);
	if (popc_modbus_uri_parse(canon, &v, &err) != 0)
		popc_fuzz_fail(data, size, "canonical text '%s' refused: %s", canon, err.msg);
	popc_modbus_uri_format(&v, again, sizeof again);
	if (strcmp(canon, again) != 0 || strcmp(u.host, v.host) != 0 || strcmp(u.port, v.port) != 0 ||
	    strcmp(u.device, v.device) != 0 || u.rtu != v.rtu || u.baud != v.baud ||
	    u.parity != v.parity || u.data_bits != v.data_bits || u.stop_bits != v.stop_bits)
		popc_fuzz_fail(data, size, "'%s' reads back as '%s'", canon, again);
	free(text);
	return 0;
}
