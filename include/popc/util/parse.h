/* Strict number parsing: every number a popc program reads from a scene, a
 * map, a table, a URI, a log or its command line goes through these, so one
 * spelling is accepted or refused everywhere.
 *
 * A number is the whole text: an optional sign, decimal digits with an
 * optional '.', and an optional exponent (e or E, optional sign, digits),
 * read in the C locale
 * whatever the process locale is, correctly rounded (popc_parse_double,
 * numfmt.h). Refused: empty text, hexadecimal ("0x2", "0x1p1"), "inf", "nan",
 * anything after the number ("2s", "1e", "2 3"), magnitudes beyond the
 * largest double, and nonzero text that would read as 0 (1e-400: below the
 * smallest subnormal, 4.9e-324). Subnormals are numbers like any other.
 *
 * A whole number is a number in the same spelling whose value is whole: "4",
 * "+4", "4.0" and "4e0" are 4, "-0" is 0, "4.5" and "0x4" are not whole
 * numbers. Its value is computed exactly from the digits (never through a
 * double), so every long long is reachable. Register maps also write
 * addresses and words in hexadecimal, as drive manuals do (POPC_PARSE_HEX).
 *
 * No blanks: " 5" is not a number. Blanks around a value belong to the syntax
 * around it, whose reader drops them (popc_trim_blanks, text.h) as libinih
 * does for "key = value" in a scene or map file, popc_scene_set for --set
 * and --vary values, the table and log readers around their cells. */
#ifndef POPC_UTIL_PARSE_H
#define POPC_UTIL_PARSE_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "popc/util/numfmt.h"

typedef enum popc_parse_status {
	POPC_PARSE_OK = 0,
	POPC_PARSE_EMPTY = -1,     /* nothing but blanks */
	POPC_PARSE_INVALID = -2,   /* not a decimal number (hex, inf, nan, junk after it) */
	POPC_PARSE_NOT_WHOLE = -3, /* a number, but a whole number is needed */
	POPC_PARSE_OVERFLOW = -4,  /* beyond the largest double, or the integer type */
	POPC_PARSE_UNDERFLOW = -5, /* nonzero, but below the smallest double: would read as 0 */
	POPC_PARSE_RANGE = -6,     /* a whole number outside [lo, hi] */
} popc_parse_status;

/* Integer flags. POPC_PARSE_HEX: also "0x" or "0X" and hexadecimal digits,
 * no sign (register maps: an address copied from a manual's table).
 * POPC_PARSE_BASE16: hexadecimal digits only, no prefix, no sign (an
 * identifier popc writes itself: the sweep plan's id). */
#define POPC_PARSE_HEX 1u
#define POPC_PARSE_BASE16 2u

/* Nonzero if the number text [s, end) that read as 0.0 has a nonzero digit
 * before its exponent: 1e-400 underflowed, 0e-400 did not. Inline: a log's
 * zero cells ("0") are many. */
static inline int popc_parse_zero_underflows(const char *s, const char *end)
{
	for (const char *p = s; p < end && *p != 'e' && *p != 'E'; p++)
		if (*p >= '1' && *p <= '9')
			return 1;
	return 0;
}

/* popc_parse_double_span inline, for the log reader's loop over every cell. */
static inline popc_parse_status popc_parse_double_exact(const char *s, const char *end,
							double *out)
{
	double v;
	size_t used = popc_parse_double(s, end, &v);
	*out = v;
	if (used == 0 || s + used != end)
		return s == end ? POPC_PARSE_EMPTY : POPC_PARSE_INVALID;
	/* one test for the common case, finite and nonzero: the bits without
	 * the sign, less one, are below those of infinity less one (zero wraps
	 * around to the top) */
	uint64_t bits;
	memcpy(&bits, &v, sizeof bits);
	bits <<= 1;
	if (bits - 1 >= (UINT64_C(0x7ff0000000000000) << 1) - 1) {
		if (bits != 0)
			return POPC_PARSE_OVERFLOW; /* infinity: popc_parse_double makes no NaN */
		/* zero: a text of at most 4 characters ("0.0", "-0.0", as the log
		 * writes them) has no other digit (an underflow needs an exponent
		 * below -323: 6 characters at least), so the log's many zero cells
		 * skip the scan */
		if (end - s > 4 && popc_parse_zero_underflows(s, end))
			return POPC_PARSE_UNDERFLOW;
	}
	return POPC_PARSE_OK;
}

/* A number filling [s, end). *out is set on success only. */
popc_parse_status popc_parse_double_span(const char *s, const char *end, double *out);
/* The same for a NUL-terminated text. */
popc_parse_status popc_parse_double_text(const char *text, double *out);

/* A whole number in [lo, hi] filling [s, end); flags 0 or POPC_PARSE_HEX.
 * *out is set on success only. */
popc_parse_status popc_parse_ll_span(const char *s, const char *end, long long lo, long long hi,
				     unsigned flags, long long *out);
popc_parse_status popc_parse_ll_text(const char *text, long long lo, long long hi,
				     long long *out);
popc_parse_status popc_parse_int_text(const char *text, int lo, int hi, int *out);

/* A whole number in [0, hi]; flags 0, POPC_PARSE_HEX or POPC_PARSE_BASE16.
 * "-0" is 0. */
popc_parse_status popc_parse_u64_span(const char *s, const char *end, uint64_t hi,
				      unsigned flags, uint64_t *out);

#endif
