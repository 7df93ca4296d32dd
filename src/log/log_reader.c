/* Streaming CSV log reader (log_reader.h). */
#include "popc/log/log_reader.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "popc/log/log_columns.h"
#include "popc/util/numfmt.h"
#include "popc/util/parse.h"
#include "popc/util/text.h"

#define READ_BLOCK (1u << 20)
#define LINE_MAX_BYTES (1u << 20)

/* Reads more of the file. Returns 0, -1 when a line outgrows the buffer, or
 * -2 on a read error (errno kept in r->read_errno): a failed read is no end of
 * file, or a disk error would pass for a short log. */
static int fill(popc_log_reader *r)
{
	if (r->start > 0) {
		memmove(r->buf, r->buf + r->start, r->end - r->start);
		r->end -= r->start;
		r->start = 0;
	}
	if (r->end == r->cap) {
		if (r->cap >= LINE_MAX_BYTES + READ_BLOCK)
			return -1;
		size_t ncap = r->cap * 2;
		char *nb = realloc(r->buf, ncap + 1);
		if (!nb)
			return -1;
		r->buf = nb;
		r->cap = ncap;
	}
	errno = 0;
	size_t n = fread(r->buf + r->end, 1, r->cap - r->end, r->f);
	r->end += n;
	if (n == 0) {
		if (ferror(r->f)) {
			r->read_errno = errno ? errno : EIO;
			return -2;
		}
		r->eof = 1;
	}
	return 0;
}

/* Next line without its end-of-line; *complete = 0 if the file ended without a
 * newline. Returns 0 at the end of the file, -1 on a line too long, -2 on a
 * read error, -3 on a NUL byte in the line (if check_nul: the rows' fast path
 * leaves that check to when it fails, as a NUL byte fails it). */
static int next_line(popc_log_reader *r, char **line, size_t *len, int *complete, int check_nul)
{
	for (;;) {
		char *nl = memchr(r->buf + r->start, '\n', r->end - r->start);
		if (nl) {
			*line = r->buf + r->start;
			*len = (size_t)(nl - *line);
			r->start += *len + 1;
			*complete = 1;
			break;
		}
		if (r->eof) {
			if (r->start == r->end)
				return 0;
			*line = r->buf + r->start;
			*len = r->end - r->start;
			r->start = r->end;
			*complete = 0;
			break;
		}
		int st = fill(r);
		if (st != 0)
			return st;
	}
	/* the cells are C strings: past a NUL byte the rest of the line would
	 * be dropped unseen (a cell "0\0junk" read as 0, cells after it missing) */
	if (check_nul && memchr(*line, '\0', *len))
		return -3;
	if (*len && (*line)[*len - 1] == '\r')
		(*len)--;
	(*line)[*len] = '\0'; /* the buffer has one spare byte past cap */
	r->lineno++;
	return 1;
}

/* The error of a failed next_line (got < 0). */
static int line_error(const popc_log_reader *r, int got, popc_error *err)
{
	if (got == -2)
		return popc_error_set(err, POPC_ERR_IO, "%s:%lld: read error: %s", r->path,
				      r->lineno + 1, strerror(r->read_errno));
	if (got == -3)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%lld: a NUL byte in the line (a log is a text file)", r->path,
				      r->lineno + 1);
	return popc_error_set(err, POPC_ERR_INVALID, "%s:%lld: line longer than %u bytes", r->path,
			      r->lineno + 1, LINE_MAX_BYTES + READ_BLOCK);
}

static char *dupn(const char *s, size_t n)
{
	char *d = malloc(n + 1);
	if (d) {
		memcpy(d, s, n);
		d[n] = '\0';
	}
	return d;
}

/* "# key = value" provenance; section headers qualify the keys after them. */
static void header_comment(popc_log_reader *r, const char *text, char *section, size_t cap)
{
	const char *s = text, *e = text + strlen(text);
	popc_trim_blanks(&s, &e);
	if (s < e && *s == '[' && e[-1] == ']') {
		snprintf(section, cap, "%.*s", (int)(e - s - 2), s + 1);
		return;
	}
	const char *eq = memchr(s, '=', (size_t)(e - s));
	if (!eq || r->n_keys >= POPC_LOG_MAX_HEADER_KEYS)
		return;
	const char *ks = s, *ke = eq, *vs = eq + 1, *ve = e;
	popc_trim_blanks(&ks, &ke);
	popc_trim_blanks(&vs, &ve);
	char key[160];
	if (section[0])
		snprintf(key, sizeof key, "%s.%.*s", section, (int)(ke - ks), ks);
	else
		snprintf(key, sizeof key, "%.*s", (int)(ke - ks), ks);
	/* "stop" is popc's end-of-log key wherever it stands (no scene section
	 * has one) */
	if (ke - ks == 4 && memcmp(ks, "stop", 4) == 0) {
		snprintf(r->stop_reason, sizeof r->stop_reason, "%.*s", (int)(ve - vs), vs);
		return;
	}
	r->key_line[r->n_keys] = r->lineno;
	r->key[r->n_keys] = dupn(key, strlen(key));
	r->value[r->n_keys] = dupn(vs, (size_t)(ve - vs));
	if (r->key[r->n_keys] && r->value[r->n_keys])
		r->n_keys++;
}

/* Whether line is blank or a comment; a comment's "key = value" is recorded
 * (header_comment), before the rows and after them. */
static int blank_or_comment(popc_log_reader *r, const char *line)
{
	const char *s = line;
	while (*s == ' ' || *s == '\t')
		s++;
	if (*s && *s != r->comment)
		return 0;
	if (*s)
		header_comment(r, s + 1, r->section, sizeof r->section);
	return 1;
}

int popc_log_reader_position(const char *header)
{
	if (header[0] != '#' || header[1] < '1' || header[1] > '9' ||
	    header[1 + strspn(header + 1, "0123456789")] != '\0' || strlen(header) > 6)
		return 0;
	return atoi(header + 1);
}

/* A delimiter or comment mark as the options spell it ('tab', 'space'), in
 * buf (at least 6 bytes). */
static const char *char_name(char c, char *buf)
{
	snprintf(buf, 6, "%s", c == '\t' ? "tab" : c == ' ' ? "space" : (char[]){c, '\0'});
	return buf;
}

static char detect_delimiter(const char *line, int decimal_comma)
{
	const char cand[3] = {',', ';', '\t'};
	int best = -1, best_n = 0;
	for (int i = decimal_comma ? 1 : 0; i < 3; i++) {
		int n = 0;
		for (const char *p = line; *p; p++)
			n += *p == cand[i];
		if (n > best_n) {
			best_n = n;
			best = i;
		}
	}
	return best < 0 ? ' ' : cand[best];
}

/* Splits line at the delimiter (runs of blanks for ' '). A cell in double
 * quotes (RFC 4180, as spreadsheets and pandas write text) is the text inside
 * them and may hold the delimiter; "" inside is a quote. Blanks around a cell
 * are no part of it, but under a tab delimiter a tab is no blank: "1\t\t2" is
 * three cells, the middle one empty (skipped as padding, it would move every
 * later cell one column left). Returns the number of cells, of which the first
 * max are stored: more than max is the caller's error, with the count. */
static int split(char *line, char delim, const char **cs, const char **ce, int max)
{
	int n = 0;
	char *p = line;
	if (delim == ' ') {
		for (;;) {
			while (*p == ' ' || *p == '\t')
				p++;
			if (!*p)
				return n;
			if (n < max)
				cs[n] = p;
			while (*p && *p != ' ' && *p != '\t')
				p++;
			if (n < max)
				ce[n] = p;
			n++;
		}
	}
	for (;;) {
		while (*p == ' ' || (*p == '\t' && delim != '\t'))
			p++;
		char *q = NULL;
		if (*p == '"') {
			/* the closing quote: one not followed by another */
			for (q = p + 1; (q = strchr(q, '"')) != NULL && q[1] == '"'; q += 2)
				;
			/* only blanks may follow it: "1e-5"9 is no quoted 1e-5 (the 9
			 * was dropped), it is text as it is */
			const char *a = q ? q + 1 : NULL;
			while (a && (*a == ' ' || (*a == '\t' && delim != '\t')))
				a++;
			if (a && *a && *a != delim)
				q = NULL;
		}
		char *d;
		const char *s, *e;
		if (q) {
			s = p + 1;
			e = q;
			d = strchr(q + 1, delim);
		} else { /* unquoted, or a quote never closed (or followed by text):
			  * the text as it is */
			s = p;
			d = strchr(p, delim);
			e = d ? d : p + strlen(p);
			popc_trim_blanks(&s, &e);
		}
		if (n < max) {
			cs[n] = s;
			ce[n] = e;
		}
		n++;
		if (!d)
			return n;
		p = d + 1;
	}
}

/* The one pass parses the columns read and skips the others to their
 * delimiter (popc_parse_double_line_skip). */
static void set_skip(popc_log_reader *r)
{
	for (int i = 0; i < r->n_cols; i++)
		r->skip[i] = r->parse[i] != 1;
}

int popc_log_reader_open(popc_log_reader *r, const char *path, const popc_log_reader_options *opt,
			 popc_error *err)
{
	memset(r, 0, sizeof *r);
	snprintf(r->path, sizeof r->path, "%s", path);
	if (opt)
		r->opt = *opt;
	r->comment = r->opt.comment ? r->opt.comment : '#';
	r->t_col = -1;
	if (strcmp(path, "-") == 0) {
		r->f = stdin;
	} else {
		r->f = fopen(path, "rb");
		if (!r->f)
			return popc_error_set(err, POPC_ERR_IO, "%s: cannot open: %s", path,
					      strerror(errno));
		r->owns_file = 1;
	}
	/* a directory opens for reading but is no log (and must not read as an
	 * empty one) */
	struct stat sb;
	if (fstat(fileno(r->f), &sb) == 0 && S_ISDIR(sb.st_mode)) {
		popc_log_reader_close(r);
		return popc_error_set(err, POPC_ERR_IO, "%s: is a directory, not a log file", path);
	}
	r->cap = READ_BLOCK;
	r->buf = malloc(r->cap + 1);
	if (!r->buf) {
		popc_log_reader_close(r);
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	}
	char *line;
	size_t len;
	int complete;
	for (;;) {
		int got = next_line(r, &line, &len, &complete, 1);
		if (got < 0) {
			int st = line_error(r, got, err);
			popc_log_reader_close(r);
			return st;
		}
		if (got == 0) {
			popc_log_reader_close(r);
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %s: no column names line", path,
					      r->lineno ? "only comments" : "empty file");
		}
		/* a UTF-8 byte order mark before the first line (a CSV saved by
		 * Excel as "CSV UTF-8") is no part of the first name */
		if (r->lineno == 1 && len >= 3 && memcmp(line, "\xEF\xBB\xBF", 3) == 0) {
			line += 3;
			len -= 3;
		}
		/* next_line took a CR before the LF; one left is inside the line: a
		 * CR-only file is one line here (the rows are not checked: a CR in
		 * one breaks its cells anyway) */
		if (memchr(line, '\r', len)) {
			popc_log_reader_close(r);
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: a carriage return (CR) inside the line: lines end "
					      "with LF or CR LF; a file with CR-only line ends (classic Mac "
					      "OS) reads as one line (convert it: tr '\\r' '\\n')",
					      path, r->lineno);
		}
		if (blank_or_comment(r, line))
			continue;
		break;
	}
	/* the header's sections end with it: "# stop = ..." after the rows is
	 * no key of the scene's last section */
	r->section[0] = '\0';
	const int decimal_comma = r->opt.decimal == ',';
	if ((r->opt.decimal && r->opt.decimal != '.' && !decimal_comma) ||
	    (decimal_comma && r->opt.delimiter == ',')) {
		popc_log_reader_close(r);
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: decimal mark '%c' with delimiter '%c': the decimal mark is "
				      "'.' or ',', and ',' needs another delimiter (';', tab)",
				      path, r->opt.decimal, r->opt.delimiter ? r->opt.delimiter : ',');
	}
	r->delimiter = r->opt.delimiter ? r->opt.delimiter : detect_delimiter(line, decimal_comma);
	/* a comment mark that is also the delimiter makes every row whose first
	 * cell is empty (",1e-5,0.1") a comment, dropped unseen */
	if (r->comment == r->delimiter) {
		char given[64] = "", name[6];
		if (!r->opt.delimiter)
			snprintf(given, sizeof given, " (detected from line %lld)", r->lineno);
		popc_error_set(err, POPC_ERR_INVALID,
			       "%s: the comment mark '%s'%s is also the delimiter%s: a row whose "
			       "first cell is empty would read as a comment; give another --comment "
			       "or --delimiter",
			       path, char_name(r->comment, name), r->opt.comment ? "" : " (the default)",
			       given);
		popc_log_reader_close(r);
		return POPC_ERR_INVALID;
	}
	const char *cs[POPC_LOG_MAX_COLUMNS], *ce[POPC_LOG_MAX_COLUMNS];
	int n = split(line, r->delimiter, cs, ce, POPC_LOG_MAX_COLUMNS);
	if (n <= 0 || n > POPC_LOG_MAX_COLUMNS) {
		popc_log_reader_close(r);
		if (n > 0)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: %d columns, more than %d", path, r->lineno, n,
					      POPC_LOG_MAX_COLUMNS);
		return popc_error_set(err, POPC_ERR_INVALID, "%s:%lld: %s", path, r->lineno,
				      r->opt.no_header ? "no cells in the first row"
						       : "no column names");
	}
	if (r->opt.no_header) {
		/* the line is the first row: kept to be returned by the first
		 * popc_log_reader_next (the buffer moves on under it) */
		r->first_row = dupn(line, len);
		if (!r->first_row) {
			popc_log_reader_close(r);
			return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
		}
		r->first_row_pending = 1;
		r->first_row_complete = complete;
	}
	for (int i = 0; i < n; i++) {
		char position[16];
		if (r->opt.no_header) /* named by position, as --column #N finds them */
			snprintf(position, sizeof position, "#%d", i + 1);
		r->col_name[i] = r->opt.no_header ? dupn(position, strlen(position))
						  : dupn(cs[i], (size_t)(ce[i] - cs[i]));
		if (!r->col_name[i]) {
			popc_log_reader_close(r);
			return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
		}
		r->n_cols = i + 1;
	}
	if (!r->opt.no_header) {
		r->names_line = r->lineno;
		r->names_numeric = 1;
		for (int i = 0; i < r->n_cols && r->names_numeric; i++) {
			double v;
			const char *name = r->col_name[i];
			r->names_numeric = popc_parse_double_exact(name, name + strlen(name), &v) ==
					   POPC_PARSE_OK;
		}
		if (r->names_numeric)
			snprintf(r->names_hint, sizeof r->names_hint,
				 " (line %lld, read as the column names, holds only numbers: a file "
				 "without a column names line needs --no-header)",
				 r->lineno);
	}
	/* a repeated name would make a column lookup pick one of two silently; an
	 * empty name (pandas' index column, a trailing delimiter) is never looked
	 * up, so it may repeat */
	for (int i = 1; i < r->n_cols; i++)
		for (int j = 0; j < i; j++)
			if (r->col_name[i][0] && strcmp(r->col_name[i], r->col_name[j]) == 0) {
				popc_error_set(err, POPC_ERR_INVALID,
					       "%s:%lld: column %d (%s) repeats the name of column %d "
					       "(line %lld): column names must be unique%s",
					       path, r->lineno, i + 1, r->col_name[i], j + 1, r->lineno,
					       r->names_hint);
				popc_log_reader_close(r);
				return POPC_ERR_INVALID;
			}
	for (int i = 0; i < r->opt.n_map; i++)
		if (popc_log_reader_column(r, r->opt.map_name[i]) < 0) {
			const char *h = r->opt.map_header[i];
			char hint[200] = "";
			if (popc_log_reader_position(h) > 0)
				snprintf(hint, sizeof hint, " (it has %d column%s)", r->n_cols,
					 r->n_cols == 1 ? "" : "s");
			else if (h[strspn(h, "0123456789")] == '\0')
				/* what a user of a headerless file types first */
				snprintf(hint, sizeof hint,
					 " (a column by position is '#%s'%s)", h,
					 r->opt.no_header ? ""
							  : "; a file without a column names line "
							    "needs --no-header");
			else if (r->names_numeric)
				snprintf(hint, sizeof hint, "%s", r->names_hint);
			popc_error_set(err, POPC_ERR_INVALID,
				       "%s:%lld: --column %s=%s: the file has no column '%s'%s", path,
				       r->lineno, r->opt.map_name[i], h, h, hint);
			popc_log_reader_close(r);
			return POPC_ERR_INVALID;
		}
	/* a headerless file read without no_header, its columns all mapped by
	 * position: its first row is taken for the names, which no lookup by
	 * name needs, and would be lost without a word. A mapping found by a
	 * number as its name says the line is names (pandas writes 0,1,2). */
	if (r->names_numeric && r->opt.n_map > 0) {
		int by_name = 0;
		for (int i = 0; i < r->opt.n_map; i++)
			by_name |= popc_log_reader_position(r->opt.map_header[i]) == 0;
		if (!by_name) {
			popc_error_set(err, POPC_ERR_INVALID,
				       "%s:%lld: the first line that is no comment holds only numbers, "
				       "and every --column maps a position: it would be read as the "
				       "column names, not as a row (a file without a column names line "
				       "needs --no-header; if the numbers are the names, map a column "
				       "by its name, --column x=%s)",
				       path, r->lineno, r->col_name[r->n_cols > 1 ? 1 : 0]);
			popc_log_reader_close(r);
			return POPC_ERR_INVALID;
		}
	}
	/* rows of plain numbers are read in one pass (popc_parse_double_row)
	 * unless the split needs more than the delimiter: runs of blanks, a
	 * decimal comma, or a comment mark that could begin a number or stand
	 * in a skipped cell (popc_number_chars_end) */
	r->fast_rows = r->delimiter != ' ' && r->opt.decimal != ',' &&
		       !strchr("0123456789.+-eE", r->comment);
	r->t_col = popc_log_reader_column(r, popc_log_columns[POPC_LOG_COLUMN_T].name);
	for (int i = 0; i < r->n_cols; i++)
		r->parse[i] = 1;
	set_skip(r);
	r->popc_log = popc_log_reader_header(r, "format") != NULL;
	/* popc writes each key once: twice, the scene would take the last value
	 * and a header lookup the first (a foreign log's comments are free text) */
	for (int i = 1; r->popc_log && i < r->n_keys; i++)
		for (int j = 0; j < i; j++)
			if (strcmp(r->key[i], r->key[j]) == 0) {
				popc_error_set(err, POPC_ERR_INVALID,
					       "%s:%lld: header key %s given twice (first on line %lld)",
					       path, r->key_line[i], r->key[i], r->key_line[j]);
				popc_log_reader_close(r);
				return POPC_ERR_INVALID;
			}
	return 0;
}

int popc_log_reader_use_columns(popc_log_reader *r, const int *cols, int n)
{
	for (int i = 0; i < r->n_cols; i++)
		r->parse[i] = 0;
	for (int i = 0; i < n; i++) {
		if (cols[i] < 0 || cols[i] >= r->n_cols)
			return POPC_ERR_INVALID;
		r->parse[cols[i]] = 1;
	}
	if (r->t_col >= 0)
		r->parse[r->t_col] = 1; /* time must increase, whoever reads it */
	set_skip(r);
	return 0;
}

int popc_log_reader_check_columns(popc_log_reader *r, const int *cols, int n)
{
	for (int i = 0; i < n; i++)
		if (cols[i] < 0 || cols[i] >= r->n_cols)
			return POPC_ERR_INVALID;
	for (int i = 0; i < n; i++)
		if (cols[i] != r->t_col)
			r->parse[cols[i]] = 2;
	set_skip(r);
	return 0;
}

/* A cell of a column that is checked but not read: one or more of a
 * number's characters (and the decimal comma where it is the mark). */
static int number_chars_only(const popc_log_reader *r, const char *s, const char *e)
{
	if (s == e)
		return 0;
	for (const char *p = popc_number_chars_end(s, e); p < e; p = popc_number_chars_end(p + 1, e))
		if (!(*p == ',' && r->opt.decimal == ','))
			return 0;
	return 1;
}

int popc_log_reader_next(popc_log_reader *r, double *values, popc_error *err)
{
	char *line;
	size_t len;
	int complete, tried_one_pass = 0;
	for (;;) {
		if (r->first_row_pending) { /* no_header: read at open, r->lineno is its line */
			r->first_row_pending = 0;
			line = r->first_row;
			complete = r->first_row_complete;
			break;
		}
		/* the common row straight from the buffer, its end found by the
		 * parse (no search for the newline first); a row the buffer cuts,
		 * or any other line, is read by next_line below */
		const char *row_end;
		if (r->fast_rows &&
		    popc_parse_double_line_skip(r->buf + r->start, r->buf + r->end, r->delimiter,
						values, r->n_cols, &row_end, r->memo,
						r->skip) == r->n_cols) {
			r->start = (size_t)(row_end - r->buf) + (*row_end == '\r' ? 2 : 1);
			r->lineno++;
			goto row_read; /* the skipped columns are NaN */
		}
		int got = next_line(r, &line, &len, &complete, !r->fast_rows);
		if (got < 0)
			return line_error(r, got, err);
		if (got == 0)
			return 0;
		/* the common row, numbers and delimiters only, in one pass; any
		 * other line (a comment, a quote, a blank, an error) goes the way
		 * below, which checks everything */
		if (r->fast_rows && complete) {
			if (popc_parse_double_row(line, line + len, r->delimiter, values,
						  r->n_cols) == r->n_cols) {
				for (int i = 0; i < r->n_cols; i++)
					if (r->parse[i] != 1)
						values[i] = (double)NAN;
				goto row_read;
			}
			tried_one_pass = 1;
		}
		if (r->fast_rows && memchr(line, '\0', len))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: a NUL byte in the line (a log is a text file)",
					      r->path, r->lineno);
		/* popc ends every line with a newline: a last line without one was
		 * cut (a full disk under an older popc, a killed process, a copy
		 * cut short), even if its cells are all there (its last number may
		 * be short). The whole rows before it are the log: the end, noted
		 * (popc_log_reader_unfinished). */
		if (!complete && r->popc_log) {
			r->cut_line = r->lineno;
			return 0;
		}
		if (blank_or_comment(r, line))
			continue;
		break;
	}
	const char *cs[POPC_LOG_MAX_COLUMNS], *ce[POPC_LOG_MAX_COLUMNS];
	int n = split(line, r->delimiter, cs, ce, r->n_cols);
	if (n != r->n_cols)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%lld: %d cells, expected %d (%s)", r->path, r->lineno, n,
				      r->n_cols,
				      n > r->n_cols ? "more cells than columns"
				      : complete    ? "short row"
						    : "truncated last line");
	for (int i = 0; i < n; i++) {
		if (!r->parse[i]) {
			values[i] = (double)NAN; /* a column nobody reads: text is fine */
			continue;
		}
		if (r->parse[i] == 2) {
			values[i] = (double)NAN; /* checked, not read */
			if (!number_chars_only(r, cs[i], ce[i]))
				return popc_error_set(
					err, POPC_ERR_INVALID,
					"%s:%lld: column %d (%s): %s '%.*s'", r->path, r->lineno, i + 1,
					r->col_name[i],
					cs[i] == ce[i] ? "empty cell" : "not a number",
					(int)(ce[i] - cs[i] > 40 ? 40 : ce[i] - cs[i]), cs[i]);
			continue;
		}
		/* a decimal comma reads as the point it stands for, in place (the
		 * cell is in this line's buffer), and is put back for messages */
		char *cell = line + (cs[i] - line), *comma[2];
		int n_comma = 0;
		if (r->opt.decimal == ',') {
			if (memchr(cell, '.', (size_t)(ce[i] - cs[i])))
				return popc_error_set(
					err, POPC_ERR_INVALID,
					"%s:%lld: column %d (%s): '%.*s' has a '.', but the decimal mark is ','",
					r->path, r->lineno, i + 1, r->col_name[i],
					(int)(ce[i] - cs[i] > 40 ? 40 : ce[i] - cs[i]), cs[i]);
			for (char *p = cell; p < cell + (ce[i] - cs[i]) && n_comma < 2; p++)
				if (*p == ',') {
					comma[n_comma++] = p;
					*p = '.';
				}
		}
		/* a number as everywhere (popc/util/parse.h), inline */
		popc_parse_status ps = popc_parse_double_exact(cs[i], ce[i], &values[i]);
		for (int k = 0; k < n_comma; k++)
			*comma[k] = ',';
		if (ps != POPC_PARSE_OK) {
			int is_nan = ce[i] - cs[i] >= 3 && (strncmp(cs[i], "nan", 3) == 0 ||
							    strncmp(cs[i], "NaN", 3) == 0 ||
							    strncmp(cs[i], "-nan", 4) == 0);
			return popc_error_set(
				err, POPC_ERR_INVALID, "%s:%lld: column %d (%s): %s '%.*s'", r->path,
				r->lineno, i + 1, r->col_name[i],
				ps == POPC_PARSE_EMPTY ? "empty cell"
				: is_nan ? "NaN is not allowed"
				: ps == POPC_PARSE_UNDERFLOW
					? "below the smallest double (4.9e-324), it would read as 0:"
					: "not a finite number",
				(int)(ce[i] - cs[i] > 40 ? 40 : ce[i] - cs[i]), cs[i]);
		}
	}
	/* a good row that is not plain numbers (quoted, blanks, a text column
	 * nobody reads): the file's rows are likely all so, and the one-pass
	 * attempt would be wasted on each; the split reads them from here */
	if (tried_one_pass)
		r->fast_rows = 0;
row_read:
	if (r->t_col >= 0) {
		double t = values[r->t_col];
		if (r->rows > 0 && !(t > r->t_prev))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (%s): time %.17g does not increase "
					      "(previous %.17g)",
					      r->path, r->lineno, r->t_col + 1, r->col_name[r->t_col], t,
					      r->t_prev);
		r->t_prev = t;
	}
	r->rows++;
	r->last_row_line = r->lineno;
	return 1;
}

int popc_log_reader_unfinished(const popc_log_reader *r)
{
	if (!r->popc_log)
		return 0;
	if (r->cut_line)
		return POPC_LOG_CUT_LINE;
	return r->stop_reason[0] ? 0 : POPC_LOG_NO_STOP;
}

int popc_log_reader_column(const popc_log_reader *r, const char *name)
{
	const char *header = name;
	int mapped = 0;
	for (int i = 0; i < r->opt.n_map; i++)
		if (strcmp(r->opt.map_name[i], name) == 0) {
			header = r->opt.map_header[i];
			mapped = 1;
		}
	if (!header[0])
		return -1;
	const int position = mapped ? popc_log_reader_position(header) : 0;
	if (position)
		return position <= r->n_cols ? position - 1 : -1;
	for (int i = 0; i < r->n_cols; i++)
		if (strcmp(r->col_name[i], header) == 0)
			return i;
	return -1;
}

int popc_log_reader_require(const popc_log_reader *r, const char *name, int *index,
			    popc_error *err)
{
	*index = popc_log_reader_column(r, name);
	if (*index >= 0)
		return 0;
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: missing column '%s' (map another header to it with --column %s=HEADER)%s",
			      r->path, name, name, r->names_hint);
}

const char *popc_log_reader_header_hint(const popc_log_reader *r)
{
	return r->names_hint;
}

long long popc_log_reader_header_line(const popc_log_reader *r, const char *key)
{
	for (int i = 0; i < r->n_keys; i++)
		if (strcmp(r->key[i], key) == 0)
			return r->key_line[i];
	return 0;
}

const char *popc_log_reader_header(const popc_log_reader *r, const char *key)
{
	for (int i = 0; i < r->n_keys; i++)
		if (strcmp(r->key[i], key) == 0)
			return r->value[i];
	return NULL;
}

int popc_log_reader_scene(const popc_log_reader *r, popc_scene *s, popc_error *err)
{
	for (int i = 0; i < r->n_keys; i++) {
		const char *dot = strchr(r->key[i], '.');
		if (!dot)
			continue;
		char section[64], who[200];
		snprintf(section, sizeof section, "%.*s", (int)(dot - r->key[i]), r->key[i]);
		/* messages name the key as the header spells it ("run.rate = 1e7:
		 * out of range"), not as --set would */
		snprintf(who, sizeof who, "%s =", r->key[i]);
		popc_error e;
		int st = popc_scene_set_option(s, who, section, dot + 1, r->value[i], &e);
		if (st) {
			const char *msg = e.msg;
			if (strncmp(msg, "--set: ", 7) == 0) /* unknown_key's prefix */
				msg += 7;
			return popc_error_set(err, st, "%s:%lld: header: %s", r->path, r->key_line[i],
					      msg);
		}
	}
	return 0;
}

void popc_log_reader_close(popc_log_reader *r)
{
	if (r->f && r->owns_file)
		fclose(r->f);
	r->f = NULL;
	for (int i = 0; i < r->n_cols; i++)
		free(r->col_name[i]);
	for (int i = 0; i < r->n_keys; i++) {
		free(r->key[i]);
		free(r->value[i]);
	}
	r->n_cols = r->n_keys = 0;
	free(r->buf);
	r->buf = NULL;
	free(r->first_row);
	r->first_row = NULL;
	r->first_row_pending = 0;
}

int popc_log_reader_add_mapping(popc_log_reader_options *opt, char *text, popc_error *err)
{
	char *eq = strchr(text, '=');
	if (!eq || eq == text || !eq[1])
		return popc_error_set(err, POPC_ERR_INVALID, "--column '%s': expected NAME=HEADER", text);
	if (opt->n_map >= POPC_LOG_MAX_COLUMNS)
		return popc_error_set(err, POPC_ERR_INVALID, "--column: at most %d mappings",
				      POPC_LOG_MAX_COLUMNS);
	*eq = '\0';
	opt->map_name[opt->n_map] = text;
	opt->map_header[opt->n_map] = eq + 1;
	opt->n_map++;
	return 0;
}
