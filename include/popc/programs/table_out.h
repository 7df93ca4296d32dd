/* A program's table output, CSV or JSON Lines with the same cells
 * (--format json of compare, chatter, energy, events, bench, sweep stats).
 * In the programs' library, not util: it falls back to stderr when not even
 * /dev/null can be opened, and the library never prints. */
#ifndef POPC_PROGRAMS_TABLE_OUT_H
#define POPC_PROGRAMS_TABLE_OUT_H

#include <stdio.h>

#include "popc/util/json.h"

/* A table written as CSV or, for --format json, as JSON Lines with the same
 * cells: the caller writes CSV lines (its header, then rows) to
 * popc_table_out_row's stream as it always did, and popc_table_out_flush
 * passes them on: unchanged for CSV; for JSON each row as one object with
 * the header's names (popc_json_csv_object), so a number has the digits of
 * its CSV cell. Every column is POPC_JSON_NUMBER but those named in
 * text_names (POPC_JSON_TEXT); the caller may change kinds[] after begin
 * (POPC_JSON_AUTO for a --vary value). */
#define POPC_TABLE_COLUMNS_MAX 256
typedef struct popc_table_out {
	FILE *f;
	int json;
	char *names_line; /* the header, split in place (JSON) */
	const char *names[POPC_TABLE_COLUMNS_MAX];
	popc_json_kind kinds[POPC_TABLE_COLUMNS_MAX];
	int n;
	char *buf; /* the rows since the last flush (JSON) */
	size_t len;
	FILE *rows;
	int failed; /* out of memory on the way: flush returns -1 */
} popc_table_out;

/* header: the CSV header line without its '\n'. Returns 0, or -1 when out of
 * memory (nothing written). CSV: the header is written to f. */
int popc_table_out_begin(popc_table_out *t, FILE *f, int json, const char *header,
			 const char *const *text_names);
/* The stream to write CSV rows to (f itself for CSV). */
FILE *popc_table_out_row(popc_table_out *t);
/* Writes the rows since the last flush. Returns 0, or -1 when out of memory. */
int popc_table_out_flush(popc_table_out *t);
/* Flushes, then frees what begin took. */
int popc_table_out_end(popc_table_out *t);

#endif
