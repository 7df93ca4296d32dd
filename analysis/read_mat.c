/* MAT files (MATLAB v5, and v7.3 where the libmatio build reads HDF5) to one
 * CSV stream for ana_log_open (read_foreign.h). Two shapes:
 * - a Simulink StructureWithTime: a struct with fields 'time' (N x 1) and
 *   'signals', a struct array whose elements hold 'values' (N x d), and
 *   'label'; the columns are 'time', then each signal's label (label(1) ...
 *   label(d) for d > 1; signals(K) when it has none);
 * - a plain N x M double matrix: columns #1 ... #M, or the strings of a cell
 *   array --names VAR.
 * The doubles are written in their shortest round-trip form: the CSV path
 * reads back the very doubles the file holds. Memory: the variable (a MAT
 * file is read a variable at a time). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "read_foreign.h"
#include "popc/util/numfmt.h"

#ifndef POPC_HAVE_MATIO

int ana_mat_to_csv(const char *path, const ana_foreign_options *o, FILE *out, popc_error *err)
{
	(void)o;
	(void)out;
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: a MAT file, and this popc-analyze was built without libmatio "
			      "(meson option -Dmatio; Debian package libmatio-dev): export the "
			      "variables as CSV, or rebuild with it",
			      path);
}

#else

#include <matio.h>
#include <sys/stat.h>

#include "read_mat_check.h"

/* A variable is read whole (Mat_VarRead allocates what its header declares),
 * so a header is checked first against what the file can hold: deflate,
 * which MAT v5's compressed variables use, expands at most 1032 to 1 (RFC
 * 1951's longest match of 258 bytes per 2 bits), so a variable of more
 * elements than 1032 x the file's size in bytes is a damaged header, not
 * data. Without the check a few damaged bytes of a 600-byte file made
 * libmatio allocate and clear gigabytes (found by tests/fuzz's
 * analyze_input). */
static int read_checked(mat_t *mat, const char *path, const char *name, const char *option,
			matvar_t **out, popc_error *err)
{
	*out = NULL;
	struct stat st;
	if (stat(path, &st) != 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: cannot stat", path);
	matvar_t *info = Mat_VarReadInfo(mat, name);
	if (!info)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: %s %s: no such variable", path,
				      option, name);
	const double budget = 1032.0 * (double)st.st_size;
	double elements = 1.0;
	for (int i = 0; i < info->rank && info->dims; i++)
		elements *= (double)info->dims[i];
	Mat_VarFree(info);
	if (!(elements <= budget))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: %s %s: its header declares %.17g elements, more than a "
				      "file of %lld bytes can hold: a damaged file",
				      path, option, name, elements, (long long)st.st_size);
	*out = Mat_VarRead(mat, name);
	if (!*out)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: %s %s: no such variable", path,
				      option, name);
	return 0;
}

/* A variable's elements as doubles, checked: N x M, real, class double,
 * every value finite. what names it in messages ("x.signals(2).values"). */
static int check_doubles(const char *path, const char *what, const matvar_t *v, size_t *rows,
			 size_t *cols, popc_error *err)
{
	if (v->class_type != MAT_C_DOUBLE || v->isComplex)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: variable %s: %s, expected real doubles (class double: "
				      "convert with double() before saving)",
				      path, what, v->isComplex ? "complex" : "not of class double");
	if (v->rank != 2 || !v->data)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: variable %s: %d dimensions, expected a matrix (N x M)",
				      path, what, v->rank);
	*rows = v->dims[0];
	*cols = v->dims[1];
	if (*rows == 0 || *cols == 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: variable %s: empty (%zu x %zu)",
				      path, what, *rows, *cols);
	const double *d = v->data;
	for (size_t j = 0; j < *cols; j++)
		for (size_t i = 0; i < *rows; i++)
			if (!isfinite(d[i + j * *rows]))
				return popc_error_set(
					err, POPC_ERR_INVALID,
					"%s: variable %s: row %zu, column %zu: %s, not a finite number",
					path, what, i + 1, j + 1,
					isnan(d[i + j * *rows]) ? "NaN" : "an infinity");
	return 0;
}

/* A char variable's text (ASCII; a char matrix is read as one row), or -1. */
static int char_text(const matvar_t *v, char *out, size_t cap)
{
	if (!v || v->class_type != MAT_C_CHAR || !v->data || cap == 0)
		return -1;
	size_t n = v->nbytes / (v->data_size ? (size_t)v->data_size : 1);
	if (n >= cap)
		n = cap - 1;
	for (size_t i = 0; i < n; i++) {
		unsigned c = v->data_size == 2 ? ((const unsigned short *)v->data)[i]
					       : ((const unsigned char *)v->data)[i];
		if (c == 0 || c > 126)
			return -1;
		out[i] = (char)c;
	}
	out[n] = '\0';
	return 0;
}

typedef struct mat_column {
	const double *d; /* column-major: row i at d[i] */
	char name[128];
} mat_column;

static int write_rows(const char *path, const mat_column *c, int n, size_t rows, FILE *out,
		      popc_error *err)
{
	for (int j = 0; j < n; j++) {
		if (j)
			fputc(',', out);
		ana_foreign_put_name(out, c[j].name);
	}
	fputc('\n', out);
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	for (size_t i = 0; i < rows; i++) {
		for (int j = 0; j < n; j++) {
			if (j)
				fputc(',', out);
			popc_format_double(c[j].d[i], b);
			fputs(b, out);
		}
		fputc('\n', out);
	}
	if (ferror(out))
		return popc_error_set(err, POPC_ERR_IO, "%s: cannot write its rows as CSV", path);
	return 0;
}

static int from_structure_with_time(const char *path, const char *name, matvar_t *v, FILE *out,
				    popc_error *err)
{
	mat_column c[POPC_LOG_MAX_COLUMNS];
	int n = 0;
	char what[256];
	size_t rows = 0, cols = 0;
	matvar_t *time = Mat_VarGetStructFieldByName(v, "time", 0);
	matvar_t *signals = Mat_VarGetStructFieldByName(v, "signals", 0);
	if (!time || !signals || signals->class_type != MAT_C_STRUCT)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: variable %s: a struct without %s, expected a Simulink "
				      "StructureWithTime (fields 'time' and 'signals')",
				      path, name, !time ? "field 'time'" : "a struct 'signals'");
	snprintf(what, sizeof what, "%s.time", name);
	int st = check_doubles(path, what, time, &rows, &cols, err);
	if (st)
		return st;
	if (cols != 1)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: variable %s: %zu x %zu, expected a column (N x 1)", path, what,
				      rows, cols);
	c[n].d = time->data;
	snprintf(c[n++].name, sizeof c[0].name, "time");
	size_t k_n = 1;
	for (int i = 0; i < signals->rank; i++)
		k_n *= signals->dims[i];
	for (size_t k = 0; k < k_n; k++) {
		matvar_t *values = Mat_VarGetStructFieldByName(signals, "values", k);
		snprintf(what, sizeof what, "%s.signals(%zu).values", name, k + 1);
		if (!values)
			return popc_error_set(err, POPC_ERR_INVALID, "%s: variable %s: missing", path,
					      what);
		size_t r = 0, d = 0;
		if ((st = check_doubles(path, what, values, &r, &d, err)) != 0)
			return st;
		if (r != rows)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: variable %s: %zu rows, and %s.time has %zu", path,
					      what, r, name, rows);
		char label[100];
		if (char_text(Mat_VarGetStructFieldByName(signals, "label", k), label,
			      sizeof label) != 0 || !label[0])
			snprintf(label, sizeof label, "signals(%zu)", k + 1);
		for (size_t j = 0; j < d; j++) {
			if (n >= POPC_LOG_MAX_COLUMNS)
				return popc_error_set(err, POPC_ERR_INVALID,
						      "%s: variable %s: more than %d columns", path,
						      name, POPC_LOG_MAX_COLUMNS);
			c[n].d = (const double *)values->data + j * rows;
			if (d == 1)
				snprintf(c[n++].name, sizeof c[0].name, "%s", label);
			else
				snprintf(c[n++].name, sizeof c[0].name, "%s(%zu)", label, j + 1);
		}
	}
	return write_rows(path, c, n, rows, out, err);
}

static int from_matrix(const char *path, mat_t *mat, const char *name, const matvar_t *v,
		       const char *names, FILE *out, popc_error *err)
{
	mat_column c[POPC_LOG_MAX_COLUMNS];
	size_t rows = 0, cols = 0;
	int st = check_doubles(path, name, v, &rows, &cols, err);
	if (st)
		return st;
	if (cols > POPC_LOG_MAX_COLUMNS)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: variable %s: %zu columns, at most %d", path, name, cols,
				      POPC_LOG_MAX_COLUMNS);
	matvar_t *nv = NULL;
	if (names) {
		if ((st = read_checked(mat, path, names, "--names", &nv, err)) != 0)
			return st;
		size_t n_names = nv->class_type == MAT_C_CELL && nv->rank == 2
					 ? nv->dims[0] * nv->dims[1] : 0;
		if (n_names != cols) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s: --names %s: %s, expected a cell array of %zu strings "
					    "(one per column of %s)",
					    path, names,
					    nv->class_type != MAT_C_CELL ? "not a cell array"
									 : "another count",
					    cols, name);
			Mat_VarFree(nv);
			return st;
		}
	}
	for (size_t j = 0; j < cols; j++) {
		c[j].d = (const double *)v->data + j * rows;
		if (!nv) {
			snprintf(c[j].name, sizeof c[j].name, "#%zu", j + 1);
		} else if (char_text(Mat_VarGetCell(nv, (int)j), c[j].name, sizeof c[j].name) != 0 ||
			   !c[j].name[0]) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s: --names %s: cell %zu is no text (ASCII characters)",
					    path, names, j + 1);
			Mat_VarFree(nv);
			return st;
		}
	}
	st = write_rows(path, c, (int)cols, rows, out, err);
	Mat_VarFree(nv);
	return st;
}

int ana_mat_to_csv(const char *path, const ana_foreign_options *o, FILE *out, popc_error *err)
{
	mat_t *mat = Mat_Open(path, MAT_ACC_RDONLY);
	if (!mat)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: cannot read as a MAT file (a MAT v7.3 file needs libmatio "
				      "built with HDF5; MATLAB's save -v7 writes one libmatio reads)",
				      path);
	/* every header, nested ones too, against the bytes that follow it,
	 * before libmatio allocates what they declare */
	int st = ana_mat_check_v5(path, err);
	if (st) {
		Mat_Close(mat);
		return st;
	}
	char name[128] = "";
	if (o->variable) {
		snprintf(name, sizeof name, "%s", o->variable);
	} else {
		/* the only variable, or a list to choose from */
		char list[512] = "";
		size_t len = 0;
		int count = 0;
		matvar_t *info;
		while ((info = Mat_VarReadNextInfo(mat)) != NULL) {
			if (count == 0)
				snprintf(name, sizeof name, "%s", info->name ? info->name : "");
			int w = snprintf(list + len, sizeof list - len, " %s",
					 info->name ? info->name : "?");
			if (w > 0 && (size_t)w < sizeof list - len)
				len += (size_t)w;
			count++;
			Mat_VarFree(info);
		}
		if (count != 1) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s: %s: choose one with --variable NAME (the file holds:%s)",
					    path, count ? "several variables" : "no variables",
					    count ? list : " nothing");
			Mat_Close(mat);
			return st;
		}
	}
	matvar_t *v = NULL;
	st = read_checked(mat, path, name, "--variable", &v, err);
	if (st) {
	} else if (v->class_type == MAT_C_STRUCT) {
		st = from_structure_with_time(path, name, v, out, err);
	} else {
		st = from_matrix(path, mat, name, v, o->names, out, err);
	}
	Mat_VarFree(v);
	Mat_Close(mat);
	return st;
}

#endif
