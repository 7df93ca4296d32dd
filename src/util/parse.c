/* Strict number parsing (parse.h): the grammar is popc_parse_double's, the
 * whole text; whole numbers are computed exactly from their digits. */
#include "popc/util/parse.h"

#include <limits.h>
#include <string.h>

popc_parse_status popc_parse_double_span(const char *s, const char *end, double *out)
{
	double v;
	popc_parse_status st = popc_parse_double_exact(s, end, &v);
	if (st == POPC_PARSE_OK)
		*out = v;
	return st;
}

popc_parse_status popc_parse_double_text(const char *text, double *out)
{
	return popc_parse_double_span(text, text + strlen(text), out);
}

static int is_digit(char c)
{
	return c >= '0' && c <= '9';
}

static int hex_value(char c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	if (c >= 'a' && c <= 'f')
		return c - 'a' + 10;
	if (c >= 'A' && c <= 'F')
		return c - 'A' + 10;
	return -1;
}

/* Hexadecimal digits filling [s, end), at least one. */
static popc_parse_status hex_magnitude(const char *s, const char *end, uint64_t *mag)
{
	if (s == end)
		return POPC_PARSE_INVALID;
	uint64_t u = 0;
	for (; s < end; s++) {
		int d = hex_value(*s);
		if (d < 0)
			return POPC_PARSE_INVALID;
		if (u > (UINT64_MAX >> 4))
			return POPC_PARSE_OVERFLOW;
		u = u << 4 | (uint64_t)d;
	}
	*mag = u;
	return POPC_PARSE_OK;
}

/* The sign and magnitude of the whole number filling [s, end), exactly.
 * The digits D (whole part, then fraction) stand for D * 10^q, q = exponent
 * - fraction length; without its leading zeros and with its trailing zeros
 * moved into q, D ends in a nonzero digit, so the value is whole iff q >= 0. */
static popc_parse_status whole_magnitude(const char *s, const char *end, unsigned flags,
					 int *neg, uint64_t *mag)
{
	*neg = 0;
	if (s == end)
		return POPC_PARSE_EMPTY;
	if (flags & POPC_PARSE_BASE16)
		return hex_magnitude(s, end, mag);
	if ((flags & POPC_PARSE_HEX) && end - s >= 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X'))
		return hex_magnitude(s + 2, end, mag);
	double ignored;
	size_t used = popc_parse_double(s, end, &ignored);
	if (used == 0 || s + used != end)
		return POPC_PARSE_INVALID;

	/* popc_parse_double took it all: sign? digits ('.' digits?)? ([eE] sign? digits)? */
	const char *p = s;
	if (*p == '-' || *p == '+')
		*neg = *p++ == '-';
	const char *ip = p;
	while (p < end && is_digit(*p))
		p++;
	long long n_int = p - ip, n_frac = 0;
	const char *fp = p;
	if (p < end && *p == '.') {
		fp = ++p;
		while (p < end && is_digit(*p))
			p++;
		n_frac = p - fp;
	}
	long long exp10 = 0; /* saturated: beyond 20 digits any exponent overflows */
	if (p < end) {
		p++; /* e or E */
		int eneg = 0;
		if (*p == '-' || *p == '+')
			eneg = *p++ == '-';
		for (; p < end; p++)
			if (exp10 < 1000000)
				exp10 = exp10 * 10 + (*p - '0');
		if (eneg)
			exp10 = -exp10;
	}
#define DIGIT(i) ((i) < n_int ? ip[(i)] : fp[(i) - n_int])
	long long first = 0, last = n_int + n_frac;
	while (first < last && DIGIT(first) == '0')
		first++;
	if (first == last) {
		*mag = 0; /* "0", "-0.000", "0e99" */
		return POPC_PARSE_OK;
	}
	long long q = exp10 - n_frac;
	while (DIGIT(last - 1) == '0') {
		last--;
		q++;
	}
	if (q < 0)
		return POPC_PARSE_NOT_WHOLE;
	if (last - first + q > 20) /* at least 10^20 > UINT64_MAX */
		return POPC_PARSE_OVERFLOW;
	uint64_t u = 0;
	for (long long i = first; i < last + q; i++) {
		unsigned d = i < last ? (unsigned)(DIGIT(i) - '0') : 0;
		if (u > (UINT64_MAX - d) / 10)
			return POPC_PARSE_OVERFLOW;
		u = u * 10 + d;
	}
#undef DIGIT
	*mag = u;
	return POPC_PARSE_OK;
}

popc_parse_status popc_parse_ll_span(const char *s, const char *end, long long lo, long long hi,
				     unsigned flags, long long *out)
{
	int neg;
	uint64_t mag;
	popc_parse_status st = whole_magnitude(s, end, flags, &neg, &mag);
	if (st != POPC_PARSE_OK)
		return st;
	long long v;
	if (neg) {
		if (mag > (uint64_t)LLONG_MAX + 1)
			return POPC_PARSE_OVERFLOW;
		v = mag == 0 ? 0 : -(long long)(mag - 1) - 1;
	} else {
		if (mag > (uint64_t)LLONG_MAX)
			return POPC_PARSE_OVERFLOW;
		v = (long long)mag;
	}
	if (v < lo || v > hi)
		return POPC_PARSE_RANGE;
	*out = v;
	return POPC_PARSE_OK;
}

popc_parse_status popc_parse_ll_text(const char *text, long long lo, long long hi, long long *out)
{
	return popc_parse_ll_span(text, text + strlen(text), lo, hi, 0, out);
}

popc_parse_status popc_parse_int_text(const char *text, int lo, int hi, int *out)
{
	long long v;
	popc_parse_status st = popc_parse_ll_text(text, lo, hi, &v);
	if (st == POPC_PARSE_OK)
		*out = (int)v;
	return st;
}

popc_parse_status popc_parse_u64_span(const char *s, const char *end, uint64_t hi,
				      unsigned flags, uint64_t *out)
{
	int neg;
	uint64_t mag;
	popc_parse_status st = whole_magnitude(s, end, flags, &neg, &mag);
	if (st != POPC_PARSE_OK)
		return st;
	if ((neg && mag != 0) || mag > hi)
		return POPC_PARSE_RANGE;
	*out = mag;
	return POPC_PARSE_OK;
}
