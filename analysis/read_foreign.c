/* The options and the dispatch of read_foreign.h: which input becomes a CSV
 * stream in a temporary file, and how it is read back. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "read_foreign.h"
#include "popc/log/log_columns.h"
#include "popc/util/parse.h"

int ana_foreign_option(ana_foreign_options *o, int opt, const char *arg, const char *verb)
{
	switch (opt) {
	case ANA_OPT_VARIABLE:
	case ANA_OPT_NAMES:
		if (!arg[0]) {
			fprintf(stderr, "popc-analyze %s: --%s: expected a MAT variable's name\n",
				verb, opt == ANA_OPT_VARIABLE ? "variable" : "names");
			return POPC_EXIT_USAGE;
		}
		if (opt == ANA_OPT_VARIABLE)
			o->variable = arg;
		else
			o->names = arg;
		return 0;
	case ANA_OPT_JOIN:
		if (o->n_join >= ANA_MAX_JOIN) {
			fprintf(stderr, "popc-analyze %s: --join: at most %d files\n", verb,
				ANA_MAX_JOIN);
			return POPC_EXIT_USAGE;
		}
		o->join[o->n_join++] = arg;
		return 0;
	case ANA_OPT_LEVER: {
		double r = 0.0;
		/* a lever arm is a length: positive, and x = r theta must stay finite */
		if (popc_parse_double_text(arg, &r) != 0 || !(r > 0.0 && r <= 1e6) || !isnormal(r)) {
			fprintf(stderr,
				"popc-analyze %s: --lever '%s': expected the lever arm in m, a number "
				"in (0, 1e6] (x = r theta, f = tau / r)\n",
				verb, arg);
			return POPC_EXIT_USAGE;
		}
		o->lever_m = r;
		return 0;
	}
	default:
		return POPC_EXIT_USAGE;
	}
}

int ana_is_mat_file(const char *path)
{
	/* only a regular file is looked into: the first bytes of a pipe
	 * (<(cmd), a FIFO) read here would be lost to the log reader */
	struct stat sb;
	if (strcmp(path, "-") == 0 || stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
		return 0;
	FILE *f = fopen(path, "rb");
	if (!f)
		return 0;
	char head[20];
	size_t n = fread(head, 1, sizeof head, f);
	fclose(f);
	/* both versions' 116-byte text header (v7.3's in HDF5's user block) */
	return n == sizeof head && memcmp(head, "MATLAB ", 7) == 0 &&
	       memcmp(head + 10, " MAT-file", 9) == 0;
}

int ana_foreign_convert(const char *path, const ana_foreign_options *o,
			const popc_log_reader_options *in, popc_log_reader_options *ropt,
			char *tmp, size_t cap, popc_error *err)
{
	tmp[0] = '\0';
	*ropt = *in;
	const int mat = ana_is_mat_file(path);
	if (!mat && o->n_join == 0)
		return 0;
	if (mat && o->n_join > 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: --join joins text files; a MAT file's signals are in one "
				      "variable (--variable)",
				      path);
	const char *dir = getenv("TMPDIR");
	if (!dir || !dir[0])
		dir = "/tmp";
	int w = snprintf(tmp, cap, "%s/popc-analyze-XXXXXX", dir);
	if (w < 0 || (size_t)w >= cap) {
		tmp[0] = '\0';
		return popc_error_set(err, POPC_ERR_IO, "%s: TMPDIR too long", path);
	}
	int fd = mkstemp(tmp);
	if (fd < 0) {
		int e = errno;
		tmp[0] = '\0';
		return popc_error_set(err, POPC_ERR_IO, "%s: cannot make a temporary file in %s: %s",
				      path, dir, strerror(e));
	}
	FILE *out = fdopen(fd, "w");
	if (!out) {
		close(fd);
		unlink(tmp);
		tmp[0] = '\0';
		return popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	}
	int st, names = 1;
	if (mat)
		st = ana_mat_to_csv(path, o, out, err);
	else
		st = ana_join_to_csv(path, o, in, out, &names, err);
	if (fclose(out) != 0 && !st)
		st = popc_error_set(err, POPC_ERR_IO, "%s: cannot write a temporary file in %s",
				    path, dir);
	if (st) {
		unlink(tmp);
		tmp[0] = '\0';
		return st;
	}
	/* the synthetic CSV: ',' and '.', names quoted (or none, joined
	 * headerless files), no comments but '#' at a line's start */
	ropt->delimiter = ',';
	ropt->decimal = '.';
	ropt->comment = '#';
	ropt->no_header = !names;
	return 0;
}

void ana_lever_scales(double lever_m, double *scale, int n_cols, const popc_log_reader *r,
		      int *scaled)
{
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
		const char *unit = popc_log_columns[id].unit;
		int c = popc_log_reader_column(r, popc_log_columns[id].name);
		if (c < 0 || c >= n_cols)
			continue;
		if (strcmp(unit, "m") == 0 || strcmp(unit, "m/s") == 0)
			scale[c] *= lever_m;
		else if (strcmp(unit, "N") == 0)
			scale[c] /= lever_m;
	}
	*scaled = 1;
}

void ana_foreign_provenance(FILE *f, const ana_foreign_options *o)
{
	if (o->lever_m > 0.0)
		fprintf(f, "# lever = %.17g m (a rotary log: x = r theta, v = r omega, f = tau / r)\n",
			o->lever_m);
	if (o->variable)
		fprintf(f, "# mat_variable = %s\n", o->variable);
	for (int i = 0; i < o->n_join; i++)
		fprintf(f, "# joined = %s\n", o->join[i]);
}
