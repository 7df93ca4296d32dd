/* Register map files (register_map.h): INI via libinih, then the keys one by
 * one from the table (register_map_keys.def) and the rules between them, with
 * file, line and key in every message. */
#include "popc/axes/register_map.h"

#include <errno.h>
#include <float.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/core/admittance_plant.h"
#include "popc/scene/ini_lines.h"
#include "popc/util/parse.h"

#define TWO_PI 6.283185307179586476925286766559

int popc_register_map_command_block(const popc_register_map *m, int *first)
{
	int n = popc_reg_type_words(m->cmd.type);
	*first = m->cmd.reg;
	if (m->cmd.seq_reg < 0)
		return n;
	if (m->cmd.seq_reg < m->cmd.reg)
		*first = m->cmd.seq_reg;
	return n + 1;
}

int popc_register_map_counts_are_scene_counts(const popc_register_map *m, double resolution_m)
{
	return fabs(m->pos.counts_per_m * resolution_m - 1.0) < 1e-9;
}

int popc_register_map_sensor_is_scene_counts(const popc_register_map *m, double resolution_N)
{
	return resolution_N > 0.0 && fabs(m->sensor.newton_per_unit / resolution_N - 1.0) < 1e-9;
}

int popc_register_map_scene_servo(const popc_scene *s, popc_servo_kind *servo,
				  double *force_resolution_N, const char **servo_key)
{
	if (s->tele_arch != POPC_TELEOP_OFF) {
		*servo = s->slave_servo;
		*force_resolution_N = s->slave_force_resolution_N;
		*servo_key = "slave.servo";
		return 1;
	}
	*servo = s->adm_servo;
	*force_resolution_N = s->adm_force_resolution_N;
	*servo_key = "admittance.servo";
	return s->causality == POPC_CAUSALITY_ADMITTANCE;
}

int popc_register_map_fits_scene(const popc_register_map *m, const popc_scene *s, popc_error *err)
{
	const char *mode = popc_cmd_mode_names[m->cmd.mode];
	const char *scene = s->source[0] ? s->source : "the scene";
	popc_servo_kind kind;
	double res_N;
	const char *key;
	if (!popc_register_map_scene_servo(s, &kind, &res_N, &key)) {
		if (m->cmd.mode == POPC_CMD_FORCE)
			return 0;
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: command.mode = %s: %s has device.causality = impedance, "
				      "which commands a force; the map needs command.mode = force",
				      m->path, mode, scene);
	}
	const char *servo = popc_servo_kind_names[kind];
	/* a teleoperation scene's drive is its slave (the master is simulated) */
	const char *device = s->tele_arch != POPC_TELEOP_OFF ? "a teleoperation slave"
							     : "device.causality = admittance";
	if (m->cmd.mode == POPC_CMD_FORCE)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: command.mode = force: %s has %s "
				      "with %s = %s, which commands a %s; the map needs "
				      "command.mode = %s and a [force_sensor]",
				      m->path, scene, device, key, servo, servo, servo);
	if ((m->cmd.mode == POPC_CMD_POSITION) != (kind == POPC_SERVO_POSITION))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: command.mode = %s: %s has %s = %s; the map "
				      "needs command.mode = %s",
				      m->path, mode, scene, key, servo, servo);
	return 0;
}

/* ---- the key table ------------------------------------------------------ */

static const char *const yes_no[] = {"no", "yes", NULL};
static const char *const read_tables[] = {"holding", "input", NULL};
static const char *const enable_tables[] = {"holding", "input", "coil", NULL};
static const char *const command_tables[] = {"holding", NULL};
static const char *const orders[] = {"hi-lo", "lo-hi", NULL};
static const char *const directions[] = {"normal", "reversed", NULL};
const char *const popc_cmd_mode_names[] = {"force", "position", "velocity", NULL};

/* the command modes of the table's .modes (register_map.h) */
#define FORCE_ONLY POPC_MAP_MODE(POPC_CMD_FORCE)
#define POSITION_ONLY POPC_MAP_MODE(POPC_CMD_POSITION)
#define VELOCITY_ONLY POPC_MAP_MODE(POPC_CMD_VELOCITY)
#define SERVO_ONLY (POSITION_ONLY | VELOCITY_ONLY)

/* the index is libmodbus' MODBUS_RTU_RTS_NONE, _UP, _DOWN (modbus_axis.c maps it) */
static const char *const rts_modes[] = {"none", "up", "down", NULL};

/* Where a key's value goes in popc_register_map. */
typedef enum key_store {
	TO_NOWHERE,   /* only enters a value derived in validate() */
	TO_TEXT,      /* char[size] */
	TO_INT,       /* int */
	TO_ENUM,      /* one of the map's enums: the choice's index */
	TO_U16,       /* uint16_t */
	TO_DOUBLE,    /* double */
	TO_WORDS,     /* uint16_t[size / 2], and their number in the int at count_offset */
} key_store;

/* the enums take a choice's index as an int (TO_ENUM) */
_Static_assert(sizeof(popc_reg_table) == sizeof(int) && sizeof(popc_reg_type) == sizeof(int) &&
		       sizeof(popc_word_order) == sizeof(int) && sizeof(popc_cmd_mode) == sizeof(int),
	       "an enum of the map is not int-sized");

typedef struct key_row {
	popc_map_key key;
	key_store store;
	size_t offset, size, count_offset;
} key_row;

#define FIELD_SIZE(field) sizeof(((popc_register_map *)0)->field)
#define TO(kind, field) TO_##kind, offsetof(popc_register_map, field), FIELD_SIZE(field), 0
#define TO_WORDS(field, count)                                                                     \
	TO_WORDS, offsetof(popc_register_map, field), FIELD_SIZE(field),                           \
		offsetof(popc_register_map, count)
#define NOWHERE TO_NOWHERE, 0, 0, 0

enum {
#define MAP_KEY(id, ...) K_##id,
#include "register_map_keys.def"
#undef MAP_KEY
	K_COUNT
};

static const key_row rows[K_COUNT] = {
#define MAP_KEY(id, sec, name, kind, store, ...)                                                   \
	[K_##id] = {{.section = sec, .key = name, .type = POPC_MAP_##kind, __VA_ARGS__}, store},
#include "register_map_keys.def"
#undef MAP_KEY
};

const popc_map_key *popc_register_map_key(size_t i)
{
	return i < K_COUNT ? &rows[i].key : NULL;
}

/* "[0, 65535]", "(0, 1e+06] m", "one of hi-lo|lo-hi", "text" */
static void describe_allowed(const popc_map_key *k, char *buf, size_t cap)
{
	const char *unit = k->unit ? k->unit : "";
	switch (k->type) {
	case POPC_MAP_TEXT: snprintf(buf, cap, "text"); break;
	case POPC_MAP_INT:
		snprintf(buf, cap, "[%ld, %ld]%s%s", (long)k->lo, (long)k->hi, unit[0] ? " " : "", unit);
		break;
	case POPC_MAP_NUMBER:
		snprintf(buf, cap, "%c%g, %g]%s%s", k->lo_open ? '(' : '[', k->lo, k->hi, unit[0] ? " " : "",
			 unit);
		break;
	case POPC_MAP_WORDS:
		snprintf(buf, cap, "1 to %d words in [%ld, 0x%lX]", POPC_MAP_ENABLE_MAX, (long)k->lo,
			 (unsigned long)k->hi);
		break;
	case POPC_MAP_CHOICE: {
		size_t n = (size_t)snprintf(buf, cap, "one of ");
		for (int i = 0; k->choices[i] && n < cap; i++)
			n += (size_t)snprintf(buf + n, cap - n, "%s%s", i ? "|" : "", k->choices[i]);
		break;
	}
	}
}

void popc_register_map_print_keys(FILE *f)
{
	for (size_t i = 0; i < K_COUNT; i++) {
		const popc_map_key *k = &rows[i].key;
		char name[80], allowed[160];
		snprintf(name, sizeof name, "%s.%s", k->section, k->key);
		describe_allowed(k, allowed, sizeof allowed);
		const char *def = k->default_text ? k->default_text : k->required ? "(required)" : "(none)";
		fprintf(f, "  %-34s default %-13s allowed %s\n      %s\n", name, def, allowed, k->help);
	}
}

/* ---- loading ------------------------------------------------------------- */

/* Values are kept as text with their line while the file is read, and
 * checked once it is all read (so cross-key errors also have a line). */
typedef struct load_ctx {
	FILE *f;
	int line;
	const char *path;
	char value[K_COUNT][128];
	int at[K_COUNT];           /* line of the key, 0: not given */
	double num[K_COUNT];       /* INT, NUMBER: the value; CHOICE: its index */
	uint16_t words[POPC_MAP_ENABLE_MAX];
	int n_words;               /* the WORDS key's */
	int status;
	popc_error *err;
} load_ctx;

/* libinih's reader: one call per line. A line that does not fit the buffer
 * (num - 1 characters) would come back in pieces, each counted as a line by
 * libinih and by us (every later message would name the wrong line) and the
 * tail parsed as a line of its own; so it is refused here, with its real
 * number (ini_lines.h). */
static void check_section_line(load_ctx *c, const char *line);

static char *read_line(char *str, int num, void *stream)
{
	load_ctx *c = stream;
	if (c->status)
		return NULL;
	int too_long = 0;
	char *r = popc_ini_read_line(str, num, c->f, &c->line, &too_long);
	if ((r || too_long == 1) && popc_ini_line_has_bare_cr(str)) /* CR-only: one long line */
		c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: %s", c->path, c->line,
					   POPC_INI_BARE_CR_WHY);
	else if (too_long == 2)
		c->status = popc_error_set(c->err, POPC_ERR_INVALID,
					   "%s:%d: a NUL byte in the line (a register map is a text file)",
					   c->path, c->line);
	else if (too_long)
		c->status = popc_error_set(c->err, POPC_ERR_INVALID,
					   "%s:%d: line longer than %d characters (shorten the comment or value)",
					   c->path, c->line, num - 1);
	else if (r)
		check_section_line(c, r);
	return c->status ? NULL : r;
}

/* "drive, position, command, enable, status": the table's sections in order */
static void list_sections(char *buf, size_t cap)
{
	size_t n = 0;
	buf[0] = '\0';
	for (int i = 0; i < K_COUNT && n < cap; i++)
		if (i == 0 || strcmp(rows[i].key.section, rows[i - 1].key.section) != 0)
			n += (size_t)snprintf(buf + n, cap - n, "%s%s", i ? ", " : "", rows[i].key.section);
}

/* A "[section]" line: libinih calls the handler for keys only, so an unknown
 * section without keys ("[nosuch]" alone, or a misspelt "[comand]" before
 * another section) passed unseen; refused here with the message of an
 * unknown section with keys, as the scene loader does. The name as libinih
 * takes it: from '[' to the first ']' (a line without one is libinih's
 * malformed line). */
static void check_section_line(load_ctx *c, const char *line)
{
	if (line[0] != '[')
		return;
	const char *end = strchr(line + 1, ']');
	if (!end)
		return;
	size_t n = (size_t)(end - line - 1);
	for (int i = 0; i < K_COUNT; i++)
		if (strlen(rows[i].key.section) == n && strncmp(rows[i].key.section, line + 1, n) == 0)
			return;
	char sections[128];
	list_sections(sections, sizeof sections);
	c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: unknown section [%.*s] (allowed: %s)",
				   c->path, c->line, (int)(n > 64 ? 64 : n), line + 1, sections);
}

static int map_handler(void *user, const char *section, const char *name, const char *value)
{
	load_ctx *c = user;
	if (c->status)
		return 1;
	int known_section = 0;
	for (int i = 0; i < K_COUNT; i++) {
		if (strcmp(section, rows[i].key.section) != 0)
			continue;
		known_section = 1;
		if (strcmp(name, rows[i].key.key) != 0)
			continue;
		if (c->at[i]) {
			c->status = popc_error_set(c->err, POPC_ERR_INVALID,
						   "%s:%d: %s.%s given twice (first on line %d)", c->path,
						   c->line, section, name, c->at[i]);
			return 0;
		}
		if (strlen(value) >= sizeof c->value[i]) {
			c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: %s.%s: value too long",
						   c->path, c->line, section, name);
			return 0;
		}
		snprintf(c->value[i], sizeof c->value[i], "%s", value);
		c->at[i] = c->line;
		return 1;
	}
	if (!known_section) {
		char sections[128];
		list_sections(sections, sizeof sections);
		c->status = popc_error_set(c->err, POPC_ERR_INVALID,
					   "%s:%d: unknown section [%s] (allowed: %s)", c->path, c->line,
					   section, sections);
	} else {
		c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: unknown key %s.%s",
					   c->path, c->line, section, name);
	}
	return 0;
}

static int bad(load_ctx *c, int k, const char *what)
{
	return popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: %s.%s = %s: %s", c->path, c->at[k],
			      rows[k].key.section, rows[k].key.key, c->value[k], what);
}

static int missing(load_ctx *c, int k, const char *why)
{
	return popc_error_set(c->err, POPC_ERR_INVALID, "%s: missing %s.%s%s%s", c->path,
			      rows[k].key.section, rows[k].key.key, why ? ": " : "", why ? why : "");
}

/* An integer as the docs promise it: a whole number as everywhere
 * (popc/util/parse.h), or hexadecimal with 0x (POPC_PARSE_HEX: register maps
 * only, as drive manuals write addresses). Never strtol's base 0, which reads
 * a leading zero as octal: "0100" copied from a manual's register table would
 * silently become register 64. */
static int parse_int(load_ctx *c, int k, const char *text)
{
	const popc_map_key *d = &rows[k].key;
	long long v;
	if (popc_parse_ll_span(text, text + strlen(text), (long long)d->lo, (long long)d->hi,
			       POPC_PARSE_HEX, &v) != POPC_PARSE_OK) {
		char what[96];
		snprintf(what, sizeof what, "expected an integer in [%ld, %ld]", (long)d->lo, (long)d->hi);
		return bad(c, k, what);
	}
	c->num[k] = (double)v;
	return 0;
}

static int parse_number(load_ctx *c, int k, const char *text)
{
	const popc_map_key *d = &rows[k].key;
	/* a number as scene values (popc/util/parse.h: no hex floats, no
	 * "inf"/"nan", exact rounding) */
	double v;
	if (popc_parse_double_text(text, &v) != POPC_PARSE_OK || v > d->hi || v < d->lo ||
	    (d->lo_open && v == d->lo)) {
		char what[96];
		snprintf(what, sizeof what, "expected a number in %c%g, %g]", d->lo_open ? '(' : '[',
			 d->lo, d->hi);
		return bad(c, k, what);
	}
	c->num[k] = v;
	return 0;
}

static int parse_choice(load_ctx *c, int k, const char *text)
{
	const popc_map_key *d = &rows[k].key;
	for (int i = 0; d->choices[i]; i++)
		if (strcmp(text, d->choices[i]) == 0) {
			c->num[k] = i;
			return 0;
		}
	if (d->refusal)
		return bad(c, k, d->refusal);
	char what[160] = "expected one of:";
	for (int i = 0; d->choices[i]; i++) {
		strncat(what, " ", sizeof what - strlen(what) - 1);
		strncat(what, d->choices[i], sizeof what - strlen(what) - 1);
	}
	return bad(c, k, what);
}

/* One to four words separated by commas or blanks (a CiA-402 drive goes
 * shutdown 0x06, switch on 0x07, enable operation 0x0F). */
static int parse_words(load_ctx *c, int k, const char *text)
{
	const popc_map_key *d = &rows[k].key;
	const char *p = text;
	c->n_words = 0;
	while (*p) {
		while (*p == ' ' || *p == ',' || *p == '\t')
			p++;
		if (!*p)
			break;
		char what[96];
		if (c->n_words == POPC_MAP_ENABLE_MAX) {
			snprintf(what, sizeof what, "at most %d words", POPC_MAP_ENABLE_MAX);
			return bad(c, k, what);
		}
		const char *end = p + strcspn(p, " ,\t");
		long long v;
		if (popc_parse_ll_span(p, end, (long long)d->lo, (long long)d->hi, POPC_PARSE_HEX,
				       &v) != POPC_PARSE_OK) {
			snprintf(what, sizeof what, "expected words in [%ld, 0x%lX] separated by commas",
				 (long)d->lo, (unsigned long)d->hi);
			return bad(c, k, what);
		}
		c->words[c->n_words++] = (uint16_t)v;
		p = end;
	}
	if (c->n_words == 0)
		return bad(c, k, "expected at least one word");
	return 0;
}

/* Whether key k belongs to the map's command mode (command.mode, parsed
 * first: the keys that belong to it depend on it). */
static int in_mode(const load_ctx *c, int k)
{
	return !rows[k].key.modes || (rows[k].key.modes & POPC_MAP_MODE((int)c->num[K_CMD_MODE]));
}

/* "only used with command.mode = position or velocity" */
static int wrong_mode(load_ctx *c, int k)
{
	char what[160] = "only used with command.mode =";
	const char *sep = " ";
	for (int i = 0; popc_cmd_mode_names[i]; i++)
		if (rows[k].key.modes & POPC_MAP_MODE(i)) {
			strncat(what, sep, sizeof what - strlen(what) - 1);
			strncat(what, popc_cmd_mode_names[i], sizeof what - strlen(what) - 1);
			sep = " or ";
		}
	char tail[64];
	snprintf(tail, sizeof tail, " (this map's is %s)", popc_cmd_mode_names[(int)c->num[K_CMD_MODE]]);
	strncat(what, tail, sizeof what - strlen(what) - 1);
	return bad(c, k, what);
}

/* Every key on its own, in file order (command.mode first, since which keys
 * a map needs depends on it): a required key that is absent, a key of
 * another command mode that is given, a value of the wrong type or out of
 * its range. An absent key with a default takes the default's text; a key of
 * another mode is neither required nor defaulted. Returns 0 or the first
 * error. */
static int parse_keys(load_ctx *c)
{
	int st = parse_choice(c, K_CMD_MODE,
			      c->at[K_CMD_MODE] ? c->value[K_CMD_MODE] : rows[K_CMD_MODE].key.default_text);
	if (st)
		return st;
	for (int k = 0; k < K_COUNT; k++) {
		const popc_map_key *d = &rows[k].key;
		const char *text = c->value[k];
		if (!in_mode(c, k)) {
			if (c->at[k])
				return wrong_mode(c, k);
			continue;
		}
		if (!c->at[k]) {
			if (d->required)
				return missing(c, k, d->required[0] ? d->required : NULL);
			if (!d->default_text)
				continue;
			text = d->default_text; /* in range: tests/modbus/test_register_map.c */
		}
		st = 0;
		switch (d->type) {
		case POPC_MAP_TEXT: break;
		case POPC_MAP_INT: st = parse_int(c, k, text); break;
		case POPC_MAP_NUMBER: st = parse_number(c, k, text); break;
		case POPC_MAP_CHOICE: st = parse_choice(c, k, text); break;
		case POPC_MAP_WORDS: st = parse_words(c, k, text); break;
		}
		if (st)
			return st;
	}
	return 0;
}

/* The parsed keys into their fields (rows[].store). */
static void store_keys(const load_ctx *c, popc_register_map *m)
{
	for (int k = 0; k < K_COUNT; k++) {
		const key_row *r = &rows[k];
		if ((!c->at[k] && !r->key.default_text) || !in_mode(c, k))
			continue;
		char *field = (char *)m + r->offset;
		/* each conversion only for its kind: the ranges of INT rows fit
		 * an int, those stored TO_U16 a uint16_t */
		switch (r->store) {
		case TO_NOWHERE: break;
		case TO_TEXT:
			snprintf(field, r->size, "%s", c->at[k] ? c->value[k] : r->key.default_text);
			break;
		case TO_INT:
		case TO_ENUM: {
			int i = (int)c->num[k];
			memcpy(field, &i, sizeof i);
			break;
		}
		case TO_U16: {
			uint16_t u = (uint16_t)c->num[k];
			memcpy(field, &u, sizeof u);
			break;
		}
		case TO_DOUBLE: memcpy(field, &c->num[k], sizeof(double)); break;
		case TO_WORDS:
			memcpy(field, c->words, (size_t)c->n_words * sizeof c->words[0]);
			memcpy((char *)m + r->count_offset, &c->n_words, sizeof c->n_words);
			break;
		}
	}
}

/* ---- the rules between keys ------------------------------------------------ */

/* timeout_ms x max_failures: how long a silent drive goes unnoticed */
static int link_silence(load_ctx *c, const popc_register_map *m)
{
	if ((long)m->timeout_ms * m->max_failures <= POPC_MAP_SILENCE_MAX_MS)
		return 0;
	/* the error's line: the later of the two keys (a default has none) */
	int at_t = c->at[K_DRIVE_TIMEOUT], at_f = c->at[K_DRIVE_FAILURES];
	char lt[24] = "default", lf[24] = "default";
	if (at_t)
		snprintf(lt, sizeof lt, "line %d", at_t);
	if (at_f)
		snprintf(lf, sizeof lf, "line %d", at_f);
	return popc_error_set(c->err, POPC_ERR_INVALID,
			      "%s:%d: drive.timeout_ms = %d (%s) x drive.max_failures = %d (%s) = %ld ms: "
			      "a silent drive must be declared lost within %d ms; lower one of them",
			      c->path, at_t > at_f ? at_t : at_f, m->timeout_ms, lt, m->max_failures, lf,
			      (long)m->timeout_ms * m->max_failures, POPC_MAP_SILENCE_MAX_MS);
}

/* Scale from "units per metre" keys: counts_per_m, or counts_per_rev with
 * lead_m (metres per screw revolution) and gear (motor revolutions per screw
 * revolution): counts_per_m = counts_per_rev * gear / lead_m. */
static int position_scale(load_ctx *c, popc_register_map *m)
{
	int direct = c->at[K_POS_CPM] != 0, via_rev = c->at[K_POS_CPR] != 0;
	if (direct && via_rev)
		return bad(c, K_POS_CPR, "give counts_per_m or counts_per_rev with lead_m, not both");
	if (!direct && !via_rev)
		return missing(c, K_POS_CPM, "or counts_per_rev with lead_m");
	if (direct) {
		if (c->at[K_POS_LEAD] || c->at[K_POS_GEAR])
			return bad(c, c->at[K_POS_LEAD] ? K_POS_LEAD : K_POS_GEAR,
				   "only used with counts_per_rev");
		m->pos.counts_per_m = c->num[K_POS_CPM];
		return 0;
	}
	if (!c->at[K_POS_LEAD])
		return missing(c, K_POS_LEAD, "counts_per_rev needs the lead (m per revolution)");
	m->pos.counts_per_m = c->num[K_POS_CPR] * c->num[K_POS_GEAR] / c->num[K_POS_LEAD];
	return 0;
}

static int soft_limits(load_ctx *c, const popc_register_map *m)
{
	if (m->pos.soft_min_m < m->pos.soft_max_m)
		return 0;
	char what[96];
	snprintf(what, sizeof what, "soft_max_m must be above soft_min_m = %g (line %d)",
		 m->pos.soft_min_m, c->at[K_POS_MIN]);
	return bad(c, K_POS_MAX, what);
}

/* newton_per_unit, or percent_of_rated_per_unit with rated_torque_Nm and
 * lead_m (and gear): a ball screw turns a motor torque tau into a force
 * F = 2 pi tau gear / lead (ideal screw, efficiency 1). */
static int command_scale(load_ctx *c, popc_register_map *m)
{
	int direct = c->at[K_CMD_NPU] != 0, pct = c->at[K_CMD_PPU] != 0;
	if (direct && pct)
		return bad(c, K_CMD_PPU, "give newton_per_unit or percent_of_rated_per_unit, not both");
	if (!direct && !pct)
		return missing(c, K_CMD_NPU, "or percent_of_rated_per_unit with rated_torque_Nm and lead_m");
	if (direct) {
		static const int torque_keys[] = {K_CMD_RATED, K_CMD_LEAD, K_CMD_GEAR};
		for (int i = 0; i < 3; i++)
			if (c->at[torque_keys[i]])
				return bad(c, torque_keys[i], "only used with percent_of_rated_per_unit");
		m->cmd.newton_per_unit = c->num[K_CMD_NPU];
		return 0;
	}
	if (!c->at[K_CMD_RATED])
		return missing(c, K_CMD_RATED, "percent_of_rated_per_unit needs the rated torque");
	if (!c->at[K_CMD_LEAD])
		return missing(c, K_CMD_LEAD, "percent_of_rated_per_unit needs the lead (m per revolution)");
	m->cmd.newton_per_unit = c->num[K_CMD_PPU] / 100.0 * c->num[K_CMD_RATED] * TWO_PI *
				 c->num[K_CMD_GEAR] / c->num[K_CMD_LEAD];
	return 0;
}

/* ---- derived scales: finite and usable both ways ---------------------------
 *
 * A scale inside its keys' ranges can still be unusable once keys combine or
 * divide: counts_per_rev 1e12 x gear 1e6 / lead_m 1e-300 is an infinite
 * counts_per_m (every position read as 0 m, so the soft limits never
 * tripped), newton_per_unit = 1e-320 put 20 N / 1e-320 = inf on the wire of a
 * float64 command, and a percent-of-rated scale underflowed to 0. So each
 * derived scale must be finite and above 0, and both directions of each
 * conversion must stay finite and in range for every value they can meet:
 * the commands |f| <= limit_N, every value the position and command
 * registers can hold, and the soft limits. Each message names the keys behind
 * the scale with their lines (a default: "(default)"); its own line is the
 * latest of them. */

/* "position.gear = 2 (line 10)", "position.gear = 1 (default)" */
static void key_term(const load_ctx *c, int k, char *buf, size_t cap)
{
	const popc_map_key *d = &rows[k].key;
	if (c->at[k])
		snprintf(buf, cap, "%s.%s = %s (line %d)", d->section, d->key, c->value[k], c->at[k]);
	else
		snprintf(buf, cap, "%s.%s = %s (default)", d->section, d->key,
			 d->default_text ? d->default_text : "?");
}

static int latest_line(const load_ctx *c, const int *keys, int n)
{
	int at = 0;
	for (int i = 0; i < n; i++)
		if (c->at[keys[i]] > at)
			at = c->at[keys[i]];
	return at;
}

/* The keys that make a scale, as "a x b / c"; ops[i] joins key i to i + 1. */
typedef struct scale_keys {
	int keys[5], n;
	const char *ops[4];
} scale_keys;

static scale_keys position_scale_keys(const load_ctx *c)
{
	if (c->at[K_POS_CPM])
		return (scale_keys){{K_POS_CPM}, 1, {NULL}};
	return (scale_keys){{K_POS_CPR, K_POS_GEAR, K_POS_LEAD}, 3, {" x ", " / "}};
}

static scale_keys command_scale_keys(const load_ctx *c)
{
	if (c->at[K_CMD_NPU])
		return (scale_keys){{K_CMD_NPU}, 1, {NULL}};
	return (scale_keys){{K_CMD_PPU, K_CMD_RATED, K_CMD_GEAR, K_CMD_LEAD},
			    4,
			    {" / 100 x ", " x 2 pi x ", " / "}};
}

static void describe_scale(const load_ctx *c, const scale_keys *s, char *buf, size_t cap)
{
	size_t n = 0;
	buf[0] = '\0';
	for (int i = 0; i < s->n && n < cap; i++) {
		char term[200];
		key_term(c, s->keys[i], term, sizeof term);
		n += (size_t)snprintf(buf + n, cap - n, "%s%s", term, i + 1 < s->n ? s->ops[i] : "");
	}
}

/* A refusal that blames a derived scale (and the extra keys, e.g. the
 * register's type): "FILE:LINE: SCALE KEYS: what". */
static int bad_scale(load_ctx *c, const scale_keys *s, const int *extra, int n_extra,
		     const char *what)
{
	char scale[700], extras[400] = "";
	describe_scale(c, s, scale, sizeof scale);
	size_t n = 0;
	for (int i = 0; i < n_extra && n < sizeof extras; i++) {
		char term[200];
		key_term(c, extra[i], term, sizeof term);
		n += (size_t)snprintf(extras + n, sizeof extras - n, ", %s", term);
	}
	int line = latest_line(c, s->keys, s->n), le = latest_line(c, extra, n_extra);
	return popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: %s%s: %s", c->path,
			      le > line ? le : line, scale, extras, what);
}

/* The smallest and largest value a register of type t can hold (finite
 * values: a float register's inf and NaN are no position and no force). */
static void type_range(popc_reg_type t, double *lo, double *hi)
{
	switch (t) {
	case POPC_REG_INT16: *lo = -32768.0, *hi = 32767.0; return;
	case POPC_REG_UINT16: *lo = 0.0, *hi = 65535.0; return;
	case POPC_REG_INT32: *lo = -2147483648.0, *hi = 2147483647.0; return;
	case POPC_REG_UINT32: *lo = 0.0, *hi = 4294967295.0; return;
	case POPC_REG_FLOAT32: *hi = (double)FLT_MAX, *lo = -*hi; return;
	case POPC_REG_FLOAT64: *hi = DBL_MAX, *lo = -*hi; return;
	}
	*lo = *hi = 0.0;
}

/* counts_per_m: finite and above 0; one count a finite length above 0; every
 * value the position register can hold a finite position (register value /
 * counts_per_m, as popc reads it). */
static int position_scale_usable(load_ctx *c, const popc_register_map *m)
{
	scale_keys s = position_scale_keys(c);
	char what[256];
	double cpm = m->pos.counts_per_m;
	if (!(isfinite(cpm) && cpm > 0.0)) {
		snprintf(what, sizeof what,
			 "gives counts_per_m = %g; the position scale must be a finite number above 0",
			 cpm);
		return bad_scale(c, &s, NULL, 0, what);
	}
	double one_count_m = 1.0 / cpm;
	if (!(isfinite(one_count_m) && one_count_m > 0.0)) {
		snprintf(what, sizeof what,
			 "one count is %g m at counts_per_m = %g; it must be a finite length above 0",
			 one_count_m, cpm);
		return bad_scale(c, &s, NULL, 0, what);
	}
	double lo, hi;
	type_range(m->pos.type, &lo, &hi);
	if (!isfinite(lo / cpm) || !isfinite(hi / cpm)) {
		static const int type_key[] = {K_POS_TYPE};
		snprintf(what, sizeof what,
			 "the %s position register's value %g reads as %g m at counts_per_m = %g; "
			 "every value it can hold must read as a finite position",
			 popc_reg_type_name(m->pos.type), hi, hi / cpm, cpm);
		return bad_scale(c, &s, type_key, 1, what);
	}
	return 0;
}

/* The soft limits in register units lie strictly inside the position
 * register's range: a drive past a limit must be able to report a value past
 * it (a register that saturates at the limit, or cannot hold a negative
 * position, would hold the reading inside and the limit would never trip). */
static int soft_limits_in_register(load_ctx *c, const popc_register_map *m)
{
	double lo, hi, cpm = m->pos.counts_per_m;
	type_range(m->pos.type, &lo, &hi);
	/* reversed: popc's limits [min, max] are [-max, -min] in the drive's frame */
	double sign = m->pos.reversed ? -1.0 : 1.0;
	double min_units = sign * (m->pos.reversed ? m->pos.soft_max_m : m->pos.soft_min_m) * cpm;
	double max_units = sign * (m->pos.reversed ? m->pos.soft_min_m : m->pos.soft_max_m) * cpm;
	int low = !(min_units > lo);
	if (!low && max_units < hi)
		return 0;
	scale_keys s = position_scale_keys(c);
	int limit_key = low != m->pos.reversed ? K_POS_MIN : K_POS_MAX; /* popc's key behind it */
	const int extra[] = {limit_key, K_POS_TYPE, K_POS_DIR};
	char what[300];
	snprintf(what, sizeof what,
		 "the soft limit is %.17g register units, not %s the %s position register's %s "
		 "value %.17g: a position past the limit could not be read, so the limit could "
		 "never trip",
		 low ? min_units : max_units, low ? "above" : "below", popc_reg_type_name(m->pos.type),
		 low ? "smallest" : "largest", low ? lo : hi);
	return bad_scale(c, &s, extra, m->pos.reversed ? 3 : 2, what);
}

/* newton_per_unit: finite and above 0 (a percent-of-rated product can
 * underflow to 0 or overflow). */
static int command_scale_usable(load_ctx *c, const popc_register_map *m)
{
	double npu = m->cmd.newton_per_unit;
	if (isfinite(npu) && npu > 0.0)
		return 0;
	scale_keys s = command_scale_keys(c);
	char what[160];
	snprintf(what, sizeof what,
		 "gives newton_per_unit = %g; the command scale must be a finite number above 0", npu);
	return bad_scale(c, &s, NULL, 0, what);
}

/* The command on the wire. popc clamps every force to [-limit_N, limit_N]
 * and writes f / newton_per_unit (modbus_axis.c), a monotone map, so the two
 * extremes bound every command: +-limit_N in command units must be finite,
 * fit the (signed) type and be at least one unit, and read back from the
 * register as a finite force within limit_N (plus half a unit, the nearest
 * rounding of the integer types, and float32's rounding). And every value the
 * register can hold must read as a finite force (a drive, or popc-servo-sim,
 * multiplies it by newton_per_unit): for float64, newton_per_unit <= 1. */
static int command_limit(load_ctx *c, const popc_register_map *m)
{
	static const int limit_key[] = {K_CMD_LIMIT}, type_key[] = {K_CMD_TYPE};
	scale_keys s = command_scale_keys(c);
	double npu = m->cmd.newton_per_unit, units = m->cmd.limit_N / npu;
	char what[300];
	if (!isfinite(units)) {
		snprintf(what, sizeof what,
			 "limit_N is %g command units at newton_per_unit = %g; a command on the wire "
			 "must be a finite value",
			 units, npu);
		return bad_scale(c, &s, limit_key, 1, what);
	}
	uint16_t w[4];
	int is_unsigned = m->cmd.type == POPC_REG_UINT16 || m->cmd.type == POPC_REG_UINT32;
	if (popc_reg_encode(units, m->cmd.type, m->cmd.order, w) || is_unsigned)
		return bad(c, K_CMD_LIMIT,
			   is_unsigned ? "an unsigned command type cannot carry a force of either sign"
				       : "limit_N in command units does not fit the command type");
	if (units < 1.0)
		return bad(c, K_CMD_LIMIT, "limit_N is below one command unit (newton_per_unit)");
	int integer = m->cmd.type != POPC_REG_FLOAT32 && m->cmd.type != POPC_REG_FLOAT64;
	double slack_N = (integer ? 0.5 * npu : 0.0) +
			 m->cmd.limit_N * (m->cmd.type == POPC_REG_FLOAT32 ? (double)FLT_EPSILON : 4 * DBL_EPSILON);
	for (int sign = -1; sign <= 1; sign += 2) {
		popc_reg_encode(sign * units, m->cmd.type, m->cmd.order, w);
		double back_N = popc_reg_decode(w, m->cmd.type, m->cmd.order) * npu;
		if (!(isfinite(back_N) && fabs(back_N) <= m->cmd.limit_N + slack_N)) {
			snprintf(what, sizeof what,
				 "a command of %g N reads back from the register as %g N, beyond limit_N",
				 sign * m->cmd.limit_N, back_N);
			return bad_scale(c, &s, limit_key, 1, what);
		}
	}
	double lo, hi;
	type_range(m->cmd.type, &lo, &hi);
	if (!isfinite(lo * npu) || !isfinite(hi * npu)) {
		snprintf(what, sizeof what,
			 "the %s command register's value %g reads as %g N at newton_per_unit = %g; "
			 "every value it can hold must read as a finite force",
			 popc_reg_type_name(m->cmd.type), hi, hi * npu, npu);
		return bad_scale(c, &s, type_key, 1, what);
	}
	return 0;
}

/* A servo command on the wire (mode = position or velocity): popc clamps
 * the position command to the soft limits and the velocity command to
 * +-limit_m_per_s, so the extremes bound every command, which must fit the
 * (signed, or for a position of one sign possibly unsigned) type without
 * saturating; a velocity clamp below one command unit could only command 0;
 * and every value the register can hold must read back as a finite position
 * or velocity (popc-servo-sim converts it). */
static int servo_command(load_ctx *c, const popc_register_map *m)
{
	int pos = m->cmd.mode == POPC_CMD_POSITION;
	int scale_key = pos ? K_CMD_CPM : K_CMD_MPS, type_key[] = {K_CMD_TYPE};
	scale_keys s = {{scale_key}, 1, {NULL}};
	/* units of the extremes, in the register's frame (reversed: minus) */
	double sign = m->cmd.reversed ? -1.0 : 1.0, lo_units, hi_units;
	if (pos) {
		lo_units = sign * m->pos.soft_min_m * m->cmd.counts_per_m;
		hi_units = sign * m->pos.soft_max_m * m->cmd.counts_per_m;
	} else {
		hi_units = m->cmd.limit_m_per_s / m->cmd.m_per_s_per_unit;
		lo_units = -hi_units;
	}
	char what[300];
	uint16_t w[4];
	double ends[2] = {lo_units, hi_units};
	for (int i = 0; i < 2; i++)
		if (!isfinite(ends[i]) || popc_reg_encode(ends[i], m->cmd.type, m->cmd.order, w)) {
			/* ends[0] comes from soft_min_m, ends[1] from soft_max_m */
			const int extra[] = {pos ? (i == 0 ? K_POS_MIN : K_POS_MAX) : K_CMD_VLIMIT,
					     K_CMD_TYPE, K_CMD_DIR};
			snprintf(what, sizeof what,
				 "the %s command's clamp is %.17g command units, which the %s command "
				 "register cannot hold",
				 pos ? "position" : "velocity", ends[i], popc_reg_type_name(m->cmd.type));
			return bad_scale(c, &s, extra, m->cmd.reversed ? 3 : 2, what);
		}
	if (!pos && hi_units < 1.0) {
		const int extra[] = {K_CMD_VLIMIT};
		return bad_scale(c, &s, extra, 1,
				 "limit_m_per_s is below one command unit: every command would be 0");
	}
	double lo, hi, per_unit = pos ? 1.0 / m->cmd.counts_per_m : m->cmd.m_per_s_per_unit;
	type_range(m->cmd.type, &lo, &hi);
	if (!isfinite(lo * per_unit) || !isfinite(hi * per_unit)) {
		snprintf(what, sizeof what,
			 "the %s command register's value %g reads as %g %s; every value it can hold "
			 "must read as a finite %s",
			 popc_reg_type_name(m->cmd.type), hi, hi * per_unit, pos ? "m" : "m/s",
			 pos ? "position" : "velocity");
		return bad_scale(c, &s, type_key, 1, what);
	}
	return 0;
}

/* The force sensor (mode = position or velocity): a signed type (the hand
 * pushes both ways), and every value the register can hold a finite force. */
static int force_sensor(load_ctx *c, const popc_register_map *m)
{
	if (m->sensor.type == POPC_REG_UINT16 || m->sensor.type == POPC_REG_UINT32)
		return bad(c, K_FS_TYPE, "an unsigned register cannot read a force of either sign");
	double lo, hi, npu = m->sensor.newton_per_unit;
	type_range(m->sensor.type, &lo, &hi);
	if (isfinite(lo * npu) && isfinite(hi * npu))
		return 0;
	scale_keys s = {{K_FS_NPU}, 1, {NULL}};
	const int type_key[] = {K_FS_TYPE};
	char what[300];
	snprintf(what, sizeof what,
		 "the %s force sensor register's value %g reads as %g N; every value it can hold "
		 "must read as a finite force",
		 popc_reg_type_name(m->sensor.type), hi, hi * npu);
	return bad_scale(c, &s, type_key, 1, what);
}

/* The command's own rules, by mode. */
static int command_rules(load_ctx *c, popc_register_map *m)
{
	int st;
	if (m->cmd.mode != POPC_CMD_FORCE) {
		if ((st = servo_command(c, m)))
			return st;
		return force_sensor(c, m);
	}
	if ((st = command_scale(c, m)) || (st = command_scale_usable(c, m)))
		return st;
	return command_limit(c, m);
}

static int enable_words(load_ctx *c, const popc_register_map *m)
{
	if (m->enable.table == POPC_TABLE_INPUT)
		return bad(c, K_EN_TABLE, "enable must be writable: holding or coil");
	if (m->enable.table == POPC_TABLE_COIL &&
	    (m->enable.n_on != 1 || m->enable.on[0] > 1 || m->enable.off > 1))
		return bad(c, K_EN_ON, "a coil enable takes on = 1 (or 0) and off = 0 (or 1)");
	if (m->enable.off == m->enable.on[m->enable.n_on - 1])
		return bad(c, K_EN_OFF, "off must differ from the last on word");
	return 0;
}

static int status_masks(load_ctx *c, const popc_register_map *m)
{
	if (m->status.ready_mask & m->status.fault_mask)
		return bad(c, K_ST_FAULT, "shares bits with ready_mask");
	return 0;
}

/* Registers [a, a + na) and [b, b + nb) of the same table overlap. */
static int overlap(int a, int na, int b, int nb)
{
	return a < b + nb && b < a + na;
}

/* The force sensor's registers against the others of its table (a sensor
 * in the holding table could be overwritten by a command or enable write). */
static int sensor_layout(load_ctx *c, const popc_register_map *m)
{
	int n = popc_reg_type_words(m->sensor.type), reg = m->sensor.reg;
	int holding = m->sensor.table == POPC_TABLE_HOLDING;
	if (reg + n > 65536)
		return bad(c, K_FS_REG, "the value runs past register 65535");
	if (m->sensor.table == m->pos.table &&
	    overlap(reg, n, m->pos.reg, popc_reg_type_words(m->pos.type)))
		return bad(c, K_FS_REG, "overlaps the position registers");
	if (m->sensor.table == m->status.table && overlap(reg, n, m->status.reg, 1))
		return bad(c, K_FS_REG, "overlaps the status register");
	if (holding && overlap(reg, n, m->cmd.reg, popc_reg_type_words(m->cmd.type)))
		return bad(c, K_FS_REG, "overlaps the command registers");
	if (holding && m->enable.table == POPC_TABLE_HOLDING && overlap(reg, n, m->enable.reg, 1))
		return bad(c, K_FS_REG, "overlaps the enable register");
	if (holding && c->at[K_CMD_SEQ] && overlap(reg, n, (int)c->num[K_CMD_SEQ], 1))
		return bad(c, K_FS_REG, "overlaps the command sequence register");
	return 0;
}

/* Registers that would step on each other. */
static int register_layout(load_ctx *c, const popc_register_map *m)
{
	int st;
	int npos = popc_reg_type_words(m->pos.type), ncmd = popc_reg_type_words(m->cmd.type);
	int en_holding = m->enable.table == POPC_TABLE_HOLDING;
	int pos_holding = m->pos.table == POPC_TABLE_HOLDING;
	int st_holding = m->status.table == POPC_TABLE_HOLDING;
	if (m->pos.reg + npos > 65536)
		return bad(c, K_POS_REG, "the value runs past register 65535");
	if (m->cmd.reg + ncmd > 65536)
		return bad(c, K_CMD_REG, "the value runs past register 65535");
	if (pos_holding && overlap(m->pos.reg, npos, m->cmd.reg, ncmd))
		return bad(c, K_CMD_REG, "overlaps the position registers");
	if (en_holding && overlap(m->enable.reg, 1, m->cmd.reg, ncmd))
		return bad(c, K_EN_REG, "overlaps the command registers");
	if (en_holding && pos_holding && overlap(m->enable.reg, 1, m->pos.reg, npos))
		return bad(c, K_EN_REG, "overlaps the position registers");
	if (m->status.table == m->pos.table && overlap(m->status.reg, 1, m->pos.reg, npos))
		return bad(c, K_ST_REG, "overlaps the position registers");
	if (st_holding && overlap(m->status.reg, 1, m->cmd.reg, ncmd))
		return bad(c, K_ST_REG, "overlaps the command registers");
	/* popc would read back its own enable word as the drive's status: with
	 * on = 1 and ready_mask = 1 a drive that never enabled would look ready */
	if (st_holding && en_holding && m->status.reg == m->enable.reg)
		return bad(c, K_ST_REG, "is the enable register (the status must be the drive's own word)");
	if (m->cmd.mode != POPC_CMD_FORCE && (st = sensor_layout(c, m)))
		return st;
	if (m->fc23 && !pos_holding)
		return bad(c, K_DRIVE_FC23, "FC23 reads holding registers; the position is an input register");
	return 0;
}

/* The optional command sequence register: a holding register right next to
 * the command, so that one FC06/FC16/FC23 write carries both (a drive sees a
 * command and its sequence value together or not at all). */
static int sequence_register(load_ctx *c, popc_register_map *m)
{
	m->cmd.seq_reg = -1;
	if (!c->at[K_CMD_SEQ])
		return 0;
	int v = (int)c->num[K_CMD_SEQ];
	int ncmd = popc_reg_type_words(m->cmd.type), before = m->cmd.reg - 1, after = m->cmd.reg + ncmd;
	if (v != before && v != after) {
		char what[200], where[64];
		if (before >= 0 && after <= 65535)
			snprintf(where, sizeof where, "%d or %d", before, after);
		else
			snprintf(where, sizeof where, "%d", before >= 0 ? before : after);
		snprintf(what, sizeof what,
			 "must be right next to the command registers %d..%d (%s), so that one write "
			 "carries both",
			 m->cmd.reg, after - 1, where);
		return bad(c, K_CMD_SEQ, what);
	}
	int npos = popc_reg_type_words(m->pos.type);
	if (m->pos.table == POPC_TABLE_HOLDING && overlap(v, 1, m->pos.reg, npos))
		return bad(c, K_CMD_SEQ, "overlaps the position registers");
	if (m->enable.table == POPC_TABLE_HOLDING && v == m->enable.reg)
		return bad(c, K_CMD_SEQ, "is the enable register");
	if (m->status.table == POPC_TABLE_HOLDING && v == m->status.reg)
		return bad(c, K_CMD_SEQ, "is the status register");
	m->cmd.seq_reg = v;
	return 0;
}

/* The RTU line keys: an RTS delay means nothing without RTS control. */
static int serial_line(load_ctx *c, popc_register_map *m)
{
	m->rts_delay_us = -1;
	if (!c->at[K_DRIVE_RTS_DELAY])
		return 0;
	if (m->rts == 0)
		return bad(c, K_DRIVE_RTS_DELAY, "only used with drive.rts = up or down");
	m->rts_delay_us = (int)c->num[K_DRIVE_RTS_DELAY];
	return 0;
}

/* The keys one by one (the table), then the rules between them, each
 * reported with the line of the key it blames. */
static int validate(load_ctx *c, popc_register_map *m)
{
	int st = parse_keys(c);
	if (st)
		return st;
	store_keys(c, m);
	if ((st = link_silence(c, m)) || (st = serial_line(c, m)) || (st = position_scale(c, m)) ||
	    (st = position_scale_usable(c, m)) || (st = soft_limits(c, m)) ||
	    (st = soft_limits_in_register(c, m)) || (st = command_rules(c, m)) ||
	    (st = enable_words(c, m)) || (st = status_masks(c, m)) || (st = register_layout(c, m)))
		return st;
	return sequence_register(c, m);
}

/* Shipped maps renamed by layout (issue 13): their vendor notes did not
 * hold. A path that names one and is not there gets the new name, not a
 * silent alias: the layout changed with the name. */
static const struct {
	const char *old_name, *new_name, *why;
} renamed_maps[] = {
	{"hilo-percent-torque", "hilo-int32",
	 "the AKD takes every value as two registers, high word first, and its current command "
	 "in Arms; for an int16 command next to an int32 position see hilo-int16-command"},
	{"cia402", "cia402-lohi",
	 "drives with a Modbus port put their CiA 402 objects at their own Modbus addresses, not "
	 "at the object index"},
};

/* "; renamed: ..." for a path whose file name is a renamed map's, else "" */
static const char *renamed_hint(const char *path, char *buf, size_t cap)
{
	const char *base = strrchr(path, '/');
	base = base ? base + 1 : path;
	for (size_t i = 0; i < sizeof renamed_maps / sizeof renamed_maps[0]; i++) {
		size_t n = strlen(renamed_maps[i].old_name);
		if (strncmp(base, renamed_maps[i].old_name, n) == 0 &&
		    (base[n] == '\0' || strcmp(base + n, ".ini") == 0)) {
			snprintf(buf, cap,
				 "; the shipped map %s.ini was renamed to %s.ini (%s; docs/MODBUS.md, "
				 "\"Shipped maps\")",
				 renamed_maps[i].old_name, renamed_maps[i].new_name, renamed_maps[i].why);
			return buf;
		}
	}
	return "";
}

int popc_register_map_load(popc_register_map *m, const char *path, popc_error *err)
{
	memset(m, 0, sizeof *m);
	m->cmd.seq_reg = -1;
	load_ctx *c = calloc(1, sizeof *c);
	if (!c)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	c->path = path;
	c->err = err;
	c->f = fopen(path, "r");
	/* a map that cannot be read is bad input (exit 2), as for a scene */
	if (!c->f) {
		int e = errno;
		char hint[512];
		int st = popc_error_set(err, POPC_ERR_INVALID, "%s: cannot open the register map: %s%s",
					path, strerror(e),
					e == ENOENT ? renamed_hint(path, hint, sizeof hint) : "");
		free(c);
		return st;
	}
	int line = ini_parse_stream(read_line, c, map_handler, c);
	/* fgets ends at the end of the file and on a read error (a directory:
	 * EISDIR), which must not read as an empty map ("missing ...") */
	int read_failed = ferror(c->f), read_errno = errno;
	fclose(c->f);
	int st = c->status;
	if (!st && read_failed)
		st = popc_error_set(err, POPC_ERR_INVALID, "%s: cannot read the register map: %s", path,
				    strerror(read_errno));
	else if (!st && line < 0)
		st = popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory while reading", path);
	else if (!st && line > 0)
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s:%d: malformed line (expected [section], key = value, or a ; comment)",
				    path, line);
	if (!st)
		st = validate(c, m);
	if (!st)
		snprintf(m->path, sizeof m->path, "%s", path);
	free(c);
	return st;
}
