/* popc error reporting: every fallible library call returns 0 on success or a
 * negative popc_status, and fills a popc_error with a message that names the
 * file, line, key and allowed range where those apply. The library never exits. */
#ifndef POPC_ERROR_H
#define POPC_ERROR_H

#include <stddef.h>

/* Process exit codes shared by all popc programs (documented in README.md). */
enum popc_exit {
	POPC_EXIT_OK = 0,          /* success */
	POPC_EXIT_RUN_FAILED = 1,  /* the run failed (I/O, numerical instability, ...) */
	POPC_EXIT_USAGE = 2,       /* bad command line, scene, map or input file */
	POPC_EXIT_SAFETY = 3,      /* safety stop on a real axis (fault bit, soft limit) */
	POPC_EXIT_COMM_LOST = 4,   /* communication with the axis lost */
	POPC_EXIT_INTERRUPTED = 5, /* stopped by SIGINT/TERM/HUP/QUIT, safe state reached */
	POPC_EXIT_UNSTABLE = 6,    /* the simulation went unstable (integrator or closed loop) */
	POPC_EXIT_BUSY = 7,        /* the sweep directory is in use by another popc (sweep, map) */
};

typedef enum popc_status {
	POPC_OK = 0,
	POPC_ERR_INVALID = -1,  /* bad input: scene key, value, file content */
	POPC_ERR_IO = -2,       /* file or stream error */
	POPC_ERR_NOMEM = -3,
	POPC_ERR_NUMERIC = -4,  /* non-finite or diverging numbers */
	POPC_ERR_COMM = -5,     /* communication with an axis */
	POPC_ERR_SAFETY = -6,   /* safety supervisor stop */
	POPC_ERR_INTERRUPTED = -7,
	POPC_ERR_DIVERGED = -8, /* the simulated closed loop diverged (the physics, not the integrator) */
	POPC_ERR_BUSY = -9,     /* a resource another process holds (a sweep directory's lock) */
} popc_status;

#define POPC_ERROR_MSG_MAX 512

typedef struct popc_error {
	char msg[POPC_ERROR_MSG_MAX];
} popc_error;

/* Writes a printf-style message into err (if err is not NULL) and returns status. */
int popc_error_set(popc_error *err, int status, const char *fmt, ...)
#if defined(__GNUC__)
	__attribute__((format(printf, 3, 4)))
#endif
	;

/* A layer's message names its own parameters (popc_plant_init: mass_kg,
 * period_s; popc_chatter_init: window_s); the layer that made them from a
 * scene or a command line names them as its user wrote them (scene keys,
 * options). One parameter and the words that replace it: */
typedef struct popc_error_name {
	const char *param; /* an identifier of the lower layer's message */
	const char *name;  /* what the user wrote: "operator.mass + device.mass" */
} popc_error_name;

/* Replaces every whole identifier (letters, digits, '_') of err's message
 * that is a table's param by its name, in one pass (a name is not read
 * again), cut at POPC_ERROR_MSG_MAX - 1 bytes. err may be NULL. */
void popc_error_name_params(popc_error *err, const popc_error_name *names, size_t n);

/* Maps a popc_status to the process exit code the CLI uses. */
int popc_status_exit_code(int status);

#endif
