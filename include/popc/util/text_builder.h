/* A line of text made in a caller's buffer, as snprintf fills one: bytes
 * past the capacity are counted, not written, so that a line too long is
 * found after it is made (len > cap). Made cell by cell by copying: a run's
 * summary row and a sweep's row are made once a run, where snprintf per cell
 * cost tens of thousands of instructions a row (docs/BENCHMARKS.md,
 * section 6). */
#ifndef POPC_UTIL_TEXT_BUILDER_H
#define POPC_UTIL_TEXT_BUILDER_H

#include <stddef.h>
#include <string.h>

#include "popc/util/numfmt.h"

typedef struct popc_text_builder {
	char *buf;
	size_t cap, len;
} popc_text_builder;

static inline void popc_text_put(popc_text_builder *t, const char *s, size_t n)
{
	if (t->len < t->cap) {
		size_t room = t->cap - t->len;
		memcpy(t->buf + t->len, s, n < room ? n : room);
	}
	t->len += n;
}

/* "%lld" of v: its digits, a '-' first when negative. */
static inline void popc_text_put_integer(popc_text_builder *t, long long v)
{
	char digits[24];
	size_t k = sizeof digits;
	unsigned long long m = v < 0 ? 0ULL - (unsigned long long)v : (unsigned long long)v;
	do
		digits[--k] = (char)('0' + m % 10);
	while ((m /= 10) != 0);
	if (v < 0)
		digits[--k] = '-';
	popc_text_put(t, digits + k, sizeof digits - k);
}

/* popc_format_double's text of v, formatted in place when the buffer has
 * the room the formatter may use (POPC_DOUBLE_TEXT_MAX + 1 bytes), so
 * that a number is not copied a second time. */
static inline void popc_text_put_double(popc_text_builder *t, double v)
{
	if (t->len <= t->cap && t->cap - t->len >= POPC_DOUBLE_TEXT_MAX + 1) {
		t->len += popc_format_double(v, t->buf + t->len);
		return;
	}
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	popc_text_put(t, b, popc_format_double(v, b));
}

/* popc_format_double_point's text of v (a decimal point always: "0.0",
 * "5.0", "1.0e+17"): a summary's real cells, which every CSV and JSON
 * reader types floating point even where a column's sampled cells are all
 * integral (DuckDB, pandas, polars typed "0" and "1" as integers). */
static inline void popc_text_put_double_point(popc_text_builder *t, double v)
{
	if (t->len <= t->cap && t->cap - t->len >= POPC_DOUBLE_TEXT_MAX + 1) {
		t->len += popc_format_double_point(v, t->buf + t->len);
		return;
	}
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	popc_text_put(t, b, popc_format_double_point(v, b));
}

#endif
