#include "popc/util/error.h"

#include <stdarg.h>
#include <stdio.h>

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
