#include "popc/util/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int popc_error_set(popc_error *err, int status, const char *fmt, ...)
{
	if (err) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof err->msg, fmt, ap);
		va_end(ap);
	}
	return status;
}

static int ident_char(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
	       c == '_';
}

void popc_error_name_params(popc_error *err, const popc_error_name *names, size_t n)
{
	if (!err)
		return;
	char out[POPC_ERROR_MSG_MAX];
	size_t o = 0;
	const char *s = err->msg;
	while (*s && o < sizeof out - 1) {
		size_t len = 0;
		while (ident_char(s[len]))
			len++;
		if (len == 0) {
			out[o++] = *s++;
			continue;
		}
		const char *w = s;
		size_t wlen = len;
		for (size_t i = 0; i < n; i++)
			if (strlen(names[i].param) == len && memcmp(names[i].param, s, len) == 0) {
				w = names[i].name;
				wlen = strlen(w);
				break;
			}
		size_t k = wlen < sizeof out - 1 - o ? wlen : sizeof out - 1 - o;
		memcpy(out + o, w, k);
		o += k;
		s += len;
	}
	out[o] = '\0';
	memcpy(err->msg, out, o + 1);
}

int popc_status_exit_code(int status)
{
	switch (status) {
	case POPC_OK: return POPC_EXIT_OK;
	case POPC_ERR_INVALID: return POPC_EXIT_USAGE;
	case POPC_ERR_SAFETY: return POPC_EXIT_SAFETY;
	case POPC_ERR_COMM: return POPC_EXIT_COMM_LOST;
	case POPC_ERR_INTERRUPTED: return POPC_EXIT_INTERRUPTED;
	case POPC_ERR_NUMERIC: return POPC_EXIT_UNSTABLE;
	case POPC_ERR_DIVERGED: return POPC_EXIT_UNSTABLE;
	case POPC_ERR_BUSY: return POPC_EXIT_BUSY;
	default: return POPC_EXIT_RUN_FAILED;
	}
}
