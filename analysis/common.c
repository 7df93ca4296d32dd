/* Shared helpers of popc-analyze (analyze.h): input options, the log wrapper
 * that derives missing columns, error printing. */
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "analyze.h"
#include "popc/core/encoder.h"
#include "popc/programs/arg_list.h"
#include "popc/programs/env.h"
#include "popc/util/numfmt.h"
#include "popc/util/same_file.h"
#include "popc/util/parse.h"
#include "popc/scene/from_scene.h"

int ana_fail(const char *verb, int status, const popc_error *err)
{
	fprintf(stderr, "popc-analyze %s: %s\n", verb, err->msg);
	/* like diff: 1 is "found something" (chatter, a --check difference), so
	 * every failure to read or write is trouble, 2 */
	(void)status;
	return POPC_EXIT_USAGE;
}

int ana_output_is_input(const char *out, char *const *inputs, int n)
{
	for (int i = 0; i < n; i++)
		if (popc_same_file(out, inputs[i]))
			return i;
	return -1;
}

void ana_put_csv_text(FILE *f, const char *text)
{
	if (!strpbrk(text, ",\"\r\n")) {
		fputs(text, f);
		return;
	}
	fputc('"', f);
	for (const char *p = text; *p; p++) {
		if (*p == '"')
			fputc('"', f);
		fputc(*p, f);
	}
	fputc('"', f);
}

void ana_put_md_text(FILE *f, const char *text)
{
	for (const char *p = text; *p; p++) {
		if (*p == '|')
			fputc('\\', f);
		fputc(*p, f);
	}
}

void ana_put_double(FILE *f, double v)
{
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	popc_format_double(v, b);
	fputs(b, f);
}

void ana_put_double_point(FILE *f, double v)
{
	char b[POPC_DOUBLE_TEXT_MAX + 1];
	popc_format_double_point(v, b);
	fputs(b, f);
}

static int parse_char_option(const char *arg, char *out)
{
	if (strcmp(arg, "tab") == 0 || strcmp(arg, "\\t") == 0 || strcmp(arg, "\t") == 0)
		*out = '\t';
	else if (strcmp(arg, "space") == 0 || strcmp(arg, " ") == 0)
		*out = ' ';
	else if (strlen(arg) == 1 && arg[0] != '\n' && arg[0] != '\r' &&
		 !(arg[0] >= '0' && arg[0] <= '9') && arg[0] != '.' && arg[0] != '-' &&
		 arg[0] != '+')
		*out = arg[0];
	else
		return -1;
	return 0;
}

/* popc's column names (the --column and --scale NAMEs) */
static int column_name_known(const char *name)
{
	return popc_log_column_find(name) >= 0;
}

/* A column that --scale may scale: a number in a unit, not a bit set */
static int column_scalable(const char *name)
{
	const int id = popc_log_column_find(name);
	return id >= 0 && popc_log_columns[id].format != POPC_LOG_CELL_FLAGS;
}

/* The names of popc's columns, each after a space; scalable_only: those
 * --scale takes */
static const char *column_names(char *buf, size_t cap, int scalable_only)
{
	size_t len = 0;
	buf[0] = '\0';
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
		const char *name = popc_log_columns[id].name;
		if (scalable_only && !column_scalable(name))
			continue;
		int n = snprintf(buf + len, cap - len, " %s", name);
		if (n < 0 || (size_t)n >= cap - len)
			break;
		len += (size_t)n;
	}
	return buf;
}

static int scale_option(ana_input_options *o, char *arg, const char *verb)
{
	char *eq = strchr(arg, '=');
	double f = 0.0;
	int bad_number = 1;
	if (eq) {
		*eq = '\0';
		bad_number = popc_parse_double_text(eq + 1, &f) != 0;
	}
	if (!eq || bad_number || f == 0.0 || !column_scalable(arg) ||
	    (popc_log_column_find(arg) == POPC_LOG_COLUMN_T && f < 0.0)) {
		char names[POPC_LOG_NAMES_LINE_MAX];
		fprintf(stderr,
			"popc-analyze %s: --scale %s%s%s: expected NAME=FACTOR, NAME one of%s, "
			"FACTOR a finite nonzero number (> 0 for t)\n",
			verb, arg, eq ? "=" : "", eq ? eq + 1 : "", column_names(names, sizeof names, 1));
		if (eq)
			*eq = '=';
		return POPC_EXIT_USAGE;
	}
	for (int i = 0; i < o->n_scales; i++)
		if (strcmp(o->scale_name[i], arg) == 0) {
			fprintf(stderr, "popc-analyze %s: --scale %s=%s: %s is already scaled\n", verb, arg,
				eq + 1, arg);
			*eq = '=';
			return POPC_EXIT_USAGE;
		}
	if (o->n_scales >= ANA_MAX_SCALES) {
		fprintf(stderr, "popc-analyze %s: --scale: at most %d\n", verb, ANA_MAX_SCALES);
		return POPC_EXIT_USAGE;
	}
	o->scale_name[o->n_scales] = arg; /* arg stays split at '=': the name */
	o->scale[o->n_scales++] = f;
	return 0;
}

const popc_option ana_input_option_table[] = {
	{"column", 0, ANA_OPT_COLUMN, "NAME=HEADER"},
	{"delimiter", 0, ANA_OPT_DELIMITER, "C"},
	{"comment", 0, ANA_OPT_COMMENT, "C"},
	{"set", 0, ANA_OPT_SET, "KEY=VALUE"},
	{"scale", 0, ANA_OPT_SCALE, "NAME=FACTOR"},
	{"decimal", 0, ANA_OPT_DECIMAL, "C"},
	{"no-header", 0, ANA_OPT_NO_HEADER, NULL},
	{"jitter", 0, ANA_OPT_JITTER, "FRACTION"},
	ANA_FOREIGN_OPTION_TABLE,
	POPC_OPTION_END,
};

void ana_getopt_tables(const popc_option *const *tables, struct option opts[ANA_MAX_OPTIONS],
		       char shorts[2 * ANA_MAX_OPTIONS])
{
	/* the sizes hold every verb's tables: one that outgrows them is a
	 * programming error, which the first run of that verb shows */
	if (popc_options_getopt(tables, opts, ANA_MAX_OPTIONS, shorts, 2 * ANA_MAX_OPTIONS) != 0)
		abort();
}

int ana_input_option(ana_input_options *o, int opt, char *arg, const char *verb)
{
	popc_error err;
	switch (opt) {
	case ANA_OPT_COLUMN: {
		if (popc_log_reader_add_mapping(&o->reader, arg, &err) != 0) {
			fprintf(stderr, "popc-analyze %s: %s\n", verb, err.msg);
			return POPC_EXIT_USAGE;
		}
		/* a misspelt name (F_c, fc) would map nothing and leave the log
		 * without that column, silently: only popc's names, each once */
		const int last = o->reader.n_map - 1;
		const char *name = o->reader.map_name[last];
		if (!column_name_known(name)) {
			char names[POPC_LOG_NAMES_LINE_MAX];
			fprintf(stderr,
				"popc-analyze %s: --column %s=%s: '%s' is not a popc column name (%s)\n",
				verb, name, o->reader.map_header[last], name,
				column_names(names, sizeof names, 0) + 1);
			return POPC_EXIT_USAGE;
		}
		for (int i = 0; i < last; i++)
			if (strcmp(o->reader.map_name[i], name) == 0) {
				fprintf(stderr,
					"popc-analyze %s: --column %s=%s: %s is already mapped to '%s'\n",
					verb, name, o->reader.map_header[last], name,
					o->reader.map_header[i]);
				return POPC_EXIT_USAGE;
			}
		return 0;
	}
	case ANA_OPT_DELIMITER:
	case ANA_OPT_COMMENT: {
		char c;
		if (parse_char_option(arg, &c) != 0) {
			fprintf(stderr,
				"popc-analyze %s: --%s '%s': expected one character (or 'tab', "
				"'space'), not a digit, '.', '+' or '-'\n",
				verb, opt == ANA_OPT_DELIMITER ? "delimiter" : "comment", arg);
			return POPC_EXIT_USAGE;
		}
		if (opt == ANA_OPT_DELIMITER && c == ',' && o->reader.decimal == ',') {
			fprintf(stderr,
				"popc-analyze %s: --delimiter ',' with --decimal ',': a decimal-comma log "
				"needs another delimiter (';', tab)\n",
				verb);
			return POPC_EXIT_USAGE;
		}
		/* one character cannot be both: a row whose first cell is empty
		 * (",1e-5,0.1") would read as a comment (in either order; a
		 * default '#' against --delimiter '#' is the reader's to refuse) */
		const char other = opt == ANA_OPT_DELIMITER ? o->reader.comment : o->reader.delimiter;
		if (c == other) {
			fprintf(stderr,
				"popc-analyze %s: --comment '%s' with --delimiter '%s': one character "
				"cannot be both (a row whose first cell is empty would read as a "
				"comment)\n",
				verb, arg, arg);
			return POPC_EXIT_USAGE;
		}
		/* blanks before a comment mark are skipped: a blank would mark none */
		if (opt == ANA_OPT_COMMENT && (c == ' ' || c == '\t')) {
			fprintf(stderr,
				"popc-analyze %s: --comment '%s': a comment mark is no blank (blanks "
				"before one are skipped, so it would mark no line)\n",
				verb, arg);
			return POPC_EXIT_USAGE;
		}
		if (opt == ANA_OPT_DELIMITER)
			o->reader.delimiter = c;
		else
			o->reader.comment = c;
		return 0;
	}
	case ANA_OPT_DECIMAL:
		if (strcmp(arg, ".") != 0 && strcmp(arg, ",") != 0) {
			fprintf(stderr, "popc-analyze %s: --decimal '%s': '.' or ','\n", verb, arg);
			return POPC_EXIT_USAGE;
		}
		if (arg[0] == ',' && o->reader.delimiter == ',') {
			fprintf(stderr,
				"popc-analyze %s: --decimal ',' with --delimiter ',': a decimal-comma log "
				"needs another delimiter (';', tab)\n",
				verb);
			return POPC_EXIT_USAGE;
		}
		o->reader.decimal = arg[0];
		return 0;
	case ANA_OPT_SCALE:
		return scale_option(o, arg, verb);
	case ANA_OPT_NO_HEADER:
		o->reader.no_header = 1;
		return 0;
	case ANA_OPT_JITTER: {
		double f = 0.0;
		if (popc_parse_double_text(arg, &f) != 0 || !(f > 0.0 && f <= ANA_JITTER_MAX)) {
			fprintf(stderr,
				"popc-analyze %s: --jitter '%s': expected a fraction of the period in "
				"(0, %g], e.g. 0.05 for steps within 5 %% of T\n",
				verb, arg, ANA_JITTER_MAX);
			return POPC_EXIT_USAGE;
		}
		o->jitter = f;
		return 0;
	}
	case ANA_OPT_SET:
		if (!strchr(arg, '=') || !strchr(arg, '.')) {
			fprintf(stderr, "popc-analyze %s: --set '%s': expected section.key=value\n",
				verb, arg);
			return POPC_EXIT_USAGE;
		}
		if (popc_arg_push(&o->sets, &o->n_sets, arg) != 0) {
			fprintf(stderr, "popc-analyze %s: out of memory\n", verb);
			return POPC_EXIT_USAGE;
		}
		return 0;
	ANA_FOREIGN_OPTION_CASES:
		return ana_foreign_option(&o->foreign, opt, arg, verb);
	default:
		return POPC_EXIT_USAGE;
	}
}

void ana_input_free(ana_input_options *o)
{
	free(o->sets);
	o->sets = NULL;
	o->n_sets = 0;
}

static const popc_error_name chatter_options[] = {
	{"window_s", "--threshold window=S"},
	{"lc_window_s", "--threshold lc_window=S"},
	{"period_s", "--set run.rate=HZ"},
	{"resolution_m", "--set encoder.resolution=M"},
	{"pc_bound_N", "controller.pc_bound"},
};

void ana_chatter_name_options(popc_error *err)
{
	popc_error_name_params(err, chatter_options, sizeof chatter_options / sizeof chatter_options[0]);
}

int ana_threshold_option(popc_chatter_config *cfg, char *arg, const char *verb)
{
	char *eq = strchr(arg, '=');
	popc_error err;
	if (!eq) {
		fprintf(stderr, "popc-analyze %s: --threshold '%s': expected name=value\n", verb, arg);
		return POPC_EXIT_USAGE;
	}
	*eq = '\0';
	int st = popc_chatter_config_set(cfg, arg, eq + 1, &err);
	*eq = '=';
	if (st) {
		ana_chatter_name_options(&err);
		fprintf(stderr, "popc-analyze %s: --threshold: %s\n", verb, err.msg);
		return POPC_EXIT_USAGE;
	}
	return 0;
}

void ana_online_observer(const popc_scene *s, popc_variant *variant, popc_ignore_mode *mode)
{
	*variant = s->variant;
	*mode = s->ignore_mode;
}

static void base_name(const char *path, char *out, size_t cap)
{
	const char *b = strrchr(path, '/');
	b = b ? b + 1 : path;
	if (strcmp(path, "-") == 0)
		b = "stdin";
	size_t n = strlen(b);
	if (n > 4 && (strcmp(b + n - 4, ".csv") == 0 || strcmp(b + n - 4, ".mat") == 0))
		n -= 4;
	snprintf(out, cap, "%.*s", (int)n, b);
}

void ana_log_name(const char *path, char *out, size_t cap)
{
	base_name(path, out, cap);
}

static int set_given(const ana_input_options *o, const char *key)
{
	size_t n = strlen(key);
	for (int i = 0; i < o->n_sets; i++)
		if (strncmp(o->sets[i], key, n) == 0 && o->sets[i][n] == '=')
			return 1;
	return 0;
}

/* The scene parameters a foreign log may lack, and which use needs them. */
static const struct {
	const char *key;
	unsigned use;
} param_keys[] = {
	{"encoder.resolution", ANA_USES_ENCODER},
	{"run.rate", ANA_USES_RATE},
	{"environment.kind", ANA_USES_ENVIRONMENT},
	{"environment.stiffness", ANA_USES_ENVIRONMENT},
	{"environment.damping", ANA_USES_ENVIRONMENT},
	{"environment.position", ANA_USES_ENVIRONMENT},
	{"controller.variant", ANA_USES_VARIANT},
	{"controller.ignore_mode", ANA_USES_VARIANT | ANA_USES_CONTROLLER},
	{"controller.pc_bound", ANA_USES_CONTROLLER | ANA_USES_PC_BOUND},
	{"controller.foaw_window", ANA_USES_CONTROLLER},
	{"controller.foaw_noise", ANA_USES_CONTROLLER},
};

static void param_value(const popc_scene *s, const char *key, char *out, size_t cap)
{
	if (strcmp(key, "encoder.resolution") == 0)
		snprintf(out, cap, "%.15g", s->enc_resolution_m);
	else if (strcmp(key, "run.rate") == 0)
		snprintf(out, cap, "%.15g", s->rate_Hz);
	else if (strcmp(key, "environment.kind") == 0)
		snprintf(out, cap, "%s", s->env_kind == POPC_ENV_SPRING ? "spring" : "wall");
	else if (strcmp(key, "environment.stiffness") == 0)
		snprintf(out, cap, "%.15g", s->env_stiffness_Npm);
	else if (strcmp(key, "environment.damping") == 0)
		snprintf(out, cap, "%.15g", s->env_damping_Nspm);
	else if (strcmp(key, "environment.position") == 0)
		snprintf(out, cap, "%.15g", s->env_position_m);
	else if (strcmp(key, "controller.variant") == 0)
		snprintf(out, cap, "%s", popc_variant_name(s->variant));
	else if (strcmp(key, "controller.ignore_mode") == 0)
		snprintf(out, cap, "%s", s->ignore_mode == POPC_IGNORE_UNDO ? "undo" : "literal");
	else if (strcmp(key, "controller.pc_bound") == 0)
		snprintf(out, cap, "%.15g", s->pc_bound_N);
	else if (strcmp(key, "controller.foaw_window") == 0)
		snprintf(out, cap, "%d", s->foaw_window);
	else
		snprintf(out, cap, "%.15g", s->foaw_noise_m);
}

/* One line per log naming every parameter the analysis took from the paper
 * scene's defaults because neither a popc header nor --set gave it: a foreign
 * log analysed with the wrong resolution or stiffness gives plausible numbers
 * that are wrong, so the assumption must be visible. */
static void note_defaults(const ana_log *l, const ana_input_options *o, unsigned uses)
{
	if (o->quiet)
		return;
	char list[1024] = "";
	size_t n = 0;
	int count = 0;
	for (size_t i = 0; i < sizeof param_keys / sizeof param_keys[0]; i++) {
		const char *key = param_keys[i].key;
		if (!(param_keys[i].use & uses) || set_given(o, key) ||
		    (l->is_popc && popc_log_reader_header(&l->r, key)))
			continue;
		if (strcmp(key, "controller.ignore_mode") == 0 &&
		    l->scene.variant != POPC_VARIANT_IGNORE && l->scene.variant != POPC_VARIANT_IMPROVED &&
		    !(uses & ANA_USES_CONTROLLER))
			continue; /* only Table I's variants read it */
		char v[64];
		param_value(&l->scene, key, v, sizeof v);
		int w = snprintf(list + n, sizeof list - n, "%s%s = %s", count ? ", " : "", key, v);
		if (w > 0 && (size_t)w < sizeof list - n)
			n += (size_t)w;
		count++;
	}
	if (count)
		fprintf(stderr,
			"popc-analyze %s: note: %s: the log does not give %s; assumed the paper "
			"scene's default%s: %s (override with --set section.key=value)\n",
			o->verb ? o->verb : "analyze", l->r.path,
			count == 1 ? "this parameter" : "these parameters", count == 1 ? "" : "s", list);
}

int ana_no_pc_force(popc_error *err, const char *path)
{
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: no PC force: the file has no column 'f_pc' or 'f_c' (map one "
			      "with --column f_pc=HEADER or --column f_c=HEADER)",
			      path);
}

/* --scale: to SI units (no multiplication without one, so that a popc log
 * still reads back bit for bit) */
static int apply_scale(const ana_log *l, double *row, long long line, popc_error *err)
{
	if (!l->scaled)
		return 0;
	for (int i = 0; i < l->r.n_cols; i++) {
		double v = row[i] * l->scale[i];
		/* a finite value the factor overflows would reach the energies as
		 * inf and come out as NaN (columns nobody reads are NaN already) */
		if (isfinite(row[i]) && !isfinite(v))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (%s): %g x --scale %g overflows a double",
					      l->r.path, line, i + 1, l->r.col_name[i], row[i], l->scale[i]);
		row[i] = v;
	}
	return 0;
}

/* Where a popc log's scene parameter came from, for a message: "run.rate =
 * 500 (header, line 8)", or the last --set that overrode the header. */
static void fact_source(const ana_log *l, const ana_input_options *o, const char *key, char *buf,
			size_t cap)
{
	const size_t n = strlen(key);
	for (int i = o->n_sets - 1; i >= 0; i--)
		if (strncmp(o->sets[i], key, n) == 0 && o->sets[i][n] == '=') {
			snprintf(buf, cap, "%s = %.40s (--set)", key, o->sets[i] + n + 1);
			return;
		}
	const char *v = popc_log_reader_header(&l->r, key);
	snprintf(buf, cap, "%s = %.40s (header, line %lld)", key, v ? v : "",
		 popc_log_reader_header_line(&l->r, key));
}

/* A popc log's header states facts its rows can check: popc's run writes t =
 * k / run.rate (the nominal tick time, on a real axis too: the measured
 * period is the dt column, which jitters and is not checked), x = count x
 * encoder.resolution, and variant none logs f_pc = 0. A header that a tool or
 * an edit changed (rate = 500 over rows 1 ms apart) would be believed, and
 * every rate, window and velocity be off: ana_log_next refuses the first row
 * that contradicts it. A replay log's t is its recording's stamps, which may
 * jitter within the --jitter the replay allowed: their mean step is checked,
 * at the end. Returns 0, or an error for a header that contradicts itself. */
static int header_checks(ana_log *l, const ana_input_options *o, popc_error *err)
{
	const popc_log_reader *r = &l->r;
	const char *variant = popc_log_reader_header(r, "variant");
	/* the variant that ran: the parallel PC's in an admittance log
	 * (docs/ADMITTANCE.md), the series PC's otherwise */
	const char *causality = popc_log_reader_header(r, "device.causality");
	const char *vkey = causality && strcmp(causality, "admittance") == 0 ? "admittance.variant"
									     : "controller.variant";
	const char *cvariant = popc_log_reader_header(r, vkey);
	/* a teleoperation log's variant names the network's PCs and drift
	 * compensation (core/teleop.h), not controller.variant, which it does
	 * not run: checked against teleop.tdpa and teleop.drift (a log written
	 * before that line named controller.variant: still read) */
	if (l->scene.tele_arch != POPC_TELEOP_OFF) {
		const char *tvariant = popc_teleop_variant_name(l->scene.tele_tdpa, l->scene.tele_drift);
		if (variant && strcmp(variant, tvariant) != 0 &&
		    !(cvariant && strcmp(variant, cvariant) == 0 && l->scene.tele_drift == POPC_DRIFT_OFF))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: header: variant = %s, but teleop.tdpa = %s and "
					      "teleop.drift = %s run '%s': the header contradicts itself",
					      r->path, popc_log_reader_header_line(r, "variant"), variant,
					      l->scene.tele_tdpa ? "on" : "off",
					      popc_drift_law_names[l->scene.tele_drift], tvariant);
		cvariant = NULL;
	}
	if (variant && cvariant && strcmp(variant, cvariant) != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%lld: header: variant = %s, but %s = %s (line "
				      "%lld): the header contradicts itself",
				      r->path, popc_log_reader_header_line(r, "variant"), variant, vkey,
				      cvariant, popc_log_reader_header_line(r, vkey));
	const char *source = popc_log_reader_header(r, "source");
	const int unscaled_t = l->c_t >= 0 && l->scale[l->c_t] == 1.0;
	if (unscaled_t && !l->period_from_time && !l->allow_uneven) {
		l->check_steps = strcmp(source, "replay") != 0;
		l->check_mean_step = !l->check_steps;
		fact_source(l, o, "run.rate", l->rate_from, sizeof l->rate_from);
	}
	if (l->c_x >= 0 && l->c_count >= 0 && l->scale[l->c_x] == 1.0 &&
	    l->scale[l->c_count] == 1.0) {
		l->check_x = 1;
		fact_source(l, o, "encoder.resolution", l->resolution_from,
			    sizeof l->resolution_from);
	}
	if (variant && strcmp(variant, "none") == 0 && l->c_f_pc >= 0) {
		l->check_no_pc = 1;
		snprintf(l->variant_from, sizeof l->variant_from, "variant = none (header, line %lld)",
			 popc_log_reader_header_line(r, "variant"));
	}
	return 0;
}

/* An error the reader gave about the converted text names the user's file
 * instead of the temporary one, and no line: the text's lines are not the
 * file's (a MAT file has none; split files are joined row by row). */
static void name_the_input(popc_error *err, const char *tmp, const char *path)
{
	const size_t n = strlen(tmp);
	if (strncmp(err->msg, tmp, n) != 0)
		return;
	const char *rest = err->msg + n;
	if (rest[0] == ':' && rest[1] >= '0' && rest[1] <= '9') {
		rest++;
		while (*rest >= '0' && *rest <= '9')
			rest++;
	}
	char msg[sizeof err->msg];
	snprintf(msg, sizeof msg, "%s%s", path, rest);
	snprintf(err->msg, sizeof err->msg, "%s", msg);
}

int ana_log_open(ana_log *l, const char *path, const ana_input_options *o, popc_error *err)
{
	memset(l, 0, sizeof *l);
	l->verb = o->verb;
	base_name(path, l->name, sizeof l->name);
	/* a MAT file or split files: read as the CSV they convert to (read_foreign.h) */
	char tmp[1100];
	popc_log_reader_options ropt;
	int st = ana_foreign_convert(path, &o->foreign, &o->reader, &ropt, tmp, sizeof tmp, err);
	if (st)
		return st;
	st = popc_log_reader_open(&l->r, tmp[0] ? tmp : path, &ropt, err);
	if (tmp[0]) {
		unlink(tmp); /* open, or not needed */
		snprintf(l->r.path, sizeof l->r.path, "%s", path);
		if (st)
			name_the_input(err, tmp, path);
	}
	if (st)
		return st;
	popc_log_reader *r = &l->r;
	l->is_popc = popc_log_reader_header(r, "format") != NULL &&
		     popc_log_reader_header(r, "source") != NULL;
	if ((st = popc_env_scene_defaults(&l->scene, err)) != 0)
		goto fail;
	snprintf(l->scene.source, sizeof l->scene.source, "%s", path);
	if (l->is_popc && (st = popc_log_reader_scene(r, &l->scene, err)) != 0)
		goto fail;
	for (int i = 0; i < o->n_sets; i++)
		if ((st = popc_scene_set_assignment(&l->scene, o->sets[i], err)) != 0)
			goto fail;
	if ((st = popc_scene_validate(&l->scene, err)) != 0)
		goto fail;
	popc_environment_from_scene(&l->env, &l->scene);
	const char *variant = popc_log_reader_header(r, "variant");
	if (variant)
		snprintf(l->variant, sizeof l->variant, "%s", variant);
	else if (set_given(o, "controller.variant"))
		snprintf(l->variant, sizeof l->variant, "%s", popc_variant_name(l->scene.variant));
	else
		snprintf(l->variant, sizeof l->variant, "unknown");

	/* every column of popc's log the file has: l->c_t, l->c_x, ... */
#define LOOK_UP(ID, name, unit, fill, format, field, meaning)                                        \
	l->c_##name = popc_log_reader_column(r, #name);
	POPC_LOG_COLUMN_TABLE(LOOK_UP)
#undef LOOK_UP
	/* only the columns read here are parsed: a recorded log's other columns
	 * (a state word as text, a date) need not be numbers */
#define INDEX(ID, name, unit, fill, format, field, meaning) l->c_##name,
	const int cols[] = {POPC_LOG_COLUMN_TABLE(INDEX)};
#undef INDEX
	int used[sizeof cols / sizeof cols[0] + ANA_MAX_EXTRA], n_used = 0;
	for (size_t i = 0; i < sizeof cols / sizeof cols[0]; i++)
		if (cols[i] >= 0)
			used[n_used++] = cols[i];
	l->n_extra = o->n_extra < ANA_MAX_EXTRA ? o->n_extra : ANA_MAX_EXTRA;
	for (int i = 0; i < l->n_extra; i++) {
		l->c_extra[i] = popc_log_reader_column(r, o->extra_name[i]);
		if (l->c_extra[i] >= 0)
			used[n_used++] = l->c_extra[i];
	}
	popc_log_reader_use_columns(r, used, n_used);
	/* a column the verb never reads is checked, not parsed, unless --column
	 * made it also one that it reads */
	_Static_assert(sizeof cols / sizeof cols[0] <= 64, "unread: one bit a column");
	int unread[sizeof cols / sizeof cols[0]], n_unread = 0;
	for (size_t i = 0; i < sizeof cols / sizeof cols[0]; i++) {
		int uses = 0;
		for (int j = 0; j < n_used; j++)
			uses += used[j] == cols[i];
		if (cols[i] >= 0 && (o->unread >> i & 1u) && uses == 1)
			unread[n_unread++] = cols[i];
	}
	popc_log_reader_check_columns(r, unread, n_unread);
	for (int i = 0; i < POPC_LOG_MAX_COLUMNS; i++)
		l->scale[i] = 1.0;
	for (int i = 0; i < o->n_scales; i++) {
		int c = popc_log_reader_column(r, o->scale_name[i]);
		if (c < 0) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s: --scale %s=%g: the log has no column '%s' (map one with "
					    "--column %s=HEADER)",
					    path, o->scale_name[i], o->scale[i], o->scale_name[i],
					    o->scale_name[i]);
			goto fail;
		}
		l->scale[c] = o->scale[i];
		l->scaled = 1;
	}
	if (o->foreign.lever_m > 0.0)
		ana_lever_scales(o->foreign.lever_m, l->scale, l->r.n_cols, r, &l->scaled);
	l->has_pc_force = l->c_f_pc >= 0 || l->c_f_c >= 0;
	l->has_w = l->has_pc_force || (l->c_W >= 0 && l->c_E_ref >= 0);
	const int rate_given =
		(l->is_popc && popc_log_reader_header(r, "run.rate")) || set_given(o, "run.rate");
	if (l->c_t < 0 && !rate_given) {
		/* without a time column the rate is the only clock: t = k T */
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: missing column 't': map the time column with --column "
				    "t=HEADER (or t=#N, its position), or give the rate of a log "
				    "without one with --set run.rate=HZ (then t = k / rate)%s",
				    path, popc_log_reader_header_hint(r));
		goto fail;
	}
	if (o->jitter > 0.0 && (!rate_given || l->c_t < 0)) {
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: --jitter %g: %s", path, o->jitter,
				    l->c_t < 0 ? "the log has no time column whose steps could jitter"
					       : "jitter is measured against the nominal period: give "
						 "the device's rate with --set run.rate=HZ");
		goto fail;
	}
	if (l->c_x < 0 && l->c_count < 0) {
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: missing column 'x' (or 'count'): map a position column with "
				    "--column x=HEADER (or x=#N, its position)%s",
				    path, popc_log_reader_header_hint(r));
		goto fail;
	}
	/* the first two rows: the period of a log that does not give its rate */
	while (l->n_ahead < 2) {
		int got = popc_log_reader_next(r, l->ahead[l->n_ahead], err);
		if (got < 0) {
			st = got;
			goto fail;
		}
		if (got == 0)
			break;
		l->ahead_line[l->n_ahead] = r->lineno;
		if ((st = apply_scale(l, l->ahead[l->n_ahead], r->lineno, err)) != 0)
			goto fail;
		l->n_ahead++;
	}
	if (l->n_ahead == 0) {
		st = popc_error_set(err, POPC_ERR_INVALID, "%s:%lld: no data rows after the column names",
				    path, r->lineno);
		goto fail;
	}
	if (rate_given || l->n_ahead < 2) {
		l->period_s = popc_scene_period_s(&l->scene);
	} else {
		l->period_s = l->ahead[1][l->c_t] - l->ahead[0][l->c_t];
		l->period_from_time = 1;
		/* a subnormal step (5e-324 s) has no finite rate, an infinite one
		 * (1e308 after -1e308) no finite time: the rates per second, v =
		 * dx/T and the observers' v T would be inf or NaN */
		if (!isnormal(l->period_s)) {
			st = popc_error_set(err, POPC_ERR_INVALID,
					    "%s:%lld: column %d (t): the first time step, %g s (lines "
					    "%lld-%lld), cannot be the period: %s (the log gives no "
					    "rate: give --set run.rate=HZ, or a time column in seconds)",
					    path, l->ahead_line[1], l->c_t + 1, l->period_s,
					    l->ahead_line[0], l->ahead_line[1],
					    isfinite(l->period_s) ? "its rate 1/T overflows a double"
								  : "it overflows a double");
			goto fail;
		}
	}
	l->allow_uneven = o->allow_uneven;
	l->jitter = o->jitter;
	l->check_jitter = o->jitter > 0.0;
	l->quiet = o->quiet;
	if (l->is_popc && (st = header_checks(l, o, err)) != 0)
		goto fail;
	popc_variant v;
	popc_ignore_mode m;
	ana_online_observer(&l->scene, &v, &m);
	popc_observer_init(&l->obs, v, m);
	unsigned uses = o->uses | ANA_USES_ENCODER;
	if (l->c_f_e < 0)
		uses |= ANA_USES_ENVIRONMENT;
	if ((l->c_W < 0 || l->c_E_ref < 0) && l->has_pc_force)
		uses |= ANA_USES_VARIANT; /* W's observer (without a PC force W is n/a) */
	if (!l->period_from_time)
		uses |= ANA_USES_RATE;
	note_defaults(l, o, (uses & ~o->ignores) | o->uses);
	return 0;
fail:
	popc_log_reader_close(r);
	return st;
}

/* The cells are finite (the reader), but what is derived from them need not
 * be: v = dx / T with dx near 8e18 m and a tiny T, f_c = f_e + f_pc near
 * 1e308 each, a W summed over rows, W - E_ref of two logged energies. What a
 * double cannot hold is refused where it first happens. */
static int check_finite(const ana_log *l, const popc_tick *t, long long line, popc_error *err)
{
	const struct {
		const char *what;
		double v;
		int derived;
	} q[] = {
		{"the velocity v = (x(k) - x(k-1)) / T", t->v_mps, l->c_v < 0},
		{"the environment force f_e (from x, v and environment.*)", t->f_e_N, l->c_f_e < 0},
		{"f_pc = f_c - f_e", t->f_pc_N, l->c_f_pc < 0},
		{"f_c = f_e + f_pc", t->f_c_N, l->c_f_c < 0},
		{"the recomputed W (the sum of f_c dx)", t->W_J, l->c_W < 0 || l->c_E_ref < 0},
		{"the recomputed E_ref (the sum of f_e dx)", t->E_ref_J, l->c_W < 0 || l->c_E_ref < 0},
		{"W - E_ref", t->W_J - t->E_ref_J, 1},
	};
	for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
		if (q[i].derived && !isfinite(q[i].v))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: %s overflows a double (from finite cells: x = %g m, "
					      "the previous x = %g m, T = %g s)",
					      l->r.path, line, q[i].what, t->x_m, l->k ? l->x_prev_m : t->x_m,
					      l->period_s);
	return 0;
}

/* An unfinished popc log is read to its last whole row, and says so: its
 * results are those of a shorter run than the one popc was asked for. */
static void note_unfinished(ana_log *l)
{
	l->unfinished = popc_log_reader_unfinished(&l->r);
	if (!l->unfinished)
		return;
	char cut[96] = "";
	if (l->unfinished == POPC_LOG_CUT_LINE)
		snprintf(cut, sizeof cut, "line %lld, the last, is cut short (no newline) and not read; ",
			 l->r.cut_line);
	fprintf(stderr,
		"popc-analyze %s: note: %s: unfinished log: %sno '# stop = ...' line; its %lld whole "
		"rows to line %lld are read (the run was cut short: a full disk, a killed process)\n",
		l->verb ? l->verb : "analyze", l->r.path, cut, l->r.rows, l->r.last_row_line);
}

/* Under --jitter, what the stamps measured: a tolerance much wider than the
 * jitter hides nothing, but the user should see how close a log came. */
static void note_jitter(const ana_log *l)
{
	if (l->jitter <= 0.0 || l->quiet || l->k < 2)
		return;
	fprintf(stderr,
		"popc-analyze %s: note: %s: the time steps are within %.3g %% of the nominal period "
		"%g s (the largest at line %lld; --jitter %g allows %g %%)\n",
		l->verb ? l->verb : "analyze", l->r.path, 100.0 * l->max_jitter, l->period_s,
		l->max_jitter_line, l->jitter, 100.0 * l->jitter);
}

int ana_log_next(ana_log *l, ana_row *out, popc_error *err)
{
	const double *row;
	int st;
	long long line; /* the row's line in the file, for messages */
	if (l->ahead_pos < l->n_ahead) {
		line = l->ahead_line[l->ahead_pos];
		row = l->ahead[l->ahead_pos++];
	} else {
		int got = popc_log_reader_next(&l->r, l->row, err);
		if (got == 0 && l->check_mean_step && l->k > 1) {
			const double T = l->period_s;
			const double mean = (l->t_prev_s - l->t_first_s) / (double)(l->k - 1);
			l->check_mean_step = 0; /* said once */
			if (!(fabs(mean - T) <= ANA_PERIOD_REL_TOL * T))
				return popc_error_set(
					err, POPC_ERR_INVALID,
					"%s:%lld: column %d (t): the mean time step of lines %lld-%lld is "
					"%.17g s, %.3g %% off the period %.17g s of %s, more than %g %%: the "
					"header contradicts the rows (a replay log's t is its recording's "
					"stamps: they may jitter, their mean step is the period)",
					l->r.path, l->t_prev_line, l->c_t + 1, l->t_first_line,
					l->t_prev_line, mean, 100.0 * fabs(mean - T) / T, T, l->rate_from,
					100.0 * ANA_PERIOD_REL_TOL);
		}
		if (got == 0 && !l->unfinished) {
			note_unfinished(l);
			note_jitter(l);
		}
		if (got <= 0)
			return got;
		line = l->r.lineno;
		if ((st = apply_scale(l, l->row, line, err)) != 0)
			return st;
		row = l->row;
	}
	const double delta = l->scene.enc_resolution_m;
	const double T = l->period_s;
	popc_tick *t = &out->tick;
	/* zeroed by a copy: gcc makes memset of this size a "rep stos", whose
	 * start-up was a twentieth of the time of reading a row */
	static const ana_row empty_row;
	*out = empty_row;
	/* no time column: the rate's clock, as popc's run writes it */
	t->t_s = l->c_t >= 0 ? row[l->c_t] : (double)l->k * T;
	out->step_s = T;
	if (l->jitter > 0.0 && l->k > 0) {
		/* measured stamps: the real step, for the definitions that take it;
		 * a verb built on the nominal T refuses one beyond the tolerance */
		const double step = t->t_s - l->t_prev_s;
		const double off = fabs(step - T) / T;
		if (!isnormal(step))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (t): the time step from line %lld, %g s, "
					      "is no usable step (subnormal or overflowing)",
					      l->r.path, line, l->c_t + 1, l->t_prev_line, step);
		if (l->check_jitter && !(off <= l->jitter))
			return popc_error_set(
				err, POPC_ERR_INVALID,
				"%s:%lld: column %d (t): the time step from line %lld (t = %.17g) is "
				"%.17g s, %.3g %% off the nominal period %.17g s (run.rate), more than "
				"--jitter %g (%g %%): %s uses the nominal T here (windows in ticks, "
				"rates per second, the controller's or the online observer's step); "
				"energy's definitions on the measured steps do not",
				l->r.path, line, l->c_t + 1, l->t_prev_line, l->t_prev_s, step,
				100.0 * off, T, l->jitter, 100.0 * l->jitter,
				l->verb ? l->verb : "the analysis");
		if (off > l->max_jitter) {
			l->max_jitter = off;
			l->max_jitter_line = line;
		}
		out->step_s = step;
	}
	if (l->period_from_time && !l->allow_uneven && l->k > 0) {
		/* the period is the first step: every step must be it (the tolerance
		 * and why: ANA_PERIOD_REL_TOL) */
		const double step = t->t_s - l->t_prev_s;
		if (!(fabs(step - T) <= ANA_PERIOD_REL_TOL * T))
			return popc_error_set(
				err, POPC_ERR_INVALID,
				"%s:%lld: column %d (t): uneven time steps: the step from line %lld (t = "
				"%.17g) is %.17g s, %.3g %% off the period %.17g s (the first step, "
				"lines %lld-%lld; the log gives no rate), more than %g %%. The analysis "
				"uses one period T: resample the log, or give --set run.rate=HZ and "
				"--jitter FRACTION if the device ran at a fixed rate and only its time "
				"stamps are uneven (energy: --allow-uneven for the observers that do not "
				"use T)",
				l->r.path, line, l->c_t + 1, l->t_prev_line, l->t_prev_s, step,
				100.0 * fabs(step - T) / T, T, l->ahead_line[0], l->ahead_line[1],
				100.0 * ANA_PERIOD_REL_TOL);
	}
	if (l->check_steps && l->k > 0) {
		const double step = t->t_s - l->t_prev_s;
		if (!(fabs(step - T) <= ANA_PERIOD_REL_TOL * T))
			return popc_error_set(
				err, POPC_ERR_INVALID,
				"%s:%lld: column %d (t): the time step from line %lld (t = %.17g) is %.17g "
				"s, %.3g %% off the period %.17g s of %s, more than %g %%: the header "
				"contradicts the rows (popc writes t = k / run.rate)",
				l->r.path, line, l->c_t + 1, l->t_prev_line, l->t_prev_s, step,
				100.0 * fabs(step - T) / T, T, l->rate_from, 100.0 * ANA_PERIOD_REL_TOL);
	}
	if (l->k == 0) {
		l->t_first_s = t->t_s;
		l->t_first_line = line;
	}
	l->t_prev_s = t->t_s;
	l->t_prev_line = line;
	if (l->c_count >= 0) {
		double c = row[l->c_count];
		/* an integer within 2^53: beyond it a double no longer holds
		 * every integer, so a count there is not exact (popc's encoder
		 * stays below it: README, exit 6); within, equal to its
		 * truncation (floor is a libm emulation on baseline x86-64) */
		const double exact_max = 9007199254740992.0; /* 2^53 */
		if (fabs(c) > exact_max && fabs(c) <= DBL_MAX)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (count): %.17g is beyond 2^53 = "
					      "9007199254740992, where counts stop being exact (a double holds "
					      "every integer only up to there)",
					      l->r.path, line, l->c_count + 1, c);
		if (!(fabs(c) <= exact_max && c == (double)(long long)c))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (count): %.17g is not an integer count",
					      l->r.path, line, l->c_count + 1, c);
		t->count = (long long)c;
		t->x_m = l->c_x >= 0 ? row[l->c_x] : popc_encoder_position(t->count, delta);
		/* popc writes x = count x resolution: a relative 1e-9 is rounding
		 * far below any other resolution (a factor 10, or 1e-5 for 1.024e-5) */
		const double x_count = popc_encoder_position(t->count, delta);
		if (l->check_x && !(fabs(t->x_m - x_count) <= 1e-9 * fabs(x_count)))
			return popc_error_set(
				err, POPC_ERR_INVALID,
				"%s:%lld: column %d (x): x = %.17g m, but count %lld x %s is %.17g m (x / "
				"count = %.6g m): the header contradicts the rows (popc writes x = count x "
				"encoder.resolution)",
				l->r.path, line, l->c_x + 1, t->x_m, t->count, l->resolution_from, x_count,
				t->count ? t->x_m / (double)t->count : 0.0);
	} else {
		/* a foreign position in metres: the nearest encoder count */
		t->x_m = row[l->c_x];
		double c = nearbyint(t->x_m / delta);
		if (!(fabs(c) < 4.0e18))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (x): %.17g m is %.3g counts of %g m",
					      l->r.path, line, l->c_x + 1, t->x_m, c, delta);
		t->count = (long long)c;
	}
	if (l->c_v >= 0)
		t->v_mps = row[l->c_v];
	else /* the backward difference the non-filtered variants use online */
		t->v_mps = l->k > 0 ? (t->x_m - l->x_prev_m) / out->step_s : 0.0;
	t->f_e_N = l->c_f_e >= 0 ? row[l->c_f_e]
				 : popc_environment_force(&l->env, t->x_m, t->v_mps);
	if (l->c_f_pc >= 0)
		t->f_pc_N = row[l->c_f_pc];
	else
		t->f_pc_N = l->c_f_c >= 0 ? row[l->c_f_c] - t->f_e_N : 0.0;
	t->f_c_N = l->c_f_c >= 0 ? row[l->c_f_c] : t->f_e_N + t->f_pc_N;
	if (l->check_no_pc && t->f_pc_N != 0.0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%lld: column %d (f_pc): f_pc = %.17g N, but %s logs no PC "
				      "force (f_pc = 0): the header contradicts the rows",
				      l->r.path, line, l->c_f_pc + 1, t->f_pc_N, l->variant_from);
	out->W_logged_J = l->c_W >= 0 ? row[l->c_W] : (double)NAN;
	/* a force count is a whole number within the sensor's +-2^52
	 * (popc_force_sensor_read): a cell beyond has no count, and its cast
	 * to long long would be undefined */
	if (l->c_f_count >= 0 && !(fabs(row[l->c_f_count]) <= 4503599627370496.0 &&
				   row[l->c_f_count] == nearbyint(row[l->c_f_count])))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%lld: column %d (f_count): %.17g is not a whole force count "
				      "within +-2^52",
				      l->r.path, line, l->c_f_count + 1, row[l->c_f_count]);
	out->adm_count = l->c_f_count >= 0 ? (long long)row[l->c_f_count] : 0;
	out->adm_x_cmd_m = l->c_x_cmd >= 0 ? row[l->c_x_cmd] : 0.0;
	/* an admittance log's own cells (docs/ADMITTANCE.md), for energy */
	if (l->c_f_count >= 0 && l->c_f_meas >= 0 && l->c_v_ve >= 0 && l->c_v_pc >= 0) {
		out->has_adm = 1;
		out->adm_n = (long long)row[l->c_f_count];
		out->adm_f_N = row[l->c_f_meas];
		out->adm_v_ve_mps = row[l->c_v_ve];
		out->adm_v_pc_mps = row[l->c_v_pc];
	}
	out->E_ref_logged_J = l->c_E_ref >= 0 ? row[l->c_E_ref] : (double)NAN;
	if (l->c_W >= 0 && l->c_E_ref >= 0) {
		t->W_J = row[l->c_W];
		t->E_ref_J = row[l->c_E_ref];
	} else {
		/* the observer that ran online, on the logged positions and forces */
		popc_observation ob;
		popc_observer_update(&l->obs, t->x_m, t->count, t->v_mps, T, t->f_e_N, &ob);
		popc_observer_commit(&l->obs, &ob, t->f_e_N, t->f_c_N);
		t->W_J = l->c_W >= 0 ? row[l->c_W] : l->obs.W_J;
		t->E_ref_J = l->c_E_ref >= 0 ? row[l->c_E_ref] : l->obs.E_ref_J;
	}
	if (l->c_flags >= 0) {
		/* a bit set (POPC_FLAG_*): 3.5, -1 or 1e30 is no flag word, and
		 * truncating it would invent or drop bits */
		double f = row[l->c_flags];
		if (!(f >= 0.0 && f <= (double)UINT_MAX && f == (double)(unsigned)f))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%lld: column %d (flags): %.17g is not a flag word (an "
					      "integer in [0, %u])",
					      l->r.path, line, l->c_flags + 1, f, UINT_MAX);
		t->flags = (unsigned)f;
	} else {
		t->flags = t->f_pc_N != 0.0 ? POPC_FLAG_ACTIVE : 0u;
	}
	if ((st = check_finite(l, t, line, err)) != 0)
		return st;
	out->pc_force_known = l->has_pc_force;
	out->w_known = l->has_w;
	out->line = line;
	out->x_true_m = l->c_x_true >= 0 ? row[l->c_x_true] : (double)NAN;
	out->E_port_J = l->c_E_port >= 0 ? row[l->c_E_port] : (double)NAN;
	out->dt_s = l->c_dt >= 0 ? row[l->c_dt] : (double)NAN;
	out->rtt_s = l->c_rtt >= 0 ? row[l->c_rtt] : (double)NAN;
	for (int i = 0; i < ANA_MAX_EXTRA; i++)
		out->extra[i] = i < l->n_extra && l->c_extra[i] >= 0 ? row[l->c_extra[i]] : (double)NAN;
	l->x_prev_m = t->x_m;
	l->k++;
	return 1;
}

void ana_log_close(ana_log *l)
{
	popc_log_reader_close(&l->r);
}

int ana_format_from_name(const char *name, ana_format *f)
{
	if (strcmp(name, "text") == 0)
		*f = ANA_TEXT;
	else if (strcmp(name, "csv") == 0)
		*f = ANA_CSV;
	else if (strcmp(name, "markdown") == 0 || strcmp(name, "md") == 0)
		*f = ANA_MARKDOWN;
	else if (strcmp(name, "json") == 0)
		*f = ANA_JSON;
	else
		return -1;
	return 0;
}
