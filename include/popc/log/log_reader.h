/* Streaming CSV log reader: popc's own logs and recorded device logs.
 *
 * Memory is constant in the length of the log (one block buffer). Header
 * comment lines ("# key = value") before the column names are kept as
 * provenance; comment lines after it ("# stop = ...") are kept too. The first
 * non-comment line holds the column names; every later line is one row of
 * numbers, parsed exactly (popc_parse_double), so values read back bitwise.
 *
 * A UTF-8 byte order mark at the start of the file is skipped.
 *
 * Columns by position: a --column HEADER "#N" (N = 1, 2, ...) is the file's
 * N-th column, whatever its name, so "#2" never names a column called "#2".
 * A file without a column names line (opt.no_header, recorded device logs)
 * has columns named "#1", "#2", ... after the cell count of its first row,
 * which is read as a row.
 *
 * Numbers use a decimal point, or a decimal comma with opt.decimal = ','.
 *
 * Cells may be in double quotes (RFC 4180). Column names may be empty (pandas'
 * index column, a trailing delimiter); an empty name is never looked up.
 * Blanks around a cell are trimmed, but under a tab delimiter a tab is no
 * blank: "1\t\t2" is three cells, the middle one empty (an error in a column
 * that is read).
 *
 * The comment mark cannot be the delimiter (given or detected): a row whose
 * first cell is empty would read as a comment. A first line of numbers read
 * as the names while every mapping is a position ("#N") is refused with the
 * hint to use no_header: no lookup by name would fail to say so, and the
 * first row would be lost.
 *
 * Errors name the file, line and column: an empty file, a repeated column name,
 * a row with too few or too many cells, a cell that is not a finite number, a
 * missing column.
 *
 * An unfinished popc log (one whose header has "format"), cut short by a full
 * disk or a killed process, reads as its whole rows: a last line without a
 * newline is the end of the log, not a row, and a log may lack its
 * "# stop = ..." line; popc_log_reader_unfinished says which, after the last
 * row, for the caller to note. A foreign log may end without a newline (RFC
 * 4180): its last line is a row.
 *
 * A popc log's header gives each key once (a key given twice is an error
 * naming both lines: the scene would take the last, a header lookup the
 * first). A carriage return inside a header or column names line is an error:
 * a file with CR-only line ends (classic Mac OS) would read as one line. */
#ifndef POPC_LOG_READER_H
#define POPC_LOG_READER_H

#include <stddef.h>
#include <stdio.h>

#include "popc/util/error.h"
#include "popc/util/numfmt.h"
#include "popc/scene/scene.h"

#define POPC_LOG_MAX_COLUMNS 64
#define POPC_LOG_MAX_HEADER_KEYS 128

typedef struct popc_log_reader_options {
	char delimiter;                 /* 0: detect from the header line (',', ';', tab, space) */
	char comment;                   /* 0: '#' */
	/* 0 or '.': decimal point. ',': decimal comma (European rigs: "1,5" with
	 * ';' between cells): a parsed cell's ',' reads as '.', bit for bit the
	 * same number, and a '.' in it is an error (a thousands separator or a
	 * mixed file). Excludes the delimiter ','; detection then picks ';' or tab. */
	char decimal;
	/* 1: no column names line; the first line that is no comment is a row */
	int no_header;
	/* --column NAME=HEADER: popc's name NAME is the file's column HEADER */
	int n_map;
	const char *map_name[POPC_LOG_MAX_COLUMNS];
	const char *map_header[POPC_LOG_MAX_COLUMNS];
} popc_log_reader_options;

typedef struct popc_log_reader {
	FILE *f;
	int owns_file;
	char path[1024];
	popc_log_reader_options opt;
	char delimiter, comment;
	/* columns */
	int n_cols;
	char *col_name[POPC_LOG_MAX_COLUMNS];
	/* header "key = value" comments (keys qualified "section.key" below a [section]) */
	int n_keys;
	char *key[POPC_LOG_MAX_HEADER_KEYS], *value[POPC_LOG_MAX_HEADER_KEYS];
	long long key_line[POPC_LOG_MAX_HEADER_KEYS]; /* the line of each key */
	char section[64];               /* the last [section] comment, for keys after it */
	char stop_reason[512];
	/* buffer */
	char *buf;
	size_t cap, start, end;
	int eof;
	int read_errno;                 /* errno of a failed read */
	long long lineno;               /* line number of the last line returned */
	long long rows;
	int t_col;                      /* index of "t", -1 if none: time must increase */
	/* 0: a column nobody reads (NaN); 1: parsed; 2: checked to be a
	 * number's characters, not parsed (NaN): popc_log_reader_check_columns */
	unsigned char parse[POPC_LOG_MAX_COLUMNS];
	unsigned char skip[POPC_LOG_MAX_COLUMNS]; /* parse != 1: the one pass skips the cell */
	int popc_log;                   /* the header has "format": popc wrote it */
	int fast_rows;                  /* rows may be read by popc_parse_double_row */
	/* each column's last cell read in one pass: a repeated cell is not parsed again */
	popc_parse_memo memo[POPC_LOG_MAX_COLUMNS];
	double t_prev;
	long long last_row_line;        /* line of the last row returned (0: none) */
	long long cut_line;             /* a popc log's last line, cut (no newline); 0: none */
	long long names_line;           /* the column names line (0: no_header) */
	char names_hint[160];           /* popc_log_reader_header_hint's text */
	/* every column name is a number: likely a headerless file read without
	 * no_header (its first row taken for names); errors then say so */
	int names_numeric;
	char *first_row;                /* no_header: the first row, read at open */
	int first_row_pending;          /* 1 until popc_log_reader_next returned it */
	int first_row_complete;         /* it ended with a newline */
} popc_log_reader;

/* How a popc log ended, when it did not end as popc ends one (a whole last
 * line, then "# stop = <reason>"). */
enum {
	POPC_LOG_NO_STOP = 1,  /* whole rows, but no stop line after them */
	POPC_LOG_CUT_LINE = 2, /* the last line has no newline: cut (cut_line), not read */
};

/* Opens a log ("-" is standard input) and reads its header and column names. */
int popc_log_reader_open(popc_log_reader *r, const char *path, const popc_log_reader_options *opt,
			 popc_error *err);

/* Reads the next row into values[0 .. n_cols-1]. Returns 1 for a row, 0 at the
 * end, or a negative popc_status (message names file:line:column). */
int popc_log_reader_next(popc_log_reader *r, double *values, popc_error *err);

/* Only the columns cols[0 .. n-1] (and the time column) are parsed from now
 * on; the others are NaN whatever they hold (text, a timestamp, an empty
 * cell), so a recorded log's extra columns need not be numbers. The cell count
 * of a row is still checked. Default after open: every column. Returns 0 or
 * POPC_ERR_INVALID for an index out of range. */
int popc_log_reader_use_columns(popc_log_reader *r, const int *cols, int n);

/* After popc_log_reader_use_columns: the columns cols[0 .. n-1] (not the
 * time column) are not read either, but each of their cells must still be one
 * or more of a number's characters (digits, '.', '+', '-', 'e', 'E', and the
 * decimal comma where it is the mark), else the row is an error naming the
 * cell; they are NaN. What is no longer checked in them: that the characters
 * make a finite number ("1.2.3", "1e999", "1e-400" pass). A verb that never
 * reads a column skips its parse so. Returns 0 or POPC_ERR_INVALID for an
 * index out of range. */
int popc_log_reader_check_columns(popc_log_reader *r, const int *cols, int n);

/* Index of popc's column NAME (through the --column map; a mapped "#N" is
 * position N), or -1. */
int popc_log_reader_column(const popc_log_reader *r, const char *name);

/* Like popc_log_reader_column, but a missing column is an error naming it. */
int popc_log_reader_require(const popc_log_reader *r, const char *name, int *index,
			    popc_error *err);

/* A header value ("variant", "source", "run.rate", ...) or NULL. */
const char *popc_log_reader_header(const popc_log_reader *r, const char *key);

/* The line of a header key (for messages), or 0 when the header lacks it. */
long long popc_log_reader_header_line(const popc_log_reader *r, const char *key);

/* A --column HEADER "#N" (N = 1 to 99999, no leading 0): the position N,
 * 1-based; 0 for a HEADER that is a name. */
int popc_log_reader_position(const char *header);

/* Rebuilds the scene of a popc log from its header on top of s (defaults
 * first). Keys the header lacks keep their values in s. An error names the
 * file and the key's line ("LOG:12: header: run.rate = 1e7: out of range"). */
int popc_log_reader_scene(const popc_log_reader *r, popc_scene *s, popc_error *err);

/* After popc_log_reader_next returned 0: 0 for a popc log that ended with its
 * stop line and for every foreign log; else POPC_LOG_NO_STOP or
 * POPC_LOG_CUT_LINE (the rows read end at last_row_line). */
int popc_log_reader_unfinished(const popc_log_reader *r);

void popc_log_reader_close(popc_log_reader *r);

/* " (line L holds only numbers: ... --no-header ...)" when the column names
 * are all numbers, else "": for messages about a column not found. */
const char *popc_log_reader_header_hint(const popc_log_reader *r);

/* Parses "NAME=HEADER" into the options' map (pointers into text). */
int popc_log_reader_add_mapping(popc_log_reader_options *opt, char *text, popc_error *err);

#endif
