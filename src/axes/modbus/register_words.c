/* Register words (register_map.h): the 16-bit words of a value of each type
 * in either word order, converted by hand (libmodbus 3.1.6's float getters and
 * setters disagree, and MODBUS_GET_INT32_FROM_INT16 is wrong for negative
 * values). */
#include "popc/axes/register_map.h"

#include <math.h>
#include <string.h>

int popc_reg_type_words(popc_reg_type t)
{
	switch (t) {
	case POPC_REG_INT16:
	case POPC_REG_UINT16: return 1;
	case POPC_REG_INT32:
	case POPC_REG_UINT32:
	case POPC_REG_FLOAT32: return 2;
	case POPC_REG_FLOAT64: return 4;
	}
	return 1;
}

const char *const popc_reg_type_names[] = {"int16", "uint16", "int32", "uint32", "float32",
					   "float64", NULL};

const char *popc_reg_type_name(popc_reg_type t)
{
	return (unsigned)t < 6 ? popc_reg_type_names[t] : "?";
}

/* The n words as one unsigned integer, most significant first. */
static uint64_t join_words(const uint16_t *w, int n, popc_word_order o)
{
	uint64_t u = 0;
	for (int i = 0; i < n; i++)
		u = (u << 16) | w[o == POPC_WORDS_HI_LO ? i : n - 1 - i];
	return u;
}

static void split_words(uint64_t u, int n, popc_word_order o, uint16_t *w)
{
	for (int i = n - 1; i >= 0; i--) {
		w[o == POPC_WORDS_HI_LO ? i : n - 1 - i] = (uint16_t)(u & 0xFFFFu);
		u >>= 16;
	}
}

double popc_reg_decode(const uint16_t *words, popc_reg_type t, popc_word_order o)
{
	uint64_t u = join_words(words, popc_reg_type_words(t), o);
	switch (t) {
	case POPC_REG_INT16: return u >= 0x8000u ? (double)u - 65536.0 : (double)u;
	case POPC_REG_UINT16:
	case POPC_REG_UINT32: return (double)u;
	case POPC_REG_INT32: /* two's complement by arithmetic, not by a cast */
		return u >= 0x80000000u ? (double)u - 4294967296.0 : (double)u;
	case POPC_REG_FLOAT32: {
		uint32_t u32 = (uint32_t)u;
		float f;
		memcpy(&f, &u32, sizeof f);
		return (double)f;
	}
	case POPC_REG_FLOAT64: {
		double d;
		memcpy(&d, &u, sizeof d);
		return d;
	}
	}
	return 0.0;
}

/* Integer encodings: nearest integer, saturated to [lo, hi]. */
static int saturate(double v, double lo, double hi, double *out)
{
	if (isnan(v)) {
		*out = 0.0;
		return 1;
	}
	double r = nearbyint(v);
	if (r < lo) {
		*out = lo;
		return 1;
	}
	if (r > hi) {
		*out = hi;
		return 1;
	}
	*out = r;
	return 0;
}

int popc_reg_encode(double v, popc_reg_type t, popc_word_order o, uint16_t *words)
{
	double r;
	int sat = 0;
	uint64_t u = 0;
	switch (t) {
	case POPC_REG_INT16:
		sat = saturate(v, -32768.0, 32767.0, &r);
		u = r < 0 ? (uint64_t)(r + 65536.0) : (uint64_t)r;
		break;
	case POPC_REG_UINT16:
		sat = saturate(v, 0.0, 65535.0, &r);
		u = (uint64_t)r;
		break;
	case POPC_REG_INT32:
		sat = saturate(v, -2147483648.0, 2147483647.0, &r);
		u = r < 0 ? (uint64_t)(r + 4294967296.0) : (uint64_t)r;
		break;
	case POPC_REG_UINT32:
		sat = saturate(v, 0.0, 4294967295.0, &r);
		u = (uint64_t)r;
		break;
	case POPC_REG_FLOAT32: {
		float f = (float)v;
		if (!isfinite(f) && isfinite(v)) {
			f = v > 0 ? 3.4028234663852886e38f : -3.4028234663852886e38f;
			sat = 1;
		}
		uint32_t u32;
		memcpy(&u32, &f, sizeof u32);
		u = u32;
		break;
	}
	case POPC_REG_FLOAT64:
		memcpy(&u, &v, sizeof u);
		break;
	}
	split_words(u, popc_reg_type_words(t), o, words);
	return sat;
}
