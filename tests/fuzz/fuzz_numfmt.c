/* numfmt harnesses: popc_parse_double against strtod, bit for bit, and
 * popc_format_double's shortest text parsed back exactly (numfmt.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "popc/util/numfmt.h"

static uint64_t bits_of(double d)
{
	uint64_t b;
	memcpy(&b, &d, sizeof b);
	return b;
}

/* Text popc's grammar and strtod's agree on: after an optional sign, a digit
 * or a '.', and no hex prefix (strtod also reads hex, inf, nan and leading
 * blanks, which popc refuses by design). */
static int decimal_start(const char *s, size_t n)
{
	size_t i = 0;
	if (i < n && (s[i] == '+' || s[i] == '-'))
		i++;
	if (i >= n || !((s[i] >= '0' && s[i] <= '9') || s[i] == '.'))
		return 0;
	if (s[i] == '0' && i + 1 < n && (s[i + 1] == 'x' || s[i + 1] == 'X'))
		return -1; /* hex: popc reads the "0" before the 'x' */
	return 1;
}

int popc_fuzz_numfmt_parse(const uint8_t *data, size_t size)
{
	/* popc parses [s, s + size) with no terminator: ASan sees a read past
	 * the end; strtod gets a NUL-terminated copy */
	const char *s = (const char *)data;
	char *z = malloc(size + 1);
	if (!z)
		return 0;
	memcpy(z, data, size);
	z[size] = '\0';
	double v = 0.0;
	size_t used = popc_parse_double(s, s + size, &v);
	if (used > size)
		popc_fuzz_fail(data, size, "consumed %zu of %zu bytes", used, size);
	const int start = decimal_start(s, size);
	if (start < 0) {
		size_t zero = s[0] == '0' ? 1 : 2;
		if (used != zero || v != 0.0 || !!signbit(v) != (s[0] == '-'))
			popc_fuzz_fail(data, size, "hex text: %zu bytes read as %g", used, v);
	} else if (start) {
		char *end;
		double ref = strtod(z, &end);
		size_t ref_used = (size_t)(end - z);
		/* a NUL byte ends strtod's text early; compare up to it */
		size_t text_len = strlen(z);
		if (used != ref_used && !(ref_used == text_len && used > text_len))
			popc_fuzz_fail(data, size, "consumed %zu bytes, strtod %zu", used, ref_used);
		if (used > 0 && used == ref_used && bits_of(v) != bits_of(ref))
			popc_fuzz_fail(data, size, "%.17g (0x%016llx), strtod %.17g (0x%016llx)", v,
				       (unsigned long long)bits_of(v), ref,
				       (unsigned long long)bits_of(ref));
	} else if (used != 0) {
		popc_fuzz_fail(data, size, "consumed %zu bytes of text that is no decimal number",
			       used);
	}
	free(z);
	return 0;
}

/* Significant digits of a formatted finite number ("-1.25e-05": 3). */
static int sig_digits(const char *t)
{
	int n = 0, leading = 1, pending_zeros = 0;
	for (const char *p = t; *p && *p != 'e'; p++) {
		if (*p < '0' || *p > '9')
			continue;
		if (leading && *p == '0')
			continue;
		leading = 0;
		if (*p == '0') {
			pending_zeros++;
		} else {
			n += pending_zeros + 1;
			pending_zeros = 0;
		}
	}
	/* trailing zeros of an integer ("123000") are not significant: the
	 * shortest form would be 1.23e+05 only past 17 digits; count them out */
	return n ? n : 1;
}

static void check_double(const uint8_t *data, size_t size, double v)
{
	char buf[POPC_DOUBLE_TEXT_MAX + 16];
	memset(buf, 'X', sizeof buf);
	size_t len = popc_format_double(v, buf);
	if (len > POPC_DOUBLE_TEXT_MAX || strlen(buf) != len)
		popc_fuzz_fail(data, size, "0x%016llx: text of %zu characters (max %d)",
			       (unsigned long long)bits_of(v), len, POPC_DOUBLE_TEXT_MAX);
	if (isnan(v)) {
		if (strcmp(buf, "nan") != 0)
			popc_fuzz_fail(data, size, "NaN written as '%s'", buf);
		return;
	}
	if (isinf(v)) {
		if (strcmp(buf, v > 0 ? "inf" : "-inf") != 0)
			popc_fuzz_fail(data, size, "infinity written as '%s'", buf);
		return;
	}
	double back = 0.0;
	size_t used = popc_parse_double(buf, buf + len, &back);
	if (used != len || bits_of(back) != bits_of(v))
		popc_fuzz_fail(data, size, "0x%016llx -> '%s' -> 0x%016llx (%zu of %zu read)",
			       (unsigned long long)bits_of(v), buf, (unsigned long long)bits_of(back),
			       used, len);
	double ref = strtod(buf, NULL);
	if (bits_of(ref) != bits_of(v))
		popc_fuzz_fail(data, size, "0x%016llx -> '%s', which strtod reads as 0x%016llx",
			       (unsigned long long)bits_of(v), buf, (unsigned long long)bits_of(ref));
	/* shortest: one digit fewer does not round-trip */
	int d = sig_digits(buf);
	if (d > 1) {
		char shorter[400];
		snprintf(shorter, sizeof shorter, "%.*g", d - 1, v);
		if (bits_of(strtod(shorter, NULL)) == bits_of(v))
			popc_fuzz_fail(data, size, "0x%016llx -> '%s' (%d digits), but '%s' reads back",
				       (unsigned long long)bits_of(v), buf, d, shorter);
	}
	/* 17 digits needed: the text of %.17g */
	if (d == 17) {
		char g17[400];
		snprintf(g17, sizeof g17, "%.17g", v);
		if (strcmp(g17, buf) != 0)
			popc_fuzz_fail(data, size, "0x%016llx -> '%s', %%.17g '%s'",
				       (unsigned long long)bits_of(v), buf, g17);
	}
}

int popc_fuzz_numfmt_format(const uint8_t *data, size_t size)
{
	/* every 8 bytes are one double's bits; a shorter tail fills the low
	 * mantissa bits of 1.0 and of a subnormal */
	size_t i = 0;
	for (; i + 8 <= size && i < 8 * 64; i += 8) {
		uint64_t b;
		memcpy(&b, data + i, sizeof b);
		double v;
		memcpy(&v, &b, sizeof v);
		check_double(data, size, v);
	}
	if (i < size) {
		uint64_t tail = 0;
		memcpy(&tail, data + i, size - i < 8 ? size - i : 8);
		double v;
		uint64_t b = UINT64_C(0x3ff0000000000000) | (tail & UINT64_C(0xfffffffffffff));
		memcpy(&v, &b, sizeof v);
		check_double(data, size, v);
		b = tail & UINT64_C(0x800fffffffffffff);
		memcpy(&v, &b, sizeof v);
		check_double(data, size, v);
	}
	return 0;
}
