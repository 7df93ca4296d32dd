/* Exact, fast conversion between doubles and decimal text for the CSV logs.
 *
 * popc_format_double writes the shortest decimal string that reads back to the
 * same double (round-trip exact, bitwise, for every finite double including
 * subnormals and negative zero). popc_parse_double reads a decimal number and
 * returns the double nearest to it (round half to even), bitwise equal to what
 * a correctly rounded strtod returns in the C locale. */
#ifndef POPC_NUMFMT_H
#define POPC_NUMFMT_H

#include <stddef.h>
#include <stdint.h>

/* Longest text popc_format_double can write, without the terminating NUL. */
#define POPC_DOUBLE_TEXT_MAX 32

/* Writes the shortest round-trip decimal form of v to buf (at least
 * POPC_DOUBLE_TEXT_MAX + 1 bytes), NUL-terminated; returns the length.
 * Layout as printf("%.17g") but with the fewest digits (the nearest to v
 * among them): plain when the decimal exponent is in [-4, 17), otherwise
 * d.ddde+XX or d.ddde-XX; e.g. "0", "-0", "0.001", "-1.5", "1e-05", "123456", "1e+17",
 * "5e-324". Where 17 digits are needed the text equals "%.17g"'s.
 * Finite values only are round-tripped; NaN is written as "nan" and infinities
 * as "inf" / "-inf" (popc never logs them, but the writer must not crash). */
size_t popc_format_double(double v, char *buf);

/* popc_format_double's text with a decimal point always: ".0" is inserted
 * where the shortest form has none, at the end of an integer ("0.0", "-0.0",
 * "5.0", "-1000.0") or before the exponent ("1.0e+17", "5.0e-324"). It reads
 * back to the same double (the digits are the same) and every CSV type
 * sniffer (DuckDB's, pandas', R's, spreadsheets') types a column of such
 * cells as floating point even where its sampled cells are all integral,
 * which "0" and "5" are not. At most POPC_DOUBLE_TEXT_MAX characters too
 * (the longest shortest form, "-2.2250738585072014e-308", has 24).
 * NaN and infinities as popc_format_double writes them. */
size_t popc_format_double_point(double v, char *buf);

/* Parses a decimal floating-point number at [s, end). Accepts an optional sign,
 * digits with an optional '.', and an optional exponent (e or E); no leading
 * spaces, no hex, no "nan"/"inf". On success stores the correctly rounded
 * double in *out and returns the number of characters consumed (> 0); returns 0
 * if no number starts at s. Stops at the first character that cannot continue
 * the number, so the caller checks what follows (delimiter, end of line). */
size_t popc_parse_double(const char *s, const char *end, double *out);

/* A row of n numbers at [s, end) in one pass: cell i is the text from the
 * start (or just past the delimiter before it) to the next delim, the last
 * one to end. Stores each cell's double in out[] while every cell so far is
 * a number as popc_parse_double reads it, filling its cell exactly (no
 * blanks, no quotes, nothing after it), finite, and not an underflow to
 * zero (a nonzero digit that read as 0, as "1e-400"); returns how many
 * consecutive cells from the first were such numbers: n for a row of plain
 * numbers, less where a cell needs a closer look (the caller's own split
 * then reads the line, and says what is wrong with it, if anything). A row
 * with other than n cells returns less than n. delim is no character a
 * number may hold (a digit, '.', '+', '-', 'e', 'E'; returns 0 for one). */
int popc_parse_double_row(const char *s, const char *end, char delim, double *out, int n);

/* popc_parse_double_row on a line that starts at s and ends inside [s, end)
 * at its first "\n" (or "\r\n"), without a search for it first: the last
 * number must be followed by "\n" or "\r\n" before end, whose first byte's
 * address goes to *line_end when all n cells are read. A line the text cuts
 * before its end returns less than n. delim is no '\n' or '\r' either. */
int popc_parse_double_line(const char *s, const char *end, char delim, double *out, int n,
			   const char **line_end);

/* The last cell one column read through popc_parse_double_line_skip: its
 * bytes with the byte after it (len of them, at most 32), their masks and
 * the value they read as. len 0: none (zero-initialized memos are empty). */
typedef struct popc_parse_memo {
	uint64_t text[4];
	uint64_t mask[4];
	double value;
	unsigned len;
} popc_parse_memo;

/* The first character at or after s that no number can hold (a digit, '.',
 * '+', '-', 'e', 'E'), or end. */
const char *popc_number_chars_end(const char *s, const char *end);

/* popc_parse_double_line with memo[0..n): a cell whose bytes and terminator
 * (delimiter or line end) equal those memo[i] holds takes memo[i].value
 * without a parse, the same bits the parse gives (they are the same text);
 * every other cell read is parsed and kept in memo[i]. With skip (NULL:
 * none), a cell with skip[i] set is not parsed: it must be one or more of a
 * number's characters (popc_number_chars_end) up to its delimiter or the
 * line's end, and out[i] is NaN. Returns and checks as
 * popc_parse_double_line otherwise. */
int popc_parse_double_line_skip(const char *s, const char *end, char delim, double *out, int n,
				const char **line_end, popc_parse_memo *memo,
				const unsigned char *skip);

#endif
