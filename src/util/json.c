/* The JSON writer (json.h). */
#include "popc/util/json.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "popc/util/numfmt.h"

void popc_json_init(popc_json *j, FILE *f)
{
	memset(j, 0, sizeof *j);
	j->f = f;
}

/* The comma before a value (not after a key: the key had it). */
static void before_value(popc_json *j)
{
	if (j->after_key) {
		j->after_key = 0;
		return;
	}
	if (j->has_item[j->depth])
		fputc(',', j->f);
	j->has_item[j->depth] = 1;
}

static void open_nest(popc_json *j, char c)
{
	before_value(j);
	fputc(c, j->f);
	if (j->depth < POPC_JSON_DEPTH_MAX)
		j->depth++;
	j->has_item[j->depth] = 0;
}

static void close_nest(popc_json *j, char c)
{
	fputc(c, j->f);
	if (j->depth > 0)
		j->depth--;
}

void popc_json_begin_object(popc_json *j) { open_nest(j, '{'); }
void popc_json_end_object(popc_json *j) { close_nest(j, '}'); }
void popc_json_begin_array(popc_json *j) { open_nest(j, '['); }
void popc_json_end_array(popc_json *j) { close_nest(j, ']'); }

/* The length of the valid UTF-8 sequence at s (at most n bytes), 0 if none
 * starts there (RFC 3629: no overlong forms, no surrogates, at most U+10FFFF). */
static size_t utf8_length(const unsigned char *s, size_t n)
{
	unsigned c = s[0];
	size_t len;
	unsigned lo = 0x80, hi = 0xbf; /* the second byte's range */
	if (c >= 0xc2 && c <= 0xdf)
		len = 2;
	else if (c >= 0xe0 && c <= 0xef) {
		len = 3;
		if (c == 0xe0)
			lo = 0xa0; /* overlong */
		if (c == 0xed)
			hi = 0x9f; /* surrogates */
	} else if (c >= 0xf0 && c <= 0xf4) {
		len = 4;
		if (c == 0xf0)
			lo = 0x90; /* overlong */
		if (c == 0xf4)
			hi = 0x8f; /* above U+10FFFF */
	} else
		return 0;
	if (n < len || s[1] < lo || s[1] > hi)
		return 0;
	for (size_t k = 2; k < len; k++)
		if (s[k] < 0x80 || s[k] > 0xbf)
			return 0;
	return len;
}

static void put_string(FILE *f, const char *text, size_t n)
{
	const unsigned char *s = (const unsigned char *)text;
	fputc('"', f);
	for (size_t i = 0; i < n;) {
		/* a span of printable ASCII that needs no escape, in one fwrite:
		 * a summary's names and text cells are all such, and a fputc per
		 * byte was most of a sweep's summary.jsonl (docs/BENCHMARKS.md 6) */
		size_t plain = i;
		while (plain < n && s[plain] >= 0x20 && s[plain] < 0x80 && s[plain] != '"' &&
		       s[plain] != '\\')
			plain++;
		if (plain > i) {
			fwrite(s + i, 1, plain - i, f);
			i = plain;
			continue;
		}
		unsigned c = s[i];
		if (c == '"' || c == '\\') {
			fputc('\\', f);
			fputc((int)c, f);
		} else if (c < 0x20) {
			static const char short_form[] = "btn\0fr"; /* \b \t \n, \f \r; 0x0b none */
			if (c >= 0x08 && c <= 0x0d && short_form[c - 0x08])
				fprintf(f, "\\%c", short_form[c - 0x08]);
			else
				fprintf(f, "\\u%04x", c);
		} else if (c < 0x80) {
			fputc((int)c, f);
		} else {
			size_t len = utf8_length(s + i, n - i);
			if (len == 0) {
				fputs("\\ufffd", f); /* not UTF-8: the replacement character */
				i++;
				continue;
			}
			fwrite(s + i, 1, len, f);
			i += len;
			continue;
		}
		i++;
	}
	fputc('"', f);
}

void popc_json_key(popc_json *j, const char *name)
{
	before_value(j);
	put_string(j->f, name, strlen(name));
	fputc(':', j->f);
	j->after_key = 1;
}

void popc_json_string(popc_json *j, const char *s, size_t n)
{
	before_value(j);
	put_string(j->f, s, n);
}

void popc_json_cstring(popc_json *j, const char *s) { popc_json_string(j, s, strlen(s)); }

void popc_json_number(popc_json *j, double v)
{
	before_value(j);
	if (!isfinite(v)) {
		fputs("null", j->f);
		return;
	}
	/* popc_format_double's forms are JSON numbers: "-0", "0.001", "1e-05",
	 * "1.5e+17" (RFC 8259 section 6: an exponent may have a sign and
	 * leading zeros) */
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	popc_format_double(v, b);
	fputs(b, j->f);
}

void popc_json_integer(popc_json *j, long long v)
{
	before_value(j);
	fprintf(j->f, "%lld", v);
}

void popc_json_null(popc_json *j)
{
	before_value(j);
	fputs("null", j->f);
}

/* (is_finite_json_number: below, with the scanner it shares) */
static int is_finite_json_number(const char *s, size_t n);

/* One cell as its kind says (json.h). */
static void put_cell(popc_json *j, popc_json_kind kind, const char *s, size_t n)
{
	if (n == 0) {
		popc_json_null(j);
		return;
	}
	if (kind == POPC_JSON_TEXT) {
		popc_json_string(j, s, n);
		return;
	}
	if (is_finite_json_number(s, n)) {
		before_value(j);
		fwrite(s, 1, n, j->f); /* the text itself: the same double, bit for bit */
		return;
	}
	/* another number text ("+1", ".5", "1."): reformatted */
	double v;
	int reads = popc_parse_double(s, s + n, &v) == n && isfinite(v);
	if (reads) {
		popc_json_number(j, v);
	} else if (kind == POPC_JSON_AUTO) {
		popc_json_string(j, s, n);
	} else {
		popc_json_null(j);
	}
}

/* The next cell of a CSV line at *p: its text unquoted into buf when quoted
 * (RFC 4180), else in place; *p moves past its ',', and *more says whether
 * there was one (another cell follows). */
static const char *next_cell(const char **p, const char *end, char *buf, size_t cap, size_t *len,
			     int *more)
{
	const char *s = *p;
	if (s < end && *s == '"') {
		size_t k = 0;
		for (s++; s < end; s++) {
			if (*s == '"') {
				if (s + 1 < end && s[1] == '"')
					s++; /* "" is one quote */
				else {
					s++;
					break;
				}
			}
			if (k < cap)
				buf[k++] = *s;
		}
		while (s < end && *s != ',')
			s++;
		*more = s < end;
		*p = s < end ? s + 1 : end;
		*len = k;
		return buf;
	}
	const char *e = memchr(s, ',', (size_t)(end - s));
	if (!e)
		e = end;
	*more = e < end;
	*p = e < end ? e + 1 : end;
	*len = (size_t)(e - s);
	return s;
}

/* The end of a CSV line without its line break (LF or CR LF). */
static const char *line_end(const char *row, size_t len)
{
	const char *end = row + len;
	while (end > row && (end[-1] == '\n' || end[-1] == '\r'))
		end--;
	return end;
}

void popc_json_csv_object(FILE *f, int n, const char *const *names, const popc_json_kind *kinds,
			  const char *row, size_t len)
{
	const char *end = line_end(row, len);
	popc_json j;
	popc_json_init(&j, f);
	popc_json_begin_object(&j);
	const char *p = row;
	int more = 1; /* a line holds one cell at least, even an empty one */
	char buf[4096];
	for (int c = 0; c < n; c++) {
		popc_json_key(&j, names[c]);
		if (!more) {
			popc_json_null(&j);
			continue;
		}
		size_t cl;
		const char *cell = next_cell(&p, end, buf, sizeof buf, &cl, &more);
		put_cell(&j, kinds[c], cell, cl);
	}
	popc_json_end_object(&j);
	fputc('\n', f);
}

/* The keys text: for every name its key as written (the comma before it
 * but the first, the escaped name, the colon), each after its length (a
 * uint32_t, copied unaligned): a row copies a key without a strlen. */
char *popc_json_csv_keys(int n, const char *const *names)
{
	char *text = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&text, &len);
	if (!f)
		return NULL;
	for (int c = 0; c < n; c++) {
		if (c > 0)
			fputc(',', f); /* the comma before every key but the first */
		put_string(f, names[c], strlen(names[c]));
		fputc(':', f);
		fputc('\0', f);
	}
	if (fclose(f) != 0) {
		free(text);
		return NULL;
	}
	/* the NULs made lengths: each key's NUL goes, its length comes first */
	char *keys = malloc(len + (size_t)n * (sizeof(uint32_t) - 1) + 1);
	size_t at = 0;
	for (size_t k = 0; keys && k < len;) {
		size_t kl = strlen(text + k);
		uint32_t l32 = (uint32_t)kl; /* a key is shorter than a row: far below 4 GB */
		memcpy(keys + at, &l32, sizeof l32);
		memcpy(keys + at + sizeof l32, text + k, kl);
		at += sizeof l32 + kl;
		k += kl + 1;
	}
	free(text);
	return keys;
}

/* The line of popc_json_csv_object_keyed, made in memory and written with
 * one fwrite when full or done: a stdio call per key and per value was most
 * of a sweep's summary.jsonl (some 50 calls a row). Anything but the common
 * forms (a plain ASCII string, a number) goes through the FILE writers above,
 * after what is held is written, so that the escaping is in one place. */
typedef struct line_out {
	FILE *f;
	size_t len;
	char buf[4096];
} line_out;

static void line_flush(line_out *o)
{
	if (o->len)
		fwrite(o->buf, 1, o->len, o->f);
	o->len = 0;
}

static void line_put(line_out *o, const char *s, size_t n)
{
	if (o->len + n > sizeof o->buf) {
		line_flush(o);
		if (n > sizeof o->buf) {
			fwrite(s, 1, n, o->f);
			return;
		}
	}
	memcpy(o->buf + o->len, s, n);
	o->len += n;
}

/* Is every byte of [s, s + n) printable ASCII needing no escape? */
static int plain_ascii(const char *s, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		unsigned char c = (unsigned char)s[i];
		if (c < 0x20 || c >= 0x80 || c == '"' || c == '\\')
			return 0;
	}
	return 1;
}

/* put_cell's value into the line: the same bytes, the rare forms by put_cell
 * itself (j's comma state: after a key, so it writes no comma). */
static void line_cell(line_out *o, popc_json *j, popc_json_kind kind, const char *s, size_t n)
{
	if (n == 0) {
		line_put(o, "null", 4);
		return;
	}
	int text = kind == POPC_JSON_TEXT;
	if (!text && is_finite_json_number(s, n)) {
		line_put(o, s, n);
		return;
	}
	double v = 0.0;
	int reads = !text && popc_parse_double(s, s + n, &v) == n && isfinite(v);
	if (reads) {
		char b[POPC_DOUBLE_TEXT_MAX + 1];
		popc_format_double(v, b);
		line_put(o, b, strlen(b));
	} else if ((text || kind == POPC_JSON_AUTO) && plain_ascii(s, n)) {
		line_put(o, "\"", 1);
		line_put(o, s, n);
		line_put(o, "\"", 1);
	} else {
		line_flush(o);
		j->after_key = 1;
		put_cell(j, kind, s, n);
	}
}

/* The end of the unquoted cell at s (its ',' or end): a loop, not memchr,
 * as cells are a few bytes and a call per cell cost more than the search. */
static const char *unquoted_end(const char *s, const char *end)
{
	while (s < end && *s != ',')
		s++;
	return s;
}

/* Past the digits at s (before end), eight at a time where eight are there:
 * a summary's numbers are mostly digits, 17 of them in a double's text. */
static const char *skip_digits(const char *s, const char *end)
{
	while (end - s >= 8) {
		uint64_t x;
		memcpy(&x, s, sizeof x);
		/* every byte in '0'..'9': high nibble 3, and no carry out of
		 * the low nibble when 6 is added */
		const uint64_t ones = UINT64_C(0x0101010101010101);
		if ((x & (ones * 0xf0)) != ones * 0x30 || ((x + ones * 6) & (ones * 0xf0)) != ones * 0x30)
			break;
		s += 8;
	}
	while (s < end && *s >= '0' && *s <= '9')
		s++;
	return s;
}

/* RFC 8259's number grammar from s (before end),
 *   -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?
 * in one pass, digits eight at a time: the end of the number, or NULL when
 * none starts at s. *magnitude bounds it: |value| < 10^*magnitude (integer
 * digits plus exponent; the exponent saturated at 100000). */
static const char *scan_json_number(const char *s, const char *end, long long *magnitude)
{
	const char *p = s;
	if (p < end && *p == '-')
		p++;
	if (p == end || *p < '0' || *p > '9')
		return NULL;
	const char *int_start = p;
	p = *p == '0' ? p + 1 : skip_digits(p, end);
	*magnitude = p - int_start;
	if (p < end && *p == '.') {
		const char *f = ++p;
		p = skip_digits(p, end);
		if (p == f)
			return NULL;
	}
	if (p < end && (*p == 'e' || *p == 'E')) {
		p++;
		int negative = p < end && *p == '-';
		if (p < end && (*p == '+' || *p == '-'))
			p++;
		const char *e = p;
		long long x = 0;
		for (; p < end && *p >= '0' && *p <= '9'; p++)
			if (x < 100000)
				x = x * 10 + (*p - '0');
		if (p == e)
			return NULL;
		*magnitude += negative ? -x : x;
	}
	return p;
}

/* Is [s, s + n) a JSON number that reads as a finite double, to be written
 * as its own text (the same double, bit for bit)? The grammar decides by
 * itself where the value is surely below 10^308 (< DBL_MAX, so it cannot
 * round to infinity). Beyond that ("1e400", or 400 digits) the text is read
 * to see: a number that reads as infinity is no JSON number here (readers
 * would turn it into inf). Reading every cell only to decide this was a
 * third of a sweep's summary.jsonl (docs/BENCHMARKS.md section 6). */
static int is_finite_json_number(const char *s, size_t n)
{
	long long magnitude;
	if (scan_json_number(s, s + n, &magnitude) != s + n)
		return 0;
	if (magnitude <= 308)
		return 1;
	double v;
	return popc_parse_double(s, s + n, &v) == n && isfinite(v);
}

/* The unquoted cell at s as a JSON number in one pass (is_finite_json_number
 * and unquoted_end would read it twice): its end when the whole cell follows
 * the grammar and is surely below 10^308, else NULL (the cell is then read
 * the slow way, which decides alike). */
static const char *number_cell_end(const char *s, const char *end)
{
	long long magnitude;
	const char *p = scan_json_number(s, end, &magnitude);
	if (!p || (p < end && *p != ',') || magnitude > 308)
		return NULL;
	return p;
}

void popc_json_csv_object_keyed(FILE *f, int n, const char *keys, const popc_json_kind *kinds,
				const char *row, size_t len)
{
	const char *end = line_end(row, len);
	popc_json j;
	popc_json_init(&j, f);
	line_out o;
	o.f = f;
	o.buf[0] = '{';
	o.len = 1;
	const char *p = row;
	int more = 1; /* a line holds one cell at least, even an empty one */
	char buf[4096];
	for (int c = 0; c < n; c++) {
		uint32_t kl;
		memcpy(&kl, keys, sizeof kl);
		line_put(&o, keys + sizeof kl, kl); /* its comma included: the value follows */
		keys += sizeof kl + kl;
		if (!more) {
			line_put(&o, "null", 4);
			continue;
		}
		const char *q;
		if (kinds[c] != POPC_JSON_TEXT && p < end && *p != ',' &&
		    (q = number_cell_end(p, end)) != NULL) {
			/* the common cell: a number, its text as it is */
			line_put(&o, p, (size_t)(q - p));
			more = q < end;
			p = q + more;
			continue;
		}
		size_t cl;
		const char *cell;
		if (p < end && *p != '"') {
			cell = p;
			p = unquoted_end(p, end);
			cl = (size_t)(p - cell);
			more = p < end;
			p += more;
		} else {
			cell = next_cell(&p, end, buf, sizeof buf, &cl, &more);
		}
		line_cell(&o, &j, kinds[c], cell, cl);
	}
	line_put(&o, "}\n", 2);
	line_flush(&o);
}

int popc_json_csv_names(char *line, const char **names, int cap)
{
	size_t len = strcspn(line, "\r\n");
	line[len] = '\0';
	int n = 0;
	for (char *p = line; n < cap;) {
		names[n++] = p;
		char *comma = strchr(p, ',');
		if (!comma)
			break;
		*comma = '\0';
		p = comma + 1;
	}
	return n;
}

int popc_table_out_begin(popc_table_out *t, FILE *f, int json, const char *header,
			 const char *const *text_names)
{
	memset(t, 0, sizeof *t);
	t->f = f;
	t->json = json;
	if (!json) {
		fprintf(f, "%s\n", header);
		return 0;
	}
	t->names_line = strdup(header);
	if (!t->names_line)
		return -1; /* nothing written, nothing to free */
	t->n = popc_json_csv_names(t->names_line, t->names, POPC_TABLE_COLUMNS_MAX);
	for (int i = 0; i < t->n; i++) {
		t->kinds[i] = POPC_JSON_NUMBER;
		for (int k = 0; text_names && text_names[k]; k++)
			if (strcmp(t->names[i], text_names[k]) == 0)
				t->kinds[i] = POPC_JSON_TEXT;
	}
	return 0;
}

/* JSON: a fresh stream for the rows; when out of memory, /dev/null and the
 * error kept for flush (the caller's writes need a stream either way) */
static void open_rows(popc_table_out *t)
{
	t->rows = open_memstream(&t->buf, &t->len);
	if (!t->rows) {
		t->rows = fopen("/dev/null", "w");
		t->failed = 1;
	}
}

FILE *popc_table_out_row(popc_table_out *t)
{
	if (!t->json)
		return t->f;
	if (!t->rows)
		open_rows(t);
	return t->rows ? t->rows : stderr; /* not even /dev/null: a last resort */
}

int popc_table_out_flush(popc_table_out *t)
{
	if (!t->json || !t->rows)
		return t->failed ? -1 : 0;
	if (fclose(t->rows) != 0)
		t->failed = 1;
	t->rows = NULL;
	/* one object a row: a line ends at a '\n' outside quotes (a quoted cell
	 * may hold one) */
	size_t at = 0;
	int quoted = 0;
	for (size_t k = 0; t->buf && k < t->len; k++) {
		if (t->buf[k] == '"')
			quoted = !quoted;
		else if (t->buf[k] == '\n' && !quoted) {
			popc_json_csv_object(t->f, t->n, t->names, t->kinds, t->buf + at, k - at);
			at = k + 1;
		}
	}
	if (t->buf && at < t->len)
		popc_json_csv_object(t->f, t->n, t->names, t->kinds, t->buf + at, t->len - at);
	free(t->buf);
	t->buf = NULL;
	t->len = 0;
	return t->failed ? -1 : 0;
}
int popc_table_out_end(popc_table_out *t)
{
	int st = popc_table_out_flush(t);
	free(t->names_line);
	t->names_line = NULL;
	return st;
}
