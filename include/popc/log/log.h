/* The CSV log (README, "The log"; docs/READING.md).
 *
 *   # popc log
 *   # format = 1
 *   # popc_version = 0.1.0
 *   # source = sim | modbus | replay
 *   # variant = ref-energy
 *   # popc_build = ..., # date = ..., # command = ...   (popc run's extra
 *   #                 lines: the provenance, src/cli/provenance.c)
 *   # [run] ... the whole resolved scene, prefixed "# "
 *   t,x,count[,x_true],v,f_e,f_pc,f_c,W,E_ref,flags[,E_port][,dt,rtt]
 *   0,-0.01,-1000,-0.01,0,0,0,0,0,0,0,0
 *
 * The columns, their units and which axes fill them: log_columns.h.
 *
 * Numbers are written in their shortest round-trip form (popc_format_double),
 * so a reader gets back the same doubles and an offline recompute equals the
 * online value bit for bit. A run that stops early ends with a comment line
 * "# stop = <reason>".
 *
 * The file holds whole lines only, whatever the disk does: the writer counts
 * the bytes of the whole lines written, and when a write fails or is cut
 * short (a full disk, ENOSPC; a file size limit, EFBIG) it cuts a regular
 * file it opened back to the last whole line (ftruncate) and writes nothing
 * more but the stop line, which it tries once and cuts away again if it does
 * not fit. So a log always reads as a valid prefix: its last whole row, then
 * "# stop = log write failed: ..." where the space allowed. A log on standard
 * output, a pipe or a device is not cut back (others may share it). */
#ifndef POPC_LOG_H
#define POPC_LOG_H

#include <stdio.h>

#include "popc/core/controller.h"
#include "popc/log/log_columns.h"
#include "popc/util/error.h"
#include "popc/scene/scene.h"

#define POPC_LOG_FORMAT_VERSION 1

typedef struct popc_log_writer {
	int fd;                /* the log's descriptor, -1 when closed */
	int owns_file;         /* opened by popc_log_open (not standard output) */
	int can_cut;           /* a regular file popc opened: ftruncate works */
	unsigned columns;
	char *buf;             /* output buffer: whole lines only */
	size_t len, cap;
	long long whole_bytes; /* bytes of whole lines in the file */
	int at_line_start;     /* the file ends with a whole line (or is empty) */
	int failed_errno;      /* a write failed: errno (0: none); no more rows go out */
	struct popc_log_cell_cache *cells; /* texts of recent values (log_writer.c) */
	char path[1024];
} popc_log_writer;

/* Opens path for writing ("-" is standard output). */
int popc_log_open(popc_log_writer *w, const char *path, unsigned columns, popc_error *err);

/* Writes the provenance header and the column names line. source is "sim",
 * "modbus" or "replay". extra (may be NULL) is written as more "# " lines. */
int popc_log_write_header(popc_log_writer *w, const char *source, const popc_scene *s,
			  const char *extra, popc_error *err);

/* Appends one row (buffered). */
int popc_log_write_row(popc_log_writer *w, const popc_log_row *r, popc_error *err);

/* Appends a "# key = value" comment line (used for the stop reason). After
 * a failed write, the stop line alone is still tried, at the end of the
 * whole lines (and cut away again if it does not fit whole). */
int popc_log_write_comment(popc_log_writer *w, const char *key, const char *value,
			   popc_error *err);

/* Writes out everything buffered. */
int popc_log_flush(popc_log_writer *w, popc_error *err);

/* Flushes and closes; safe to call twice. */
int popc_log_close(popc_log_writer *w, popc_error *err);

#endif
