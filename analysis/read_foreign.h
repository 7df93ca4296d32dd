/* popc-analyze: recorded device logs that are not one CSV file (issue 27):
 * MAT files (read_mat.c, through libmatio when built with it), signals split
 * across files joined row by row (read_split.c), and rotary logs at a lever
 * (--lever). Each is turned into one plain CSV stream in a temporary file
 * (numbers in popc_format_double's shortest round-trip form, which reads back
 * to the same double) that ana_log_open then reads like any foreign log, so
 * every check and every result is the CSV path's, bit for bit. */
#ifndef POPC_ANALYZE_READ_FOREIGN_H
#define POPC_ANALYZE_READ_FOREIGN_H

#include <stdio.h>

#include "popc/util/error.h"
#include "popc/log/log_reader.h"

#define ANA_MAX_JOIN 8

typedef struct ana_foreign_options {
	const char *variable;  /* --variable NAME: the MAT variable (NULL: the only one) */
	const char *names;     /* --names VAR: a MAT cell array naming a matrix's columns */
	int n_join;            /* --join FILE: files joined to the log row by row */
	const char *join[ANA_MAX_JOIN];
	double lever_m;        /* --lever R: rotary log, x = R theta, f = tau / R (0: none) */
} ana_foreign_options;

/* Long options (their ids follow ana_input_options' ANA_OPT_*). */
enum {
	ANA_OPT_VARIABLE = 1100,
	ANA_OPT_NAMES,
	ANA_OPT_JOIN,
	ANA_OPT_LEVER,
};
#define ANA_FOREIGN_OPTION_CASES                                             \
	case ANA_OPT_VARIABLE:                                               \
	case ANA_OPT_NAMES:                                                  \
	case ANA_OPT_JOIN:                                                   \
	case ANA_OPT_LEVER
#define ANA_FOREIGN_OPTION_TABLE                                             \
	{"variable", 0, ANA_OPT_VARIABLE, "NAME"},                           \
	{"names", 0, ANA_OPT_NAMES, "VAR"},                                  \
	{"join", 0, ANA_OPT_JOIN, "FILE"},                                   \
	{"lever", 0, ANA_OPT_LEVER, "R"}
#define ANA_FOREIGN_HELP                                                                       \
	"\nMAT files, signals split across files, rotary logs (with the options above):\n"     \
	"  --variable NAME          a MAT file's variable to read: a matrix (N x M doubles)\n"  \
	"                           or a Simulink StructureWithTime (default: the file's\n"    \
	"                           only variable); its columns are 'time' and the signals'\n" \
	"                           labels, a matrix's #1, #2, ... or --names'\n"               \
	"  --names VAR              a MAT cell array of strings naming the matrix's columns\n"  \
	"  --join FILE              FILE holds more columns of the same rows (a signal per\n"   \
	"                           file): joined to the log row by row (repeatable; with\n"    \
	"                           --no-header the columns are numbered across the files)\n"  \
	"  --lever R                a rotary log in rad and N m at a lever of R m: x = R\n"    \
	"                           theta, v = R omega, f = tau / R (W and E_ref stay J)\n"

/* Handles one ANA_FOREIGN option; 0, or 2 after printing why. */
int ana_foreign_option(ana_foreign_options *o, int opt, const char *arg, const char *verb);

/* 1 when PATH starts as a MAT file does ("MATLAB 5.0 MAT-file", "MATLAB 7.3
 * MAT-file": the text header both versions begin with). */
int ana_is_mat_file(const char *path);

/* When PATH is a MAT file or o joins files: writes the log as one CSV into a
 * new temporary file, its name in tmp (removed by the caller after opening),
 * and sets *ropt to the options that read it (names line, ',', '.', the
 * --column map of in). Else tmp[0] = 0 and nothing is done. Errors name the
 * file and the variable or line. */
int ana_foreign_convert(const char *path, const ana_foreign_options *o,
			const popc_log_reader_options *in, popc_log_reader_options *ropt,
			char *tmp, size_t cap, popc_error *err);

/* MAT file to CSV (read_mat.c; without libmatio: refused, exit 2). */
int ana_mat_to_csv(const char *path, const ana_foreign_options *o, FILE *out, popc_error *err);

/* Split files to CSV (read_split.c): path, then o->join[], row by row. */
int ana_join_to_csv(const char *path, const ana_foreign_options *o,
		    const popc_log_reader_options *in, FILE *out, int *wrote_names,
		    popc_error *err);

/* --lever R: multiplies the scale of each of popc's columns the log has by
 * its factor at the lever, from the column's unit: m and m/s times R (x =
 * R theta, v = R omega), N divided by R (f = tau / R), J and s as they are
 * (tau theta = f x). *scaled = 1. */
void ana_lever_scales(double lever_m, double *scale, int n_cols, const popc_log_reader *r,
		      int *scaled);

/* The provenance lines of an output (only the options given, so every other
 * output stays as it was): "# lever = R m ...", "# mat_variable = NAME",
 * "# joined = FILE" per --join. */
void ana_foreign_provenance(FILE *f, const ana_foreign_options *o);

/* The file's column header text in a synthetic CSV: quoted ("#1" would read
 * as a comment otherwise, a label may hold ','). Inline: read_mat.c and
 * read_split.c use it, and read_foreign.c calls them (no call cycle). */
static inline void ana_foreign_put_name(FILE *f, const char *name)
{
	fputc('"', f);
	for (const char *p = name; *p; p++) {
		if (*p == '"')
			fputc('"', f);
		fputc(*p, f);
	}
	fputc('"', f);
}

#endif
