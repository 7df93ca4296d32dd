/* A small JSON writer (RFC 8259) for the machine-readable summaries: one
 * object per line (JSON Lines), numbers in their shortest round-trip form.
 *
 * Strings are escaped as RFC 8259 section 7 requires: '"' and '\' with a
 * backslash, the control characters U+0000 to U+001F as \b \f \n \r \t or
 * \u00XX; valid UTF-8 passes unchanged, and a byte that is not part of a
 * valid UTF-8 sequence becomes U+FFFD (\ufffd), so the output is always
 * valid UTF-8 and valid JSON. A number that is not finite is written null:
 * JSON has no NaN or infinity. */
#ifndef POPC_UTIL_JSON_H
#define POPC_UTIL_JSON_H

#include <stddef.h>
#include <stdio.h>

/* Nesting depth the writer tracks (objects and arrays). */
#define POPC_JSON_DEPTH_MAX 8

typedef struct popc_json {
	FILE *f;
	int depth;
	unsigned char has_item[POPC_JSON_DEPTH_MAX + 1]; /* a comma before the next */
	int after_key;                                   /* a value completes a member */
} popc_json;

void popc_json_init(popc_json *j, FILE *f);
void popc_json_begin_object(popc_json *j);
void popc_json_end_object(popc_json *j);
void popc_json_begin_array(popc_json *j);
void popc_json_end_array(popc_json *j);
/* A member's name; the next call writes its value. */
void popc_json_key(popc_json *j, const char *name);
void popc_json_string(popc_json *j, const char *s, size_t n);
void popc_json_cstring(popc_json *j, const char *s);
void popc_json_number(popc_json *j, double v); /* null when not finite */
void popc_json_integer(popc_json *j, long long v);
void popc_json_null(popc_json *j);

/* How a CSV cell becomes a JSON value (popc_json_csv_object). An empty cell
 * is null whatever the kind: a value not measured, as in the CSV. */
typedef enum popc_json_kind {
	POPC_JSON_TEXT,   /* a string, always */
	POPC_JSON_NUMBER, /* a number: the cell's text when it is a JSON number
			   * already (popc's shortest form is), else the double
			   * it reads as, shortest; null when it reads as none or
			   * not finite */
	POPC_JSON_AUTO,   /* a number where the whole cell reads as a finite
			   * number (as NUMBER), else a string: a --vary value */
} popc_json_kind;

/* Writes one CSV line (row, len bytes, without or with its '\n'; cells
 * separated by ',', RFC 4180 quotes allowed) as one object on one line:
 * {"names[0]": cell 0, ...}\n. A row with fewer cells than names gives null
 * for the missing ones; cells beyond n are ignored. */
void popc_json_csv_object(FILE *f, int n, const char *const *names, const popc_json_kind *kinds,
			  const char *row, size_t len);

/* The same objects for many rows with the same names: popc_json_csv_keys
 * writes the n names once as the objects' keys (malloc'd; NULL when out of
 * memory), and popc_json_csv_object_keyed writes a row with them, the same
 * bytes as popc_json_csv_object (a sweep's summary.jsonl: the names escaped
 * once, not once a row). */
char *popc_json_csv_keys(int n, const char *const *names);
void popc_json_csv_object_keyed(FILE *f, int n, const char *keys, const popc_json_kind *kinds,
				const char *row, size_t len);

/* Splits a CSV header line like popc_json_csv_object's rows: up to cap
 * names, each NUL-terminated in place of its separator (line is changed).
 * Returns the number of names. */
int popc_json_csv_names(char *line, const char **names, int cap);

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
