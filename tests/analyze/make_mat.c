/* Writes MAT files from a plain CSV log (numbers only, one names line) with
 * libmatio itself, for test_mat.sh: no binary from elsewhere is checked in.
 *
 *   make_mat VERSION KIND IN.csv OUT.mat
 *
 * VERSION: 5 (MAT_FT_MAT5), 5z (the same, every variable compressed) or 73 (MAT_FT_MAT73; exit 77 when this libmatio
 * cannot create one: built without HDF5). KIND:
 *   matrix   variable 'log', N x M doubles, and 'names', a 1 x M cell of the
 *            CSV's column names
 *   swt      variable 'log', a Simulink StructureWithTime: 'time' is the CSV's
 *            first column, one signal per other column, labelled by its name
 *   int32    'log' as matrix, of class int32 (refused: not double)
 *   nan      'log' as matrix with row 5 of column 2 NaN (refused)
 *   cube     'log' as N x M x 1... a 3-D array (refused: not a matrix)
 *   swt_rows 'log' as swt, with the last signal one row short (refused)
 *   swt_huge 'log' as swt, then its nested 'signals' struct array's header
 *            damaged to 1 x 2147483647 elements (refused before libmatio
 *            allocates them: read_mat_check.c); v5 uncompressed only
 *   data_huge as matrix, then the first string of 'names' damaged to
 *            2147483640 bytes (refused likewise); v5 uncompressed only
 * The doubles are those strtod reads from the CSV's shortest round-trip text:
 * the very doubles the CSV path reads. */
#include <matio.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_COLS 16

static double *data;
static size_t n_rows, n_cols;
static char names[MAX_COLS][64];
static int32_t *ints; /* the int32 copy (Mat_VarCreate copies it: freed at the end) */

static int read_csv(const char *path)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	char line[4096];
	size_t cap = 0;
	double *rows = NULL;
	if (!fgets(line, sizeof line, f))
		return -1;
	for (char *tok = strtok(line, ",\n"); tok && n_cols < MAX_COLS; tok = strtok(NULL, ",\n"))
		snprintf(names[n_cols++], sizeof names[0], "%s", tok);
	while (fgets(line, sizeof line, f)) {
		if (n_rows == cap) {
			cap = cap ? 2 * cap : 1024;
			rows = realloc(rows, cap * n_cols * sizeof *rows);
			if (!rows)
				return -1;
		}
		char *p = line;
		for (size_t j = 0; j < n_cols; j++) {
			rows[n_rows * n_cols + j] = strtod(p, &p);
			if (*p == ',')
				p++;
		}
		n_rows++;
	}
	fclose(f);
	/* column-major, as MAT stores a matrix */
	data = malloc(n_rows * n_cols * sizeof *data);
	if (!data)
		return -1;
	for (size_t i = 0; i < n_rows; i++)
		for (size_t j = 0; j < n_cols; j++)
			data[i + j * n_rows] = rows[i * n_cols + j];
	free(rows);
	return 0;
}

static matvar_t *text(const char *name, const char *s)
{
	size_t dims[2] = {1, strlen(s)};
	return Mat_VarCreate(name, MAT_C_CHAR, MAT_T_UINT8, 2, dims, (void *)s, 0);
}

static matvar_t *matrix(const char *kind)
{
	size_t dims[3] = {n_rows, n_cols, 1};
	if (strcmp(kind, "int32") == 0) {
		ints = malloc(n_rows * n_cols * sizeof *ints);
		if (!ints)
			return NULL;
		for (size_t i = 0; i < n_rows * n_cols; i++)
			ints[i] = (int32_t)data[i];
		return Mat_VarCreate("log", MAT_C_INT32, MAT_T_INT32, 2, dims, ints, 0);
	}
	if (strcmp(kind, "nan") == 0)
		data[4 + 1 * n_rows] = (double)NAN;
	if (strcmp(kind, "cube") == 0) {
		dims[1] = 1;
		dims[2] = n_cols;
		return Mat_VarCreate("log", MAT_C_DOUBLE, MAT_T_DOUBLE, 3, dims, data, 0);
	}
	return Mat_VarCreate("log", MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data, 0);
}

static matvar_t *names_cell(void)
{
	size_t dims[2] = {1, n_cols};
	matvar_t *c = Mat_VarCreate("names", MAT_C_CELL, MAT_T_CELL, 2, dims, NULL, 0);
	for (size_t j = 0; j < n_cols; j++)
		Mat_VarSetCell(c, (int)j, text(NULL, names[j]));
	return c;
}

static matvar_t *structure_with_time(int short_last)
{
	const char *top[] = {"time", "signals", "blockName"};
	const char *sig[] = {"values", "dimensions", "label"};
	size_t one[2] = {1, 1}, k_dims[2] = {1, n_cols - 1};
	matvar_t *s = Mat_VarCreateStruct("log", 2, one, top, 3);
	size_t col[2] = {n_rows, 1};
	Mat_VarSetStructFieldByName(s, "time", 0,
				    Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, col, data, 0));
	Mat_VarSetStructFieldByName(s, "blockName", 0, text(NULL, "popc/To Workspace"));
	matvar_t *signals = Mat_VarCreateStruct("signals", 2, k_dims, sig, 3);
	for (size_t j = 1; j < n_cols; j++) {
		size_t d[2] = {n_rows - (short_last && j == n_cols - 1), 1};
		double width = 1.0;
		Mat_VarSetStructFieldByName(
			signals, "values", j - 1,
			Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, d, data + j * n_rows, 0));
		Mat_VarSetStructFieldByName(
			signals, "dimensions", j - 1,
			Mat_VarCreate(NULL, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, one, &width, MAT_F_DONT_COPY_DATA));
		Mat_VarSetStructFieldByName(signals, "label", j - 1, text(NULL, names[j]));
	}
	Mat_VarSetStructFieldByName(s, "signals", 0, signals);
	return s;
}

/* The first miUTF8 data tag (10 00 00 00) in the second variable, past its
 * 40 bytes of tag, flags and dimensions: the first string of
 * 'names', whose size becomes 2147483640 bytes (libmatio allocates a
 * string's declared bytes before it reads them). */
static int damage_first_data(const char *path)
{
	FILE *f = fopen(path, "r+b");
	if (!f)
		return 1;
	static unsigned char buf[1 << 20];
	size_t n = fread(buf, 1, sizeof buf, f);
	int st = 1;
	/* past 'log', the first variable: its tag's size at byte 132 */
	const size_t names_at = n >= 136 ? 136 + ((size_t)buf[132] | (size_t)buf[133] << 8 |
						  (size_t)buf[134] << 16 | (size_t)buf[135] << 24)
					 : n;
	for (size_t i = names_at + 40; i + 8 <= n; i += 8) {
		if (buf[i] != 16 || buf[i + 1] || buf[i + 2] || buf[i + 3])
			continue;
		static const unsigned char huge[4] = {0xf8, 0xff, 0xff, 0x7f};
		st = fseek(f, (long)(i + 4), SEEK_SET) != 0 || fwrite(huge, 1, 4, f) != 4;
		break;
	}
	return fclose(f) != 0 || st;
}

/* The third 2-D dimensions subelement of a v5 file written on this machine
 * (miINT32, 8 bytes: the tag 05 00 00 00 08 00 00 00 in little-endian), past
 * the 128-byte header: in a StructureWithTime, 'log''s (1 x 1), 'time''s
 * (N x 1), then 'signals'' (1 x K), whose K becomes 2147483647. */
static int damage_third_dims(const char *path)
{
	static const unsigned char tag[8] = {5, 0, 0, 0, 8, 0, 0, 0};
	FILE *f = fopen(path, "r+b");
	if (!f)
		return 1;
	unsigned char buf[1 << 16];
	size_t n = fread(buf, 1, sizeof buf, f);
	int seen = 0, st = 1;
	for (size_t i = 128; i + 16 <= n; i += 8) {
		if (memcmp(buf + i, tag, 8) != 0 || ++seen < 3)
			continue;
		static const unsigned char huge[4] = {0xff, 0xff, 0xff, 0x7f};
		st = fseek(f, (long)(i + 12), SEEK_SET) != 0 || fwrite(huge, 1, 4, f) != 4;
		break;
	}
	return fclose(f) != 0 || st;
}

int main(int argc, char **argv)
{
	if (argc != 5) {
		fprintf(stderr, "usage: make_mat 5|5z|73 matrix|swt|int32|nan|cube|swt_rows|swt_huge|data_huge IN.csv OUT.mat\n");
		return 2;
	}
	if (read_csv(argv[3]) != 0 || n_rows < 6 || n_cols < 2) {
		fprintf(stderr, "make_mat: %s: cannot read a CSV of at least 6 rows, 2 columns\n", argv[3]);
		return 1;
	}
	const enum mat_ft ver = strcmp(argv[1], "73") == 0 ? MAT_FT_MAT73 : MAT_FT_MAT5;
	/* 5z: v5 with every variable compressed (zlib), as MATLAB's save writes them */
	const enum matio_compression z =
		strcmp(argv[1], "5z") == 0 ? MAT_COMPRESSION_ZLIB : MAT_COMPRESSION_NONE;
	mat_t *mat = Mat_CreateVer(argv[4], NULL, ver);
	if (!mat) {
		if (ver == MAT_FT_MAT73) {
			fprintf(stderr, "make_mat: this libmatio cannot write MAT v7.3 (no HDF5)\n");
			return 77;
		}
		fprintf(stderr, "make_mat: %s: cannot create\n", argv[4]);
		return 1;
	}
	const char *kind = argv[2];
	const int damaged = strcmp(kind, "swt_huge") == 0 || strcmp(kind, "data_huge") == 0;
	if (damaged && (ver != MAT_FT_MAT5 || z != MAT_COMPRESSION_NONE)) {
		fprintf(stderr, "make_mat: %s: v5 uncompressed only (5)\n", kind);
		return 2;
	}
	matvar_t *v = strncmp(kind, "swt", 3) == 0 ? structure_with_time(strcmp(kind, "swt_rows") == 0)
						   : matrix(kind);
	int st = !v || Mat_VarWrite(mat, v, z) != 0;
	if (!st && (strcmp(kind, "matrix") == 0 || strcmp(kind, "data_huge") == 0)) {
		matvar_t *c = names_cell();
		st = Mat_VarWrite(mat, c, z) != 0;
		Mat_VarFree(c);
	}
	Mat_VarFree(v);
	Mat_Close(mat);
	if (!st && strcmp(kind, "swt_huge") == 0)
		st = damage_third_dims(argv[4]);
	if (!st && strcmp(kind, "data_huge") == 0)
		st = damage_first_data(argv[4]);
	free(data);
	free(ints);
	if (st)
		fprintf(stderr, "make_mat: %s: cannot write\n", argv[4]);
	return st;
}
