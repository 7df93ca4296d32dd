/* A MAT v5 file's element tree checked before libmatio reads it (read_mat.c).
 *
 * libmatio allocates what an array's header declares before it reads the
 * array's data: a cell or struct nested anywhere in a variable, whose
 * dimensions a few damaged bytes turned into 1.7e9, made it allocate and
 * clear gigabytes for about 10 s on a 3 KB file (found by tests/fuzz's
 * analyze_input). The top-level header check in read_mat.c does not reach
 * a nested header, and libmatio's Mat_VarReadInfo itself walks the nested
 * ones, so the whole tree is walked here first, reading only tags and
 * headers, and every array is held to the bytes that really follow it.
 *
 * The layout is the MAT-File Format of MathWorks (version 5, ch. 1):
 *   - a 128-byte header: text, subsystem offset, version 0x0100 at byte
 *     124, the endian indicator "IM" at 126 ("MI" when written on a machine
 *     of the other byte order);
 *   - data elements, each a tag (u32 type, u32 size in bytes) and its data
 *     padded to 8 bytes, or a small element (size < 5 in the upper 16 bits
 *     of the first word, type in the lower, the data in the second word);
 *   - top-level elements are miMATRIX (14) or miCOMPRESSED (15: a zlib
 *     stream holding one miMATRIX);
 *   - a miMATRIX holds the array flags (miUINT32, 8 bytes: the class in the
 *     low byte, a sparse array's nzmax in the second word), the dimensions
 *     (miINT32), the name (miINT8), then by class: a cell's elements, each a
 *     miMATRIX; a struct's field name length (miINT32), field names (miINT8)
 *     and one miMATRIX per element and field; an object's class name first;
 *     otherwise the data.
 * Every array element takes at least 8 bytes (a cell's or field's tag) or 1
 * byte (a number or character, stored at least as miINT8), so an array
 * declaring more elements than that in the bytes its element holds is a
 * damaged header. For a compressed variable the bytes are the inflated
 * stream's, read through: a declared size the stream does not hold ends the
 * walk at the stream's end. */
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "read_mat_check.h"

#ifdef POPC_HAVE_MATIO

#include <zlib.h>

enum {
	MI_INT8 = 1,
	MI_INT32 = 5,
	MI_UINT32 = 6,
	MI_MATRIX = 14,
	MI_COMPRESSED = 15,
};
enum {
	MX_CELL = 1,
	MX_STRUCT = 2,
	MX_OBJECT = 3,
	MX_SPARSE = 5,
	MX_FUNCTION = 16,
	MX_OPAQUE = 17,
};
#define MAT_MAX_DEPTH 32 /* nested cells and structs (MATLAB has no limit; files go a few deep) */
#define MAT_MAX_DIMS 32

typedef struct mat_walk {
	FILE *f;
	int swap; /* the file's byte order is not this machine's */
	int inflating;
	z_stream z;
	uint64_t z_in_left; /* compressed bytes of the element not yet fed to zlib */
	uint64_t z_len;     /* the element's inflated length (counted first) */
	uint64_t file_size;
	unsigned char in[16384];
	const char *path;
	char var[64]; /* the top-level variable, for messages */
	popc_error *err;
} mat_walk;

typedef struct mat_element {
	uint32_t type;
	uint32_t n;            /* data bytes */
	int small;             /* the data is in word[1] */
	unsigned char word[4]; /* a small element's data */
} mat_element;

static uint32_t u32(const mat_walk *w, const unsigned char *b)
{
	uint32_t v = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
	if (w->swap)
		v = (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
	return v;
}

static uint64_t padded(uint64_t n)
{
	return (n + 7) & ~(uint64_t)7;
}

static int damaged(mat_walk *w, const char *what, double declared, uint64_t bytes)
{
	if (declared >= 0)
		return popc_error_set(w->err, POPC_ERR_INVALID,
				      "%s: variable %s: %s declares %.17g elements in %llu bytes: "
				      "a damaged file",
				      w->path, w->var[0] ? w->var : "?", what, declared,
				      (unsigned long long)bytes);
	return popc_error_set(w->err, POPC_ERR_INVALID, "%s: variable %s: %s: a damaged file",
			      w->path, w->var[0] ? w->var : "?", what);
}

/* The bytes that really follow: of the file, or of the inflated stream. An
 * array is held to these, not to the sizes its tags declare. */
static uint64_t bytes_after(mat_walk *w)
{
	if (w->inflating)
		return w->z_len > w->z.total_out ? w->z_len - (uint64_t)w->z.total_out : 0;
	off_t at = ftello(w->f);
	return at >= 0 && (uint64_t)at < w->file_size ? w->file_size - (uint64_t)at : 0;
}

static uint64_t at_most(uint64_t a, uint64_t b)
{
	return a < b ? a : b;
}

/* n bytes of the element's data into buf (NULL: skipped); 0, 1 when the
 * compressed stream ended first, -1 at the end of the file or on a zlib
 * error */
static int take_bytes(mat_walk *w, void *buf, uint64_t n)
{
	unsigned char scratch[4096];
	while (n > 0) {
		size_t chunk = buf ? (size_t)n : (n < sizeof scratch ? (size_t)n : sizeof scratch);
		unsigned char *to = buf ? buf : scratch;
		if (!w->inflating) {
			if (!buf)
				return fseeko(w->f, (off_t)n, SEEK_CUR) == 0 ? 0 : -1;
			return fread(buf, 1, chunk, w->f) == chunk ? 0 : -1;
		}
		w->z.next_out = to;
		w->z.avail_out = (uInt)chunk;
		while (w->z.avail_out > 0) {
			if (w->z.avail_in == 0 && w->z_in_left > 0) {
				size_t want = w->z_in_left < sizeof w->in ? (size_t)w->z_in_left
									  : sizeof w->in;
				if (fread(w->in, 1, want, w->f) != want)
					return -1;
				w->z_in_left -= want;
				w->z.next_in = w->in;
				w->z.avail_in = (uInt)want;
			}
			int zs = inflate(&w->z, Z_NO_FLUSH);
			if (zs == Z_STREAM_END && w->z.avail_out > 0)
				return 1;
			if (zs != Z_OK && zs != Z_STREAM_END)
				return -1;
			if (zs == Z_OK && w->z.avail_in == 0 && w->z_in_left == 0 && w->z.avail_out > 0)
				return -1; /* the element's compressed bytes are used up */
		}
		if (buf)
			return 0;
		n -= chunk;
	}
	return 0;
}

/* The next element's tag, out of *left bytes; its data bytes (padded) are
 * then counted out of *left too, and must fit. */
static int take_tag(mat_walk *w, uint64_t *left, mat_element *e, const char *what)
{
	unsigned char t[8];
	if (*left < 8)
		return damaged(w, what, -1, 0);
	if (take_bytes(w, t, 8) != 0)
		return damaged(w, "the file ends inside an element", -1, 0);
	*left -= 8;
	uint32_t first = u32(w, t);
	e->small = (first >> 16) != 0;
	if (e->small) {
		e->type = first & 0xffffu;
		e->n = first >> 16;
		if (e->n > 4)
			return damaged(w, what, -1, 0);
		memcpy(e->word, t + 4, 4);
		return 0;
	}
	e->type = first;
	e->n = u32(w, t + 4);
	if (padded(e->n) > *left)
		return damaged(w, "an element larger than the array that holds it", -1, 0);
	/* libmatio allocates a data element's declared bytes before it reads
	 * them (an array's own size is not allocated, and libmatio's compressed
	 * writer declares it too large: below) */
	if (e->type != MI_MATRIX && e->n > bytes_after(w))
		return popc_error_set(w->err, POPC_ERR_INVALID,
				      "%s: variable %s: a data element declares %u bytes and %llu "
				      "follow it: a damaged file",
				      w->path, w->var[0] ? w->var : "?", e->n,
				      (unsigned long long)bytes_after(w));
	*left -= padded(e->n);
	return 0;
}

/* A non-small element's data, skipped or read (up to cap bytes; the rest skipped). */
static int take_data(mat_walk *w, const mat_element *e, void *buf, size_t cap)
{
	if (e->small) {
		if (buf)
			memcpy(buf, e->word, cap < 4 ? cap : 4);
		return 0;
	}
	uint64_t n = padded(e->n);
	uint64_t first = buf ? (cap < n ? cap : n) : 0;
	if ((first && take_bytes(w, buf, first) != 0) || take_bytes(w, NULL, n - first) != 0)
		return damaged(w, "the file ends inside an element", -1, 0);
	return 0;
}

static int walk_matrix(mat_walk *w, uint64_t payload, int depth);

/* count data elements, each held by take_tag to the bytes that follow */
static int walk_data(mat_walk *w, uint64_t *left, int count)
{
	for (int i = 0; i < count; i++) {
		mat_element e = {0};
		int st = take_tag(w, left, &e, "an array without its data");
		if (st || (st = take_data(w, &e, NULL, 0)) != 0)
			return st;
	}
	return 0;
}

/* count arrays (a cell's elements, a struct's fields), each a miMATRIX */
static int walk_children(mat_walk *w, uint64_t *left, double count, int depth)
{
	const uint64_t there = at_most(*left, bytes_after(w));
	if (count * 8.0 > (double)there)
		return damaged(w, depth ? "a nested cell or struct" : "a cell or struct", count,
			       there);
	/* count <= the bytes / 8 here: a whole number that fits */
	const uint64_t n = (uint64_t)count;
	for (uint64_t i = 0; i < n; i++) {
		mat_element e;
		int st = take_tag(w, left, &e, "a cell or field cut short");
		if (st)
			return st;
		if (e.small || e.type != MI_MATRIX)
			return damaged(w, "a cell or field that is not an array", -1, 0);
		if ((st = walk_matrix(w, e.n, depth + 1)) != 0)
			return st;
		if (take_bytes(w, NULL, padded(e.n) - e.n) < 0)
			return damaged(w, "the file ends inside an element", -1, 0);
	}
	return 0;
}

/* One miMATRIX's payload bytes, all consumed. */
static int walk_matrix(mat_walk *w, uint64_t payload, int depth)
{
	if (payload == 0)
		return 0; /* an empty array: a tag without data */
	if (depth > MAT_MAX_DEPTH)
		return damaged(w, "arrays nested more than 32 deep", -1, 0);
	uint64_t left = payload;
	mat_element e;
	unsigned char b[4 * MAT_MAX_DIMS];
	int st = take_tag(w, &left, &e, "an array without its flags");
	if (st)
		return st;
	if (e.small || e.type != MI_UINT32 || e.n != 8)
		return damaged(w, "an array's flags", -1, 0);
	if ((st = take_data(w, &e, b, 8)) != 0)
		return st;
	const unsigned cls = u32(w, b) & 0xffu;
	const int complex = (u32(w, b) & 0x800u) != 0; /* the flags' complex bit */
	const uint32_t nzmax = u32(w, b + 4);

	if ((st = take_tag(w, &left, &e, "an array without its dimensions")) != 0)
		return st;
	if (e.small || e.type != MI_INT32 || e.n % 4 != 0 || e.n < 8 || e.n > sizeof b)
		return damaged(w, "an array's dimensions", -1, 0);
	const uint32_t rank = e.n / 4;
	if ((st = take_data(w, &e, b, sizeof b)) != 0)
		return st;
	double elements = 1.0;
	for (uint32_t i = 0; i < rank; i++) {
		int32_t d = (int32_t)u32(w, b + 4 * i);
		if (d < 0)
			return damaged(w, "a negative dimension", -1, 0);
		elements *= (double)d;
	}

	if ((st = take_tag(w, &left, &e, "an array without its name")) != 0)
		return st;
	if (e.type != MI_INT8)
		return damaged(w, "an array's name", -1, 0);
	char name[sizeof w->var] = "";
	if ((st = take_data(w, &e, name, sizeof name - 1)) != 0)
		return st;
	if (depth == 0) {
		size_t len = e.n < sizeof name - 1 ? e.n : sizeof name - 1;
		name[len] = '\0';
		snprintf(w->var, sizeof w->var, "%s", name);
	}

	switch (cls) {
	case MX_CELL:
		st = walk_children(w, &left, elements, depth);
		break;
	case MX_OBJECT:
	case MX_STRUCT: {
		if (cls == MX_OBJECT &&
		    ((st = take_tag(w, &left, &e, "an object without its class")) != 0 ||
		     (st = take_data(w, &e, NULL, 0)) != 0))
			return st;
		if ((st = take_tag(w, &left, &e, "a struct without its field names")) != 0)
			return st;
		if (e.type != MI_INT32 || e.n != 4)
			return damaged(w, "a struct's field name length", -1, 0);
		if ((st = take_data(w, &e, b, 4)) != 0)
			return st;
		const uint32_t name_len = u32(w, b);
		if ((st = take_tag(w, &left, &e, "a struct without its field names")) != 0 ||
		    (st = take_data(w, &e, NULL, 0)) != 0)
			return st;
		if (e.type != MI_INT8 || (name_len == 0 && e.n != 0))
			return damaged(w, "a struct's field names", -1, 0);
		const double fields = name_len ? (double)(e.n / name_len) : 0.0;
		st = walk_children(w, &left, elements * fields, depth);
		break;
	}
	case MX_SPARSE:
		/* its dimensions are not stored; nzmax values and row indices are */
		if ((double)nzmax > (double)at_most(left, bytes_after(w)))
			st = damaged(w, "a sparse array", (double)nzmax, at_most(left, bytes_after(w)));
		else
			st = walk_data(w, &left, complex ? 4 : 3); /* ir, jc, pr, pi */
		break;
	case MX_FUNCTION:
	case MX_OPAQUE:
		break; /* libmatio reads neither as data */
	default:
		if (elements > (double)at_most(left, bytes_after(w)))
			st = damaged(w, depth ? "a nested array" : "the array", elements,
				     at_most(left, bytes_after(w)));
		else if (elements > 0)
			st = walk_data(w, &left, complex ? 2 : 1); /* real, imaginary */
		break;
	}
	if (st)
		return st;
	/* the data: skipped. A compressed stream may end before the sizes
	 * declared: libmatio's writer declares a char array's data at two bytes
	 * a character and writes UTF-8; libmatio reads such a file, and so the
	 * bound above holds to the bytes that are there, not to the sizes */
	if (take_bytes(w, NULL, left) < 0)
		return damaged(w, "the file ends inside an element", -1, 0);
	return 0;
}

int ana_mat_check_v5(const char *path, popc_error *err)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return popc_error_set(err, POPC_ERR_IO, "%s: cannot open", path);
	mat_walk *w = calloc(1, sizeof *w);
	if (!w) {
		fclose(f);
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	}
	w->f = f;
	w->path = path;
	w->err = err;
	int st = 0;
	struct stat sb;
	unsigned char h[128];
	if (fstat(fileno(f), &sb) != 0 || fread(h, 1, sizeof h, f) != sizeof h)
		goto done; /* too short for v5: libmatio's to refuse */
	if (h[126] == 'M' && h[127] == 'I')
		w->swap = 1;
	else if (!(h[126] == 'I' && h[127] == 'M'))
		goto done; /* not v5 (v4 or v7.3's HDF5): libmatio's */
	const unsigned version = w->swap ? (unsigned)h[124] << 8 | h[125] : (unsigned)h[125] << 8 | h[124];
	if (version != 0x0100)
		goto done;
	const uint64_t size = (uint64_t)sb.st_size;
	w->file_size = size;
	uint64_t pos = 128;
	while (st == 0 && pos + 8 <= size) {
		unsigned char t[8];
		if (fseeko(f, (off_t)pos, SEEK_SET) != 0 || fread(t, 1, 8, f) != 8)
			break;
		const uint32_t type = u32(w, t), n = u32(w, t + 4);
		w->var[0] = '\0';
		if (type == MI_MATRIX || type == MI_COMPRESSED) {
			if ((uint64_t)n > size - pos - 8) {
				st = popc_error_set(err, POPC_ERR_INVALID,
						    "%s: a variable at byte %llu declares %u bytes and "
						    "the file ends %llu bytes after it: a damaged or cut file",
						    path, (unsigned long long)pos, n,
						    (unsigned long long)(size - pos - 8));
				break;
			}
		}
		if (type == MI_MATRIX) {
			st = walk_matrix(w, n, 0);
			pos += 8 + padded(n);
		} else if (type == MI_COMPRESSED) {
			memset(&w->z, 0, sizeof w->z);
			if (inflateInit(&w->z) != Z_OK) {
				st = popc_error_set(err, POPC_ERR_NOMEM, "%s: cannot start zlib", path);
				break;
			}
			w->inflating = 1;
			/* first the stream's length, counted in a scratch buffer
			 * (at most 1032 times the element's bytes: deflate's
			 * largest expansion), then the walk from its start */
			w->z_in_left = n;
			w->z_len = UINT64_MAX;
			if (take_bytes(w, NULL, UINT64_MAX) < 0) {
				inflateEnd(&w->z);
				w->inflating = 0;
				st = popc_error_set(err, POPC_ERR_INVALID,
						    "%s: the compressed variable at byte %llu: not a "
						    "zlib stream: a damaged file",
						    path, (unsigned long long)pos);
				break;
			}
			w->z_len = (uint64_t)w->z.total_out;
			inflateReset(&w->z);
			w->z.avail_in = 0;
			w->z_in_left = n;
			if (fseeko(f, (off_t)(pos + 8), SEEK_SET) != 0) {
				inflateEnd(&w->z);
				st = popc_error_set(err, POPC_ERR_IO, "%s: cannot read", path);
				break;
			}
			uint64_t left = UINT64_MAX;
			mat_element e;
			st = take_tag(w, &left, &e, "a compressed variable without its array");
			if (st == 0 && (e.small || e.type != MI_MATRIX))
				st = damaged(w, "a compressed variable that is not an array", -1, 0);
			if (st == 0)
				st = walk_matrix(w, e.n, 0);
			inflateEnd(&w->z);
			w->inflating = 0;
			pos += 8 + (uint64_t)n;
		} else {
			pos += 8 + padded(n); /* not an array: libmatio skips or refuses it */
		}
	}
done:
	fclose(f);
	free(w);
	return st;
}

#endif
