/* Register map files (register_map.h): INI via libinih, then validation with
 * file, line and key in every message, and the word conversions. */
#include "popc/axes/register_map.h"

#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/scene/ini_lines.h"
#include "popc/util/parse.h"

#define TWO_PI 6.283185307179586476925286766559

/* ---- word conversion ----------------------------------------------------- */

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

static const char *const type_names[] = {"int16", "uint16", "int32", "uint32", "float32", "float64",
					 NULL};

const char *popc_reg_type_name(popc_reg_type t)
{
	return (unsigned)t < 6 ? type_names[t] : "?";
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

/* ---- loading ------------------------------------------------------------- */

/* Every key a map may hold; values are kept as text with their line, and
 * checked once the whole file is read (so cross-key errors also have a line). */
enum {
	K_DRIVE_NAME, K_DRIVE_SLAVE, K_DRIVE_FC23, K_DRIVE_TIMEOUT, K_DRIVE_FAILURES,
	K_DRIVE_ENABLE_TIMEOUT, K_DRIVE_WATCHDOG,
	K_POS_REG, K_POS_TABLE, K_POS_TYPE, K_POS_ORDER, K_POS_CPM, K_POS_CPR, K_POS_LEAD,
	K_POS_GEAR, K_POS_MIN, K_POS_MAX,
	K_CMD_REG, K_CMD_TABLE, K_CMD_TYPE, K_CMD_ORDER, K_CMD_NPU, K_CMD_PPU, K_CMD_RATED,
	K_CMD_LEAD, K_CMD_GEAR, K_CMD_LIMIT, K_CMD_SEQ,
	K_EN_REG, K_EN_TABLE, K_EN_ON, K_EN_OFF,
	K_ST_REG, K_ST_TABLE, K_ST_READY, K_ST_FAULT,
	K_COUNT
};

static const struct {
	const char *section, *key;
} map_keys[K_COUNT] = {
	{"drive", "name"}, {"drive", "slave"}, {"drive", "fc23"}, {"drive", "timeout_ms"},
	{"drive", "max_failures"}, {"drive", "enable_timeout_ms"}, {"drive", "watchdog_ms"},
	{"position", "register"}, {"position", "table"}, {"position", "type"},
	{"position", "word_order"}, {"position", "counts_per_m"}, {"position", "counts_per_rev"},
	{"position", "lead_m"}, {"position", "gear"}, {"position", "soft_min_m"},
	{"position", "soft_max_m"},
	{"command", "register"}, {"command", "table"}, {"command", "type"}, {"command", "word_order"},
	{"command", "newton_per_unit"}, {"command", "percent_of_rated_per_unit"},
	{"command", "rated_torque_Nm"}, {"command", "lead_m"}, {"command", "gear"},
	{"command", "limit_N"}, {"command", "sequence_register"},
	{"enable", "register"}, {"enable", "table"}, {"enable", "on"}, {"enable", "off"},
	{"status", "register"}, {"status", "table"}, {"status", "ready_mask"}, {"status", "fault_mask"},
};

typedef struct load_ctx {
	FILE *f;
	int line;
	const char *path;
	char value[K_COUNT][128];
	int at[K_COUNT];           /* line of the key, 0: not given */
	int status;
	popc_error *err;
} load_ctx;

/* libinih's reader: one call per line. A line that does not fit the buffer
 * (num - 1 characters) would come back in pieces, each counted as a line by
 * libinih and by us (every later message would name the wrong line) and the
 * tail parsed as a line of its own; so it is refused here, with its real
 * number (ini_lines.h). */
static char *read_line(char *str, int num, void *stream)
{
	load_ctx *c = stream;
	if (c->status)
		return NULL;
	int too_long = 0;
	char *r = popc_ini_read_line(str, num, c->f, &c->line, &too_long);
	if (too_long == 2)
		c->status = popc_error_set(c->err, POPC_ERR_INVALID,
					   "%s:%d: a NUL byte in the line (a register map is a text file)",
					   c->path, c->line);
	else if (too_long)
		c->status = popc_error_set(c->err, POPC_ERR_INVALID,
					   "%s:%d: line longer than %d characters (shorten the comment or value)",
					   c->path, c->line, num - 1);
	return r;
}

static int map_handler(void *user, const char *section, const char *name, const char *value)
{
	load_ctx *c = user;
	if (c->status)
		return 1;
	int known_section = 0;
	for (int i = 0; i < K_COUNT; i++) {
		if (strcmp(section, map_keys[i].section) != 0)
			continue;
		known_section = 1;
		if (strcmp(name, map_keys[i].key) != 0)
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
	if (!known_section)
		c->status = popc_error_set(c->err, POPC_ERR_INVALID,
					   "%s:%d: unknown section [%s] (allowed: drive, position, "
					   "command, enable, status)",
					   c->path, c->line, section);
	else
		c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: unknown key %s.%s",
					   c->path, c->line, section, name);
	return 0;
}

static int bad(load_ctx *c, int k, const char *what)
{
	return popc_error_set(c->err, POPC_ERR_INVALID, "%s:%d: %s.%s = %s: %s", c->path, c->at[k],
			      map_keys[k].section, map_keys[k].key, c->value[k], what);
}

static int missing(load_ctx *c, int k, const char *why)
{
	return popc_error_set(c->err, POPC_ERR_INVALID, "%s: missing %s.%s%s%s", c->path,
			      map_keys[k].section, map_keys[k].key, why ? ": " : "", why ? why : "");
}

/* An integer as the docs promise it: a whole number as everywhere
 * (popc/util/parse.h), or hexadecimal with 0x. Never strtol's base 0, which
 * reads a leading zero as octal: "0100" copied from a manual's register table
 * would silently become register 64. */
/* Integer in [lo, hi], decimal or 0x hex. def is used when the key is absent
 * and def_ok; otherwise absence is an error. */
static int get_int(load_ctx *c, int k, long lo, long hi, int def_ok, long def, long *out)
{
	if (!c->at[k]) {
		if (!def_ok)
			return missing(c, k, NULL);
		*out = def;
		return 0;
	}
	const char *text = c->value[k];
	long long v;
	if (popc_parse_ll_span(text, text + strlen(text), lo, hi, POPC_PARSE_HEX, &v) != 0) {
		char what[96];
		snprintf(what, sizeof what, "expected an integer in [%ld, %ld]", lo, hi);
		return bad(c, k, what);
	}
	*out = (long)v;
	return 0;
}

/* Finite number in (lo, hi] when open_lo, else [lo, hi]. */
static int get_num(load_ctx *c, int k, double lo, double hi, int open_lo, double def, double *out)
{
	if (!c->at[k]) {
		*out = def;
		return 0;
	}
	/* a number as scene values (popc/util/parse.h: no hex floats, no
	 * "inf"/"nan", exact rounding) */
	double v;
	if (popc_parse_double_text(c->value[k], &v) != 0 || v > hi || v < lo || (open_lo && v == lo)) {
		char what[96];
		snprintf(what, sizeof what, "expected a number in %c%g, %g]", open_lo ? '(' : '[', lo, hi);
		return bad(c, k, what);
	}
	*out = v;
	return 0;
}

static int get_enum(load_ctx *c, int k, const char *const *names, int def, int *out)
{
	if (!c->at[k]) {
		if (def < 0)
			return missing(c, k, NULL);
		*out = def;
		return 0;
	}
	for (int i = 0; names[i]; i++)
		if (strcmp(c->value[k], names[i]) == 0) {
			*out = i;
			return 0;
		}
	char what[160] = "expected one of:";
	for (int i = 0; names[i]; i++) {
		strncat(what, " ", sizeof what - strlen(what) - 1);
		strncat(what, names[i], sizeof what - strlen(what) - 1);
	}
	return bad(c, k, what);
}

static const char *const yes_no[] = {"no", "yes", NULL};
static const char *const read_tables[] = {"holding", "input", NULL};
static const char *const enable_tables[] = {"holding", "input", "coil", NULL};
static const char *const orders[] = {"hi-lo", "lo-hi", NULL};

/* Scale from "units per metre" keys: counts_per_m, or counts_per_rev with
 * lead_m (metres per screw revolution) and gear (motor revolutions per screw
 * revolution): counts_per_m = counts_per_rev * gear / lead_m. */
static int position_scale(load_ctx *c, double *counts_per_m)
{
	int direct = c->at[K_POS_CPM] != 0, via_rev = c->at[K_POS_CPR] != 0;
	if (direct && via_rev)
		return bad(c, K_POS_CPR, "give counts_per_m or counts_per_rev with lead_m, not both");
	if (!direct && !via_rev)
		return missing(c, K_POS_CPM, "or counts_per_rev with lead_m");
	int st;
	if (direct) {
		if (c->at[K_POS_LEAD] || c->at[K_POS_GEAR])
			return bad(c, c->at[K_POS_LEAD] ? K_POS_LEAD : K_POS_GEAR,
				   "only used with counts_per_rev");
		return get_num(c, K_POS_CPM, 0, 1e15, 1, 0, counts_per_m);
	}
	double cpr, lead, gear;
	if ((st = get_num(c, K_POS_CPR, 0, 1e12, 1, 0, &cpr)))
		return st;
	if (!c->at[K_POS_LEAD])
		return missing(c, K_POS_LEAD, "counts_per_rev needs the lead (m per revolution)");
	if ((st = get_num(c, K_POS_LEAD, 0, 10, 1, 0, &lead)) ||
	    (st = get_num(c, K_POS_GEAR, 0, 1e6, 1, 1, &gear)))
		return st;
	*counts_per_m = cpr * gear / lead;
	return 0;
}

/* newton_per_unit, or percent_of_rated_per_unit with rated_torque_Nm and
 * lead_m (and gear): a ball screw turns a motor torque tau into a force
 * F = 2 pi tau gear / lead (ideal screw, efficiency 1). */
static int command_scale(load_ctx *c, double *newton_per_unit)
{
	int direct = c->at[K_CMD_NPU] != 0, pct = c->at[K_CMD_PPU] != 0;
	if (direct && pct)
		return bad(c, K_CMD_PPU, "give newton_per_unit or percent_of_rated_per_unit, not both");
	if (!direct && !pct)
		return missing(c, K_CMD_NPU, "or percent_of_rated_per_unit with rated_torque_Nm and lead_m");
	int st;
	if (direct) {
		for (int k = K_CMD_RATED; k <= K_CMD_GEAR; k++)
			if (c->at[k])
				return bad(c, k, "only used with percent_of_rated_per_unit");
		return get_num(c, K_CMD_NPU, 0, 1e9, 1, 0, newton_per_unit);
	}
	double ppu, rated, lead, gear;
	if ((st = get_num(c, K_CMD_PPU, 0, 100, 1, 0, &ppu)))
		return st;
	if (!c->at[K_CMD_RATED])
		return missing(c, K_CMD_RATED, "percent_of_rated_per_unit needs the rated torque");
	if (!c->at[K_CMD_LEAD])
		return missing(c, K_CMD_LEAD, "percent_of_rated_per_unit needs the lead (m per revolution)");
	if ((st = get_num(c, K_CMD_RATED, 0, 1e6, 1, 0, &rated)) ||
	    (st = get_num(c, K_CMD_LEAD, 0, 10, 1, 0, &lead)) ||
	    (st = get_num(c, K_CMD_GEAR, 0, 1e6, 1, 1, &gear)))
		return st;
	*newton_per_unit = ppu / 100.0 * rated * TWO_PI * gear / lead;
	return 0;
}

/* "on" holds one to four words separated by commas or spaces (a CiA-402
 * drive goes shutdown 0x06, switch on 0x07, enable operation 0x0F). */
static int enable_words(load_ctx *c, popc_register_map *m)
{
	if (!c->at[K_EN_ON])
		return missing(c, K_EN_ON, NULL);
	const char *p = c->value[K_EN_ON];
	m->enable.n_on = 0;
	while (*p) {
		while (*p == ' ' || *p == ',' || *p == '\t')
			p++;
		if (!*p)
			break;
		if (m->enable.n_on == POPC_MAP_ENABLE_MAX)
			return bad(c, K_EN_ON, "at most 4 words");
		const char *end = p + strcspn(p, " ,\t");
		long long v;
		if (popc_parse_ll_span(p, end, 0, 0xFFFF, POPC_PARSE_HEX, &v) != 0)
			return bad(c, K_EN_ON, "expected words in [0, 0xFFFF] separated by commas");
		m->enable.on[m->enable.n_on++] = (uint16_t)v;
		p = end;
	}
	if (m->enable.n_on == 0)
		return bad(c, K_EN_ON, "expected at least one word");
	return 0;
}

/* Registers [a, a + na) and [b, b + nb) of the same table overlap. */
static int overlap(int a, int na, int b, int nb)
{
	return a < b + nb && b < a + na;
}

/* The optional command sequence register: a holding register right next to
 * the command, so that one FC06/FC16/FC23 write carries both (a drive sees a
 * command and its sequence value together or not at all). */
static int sequence_register(load_ctx *c, popc_register_map *m)
{
	m->cmd.seq_reg = -1;
	if (!c->at[K_CMD_SEQ])
		return 0;
	long v;
	int st = get_int(c, K_CMD_SEQ, 0, 65535, 0, 0, &v);
	if (st)
		return st;
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
	if (m->pos.table == POPC_TABLE_HOLDING && overlap((int)v, 1, m->pos.reg, npos))
		return bad(c, K_CMD_SEQ, "overlaps the position registers");
	if (m->enable.table == POPC_TABLE_HOLDING && v == m->enable.reg)
		return bad(c, K_CMD_SEQ, "is the enable register");
	if (m->status.table == POPC_TABLE_HOLDING && v == m->status.reg)
		return bad(c, K_CMD_SEQ, "is the status register");
	m->cmd.seq_reg = (int)v;
	return 0;
}

static int validate(load_ctx *c, popc_register_map *m)
{
	long v;
	int e, st;
	snprintf(m->name, sizeof m->name, "%s", c->at[K_DRIVE_NAME] ? c->value[K_DRIVE_NAME] : "unnamed drive");
	/* Modbus over serial line spec V1.02, 2.2: unicast addresses 1..247 */
	if ((st = get_int(c, K_DRIVE_SLAVE, 1, 247, 1, 1, &v)))
		return st;
	m->slave = (int)v;
	if ((st = get_enum(c, K_DRIVE_FC23, yes_no, 0, &m->fc23)))
		return st;
	if ((st = get_int(c, K_DRIVE_TIMEOUT, 1, 10000, 1, 20, &v)))
		return st;
	m->timeout_ms = (int)v;
	if ((st = get_int(c, K_DRIVE_FAILURES, 1, 100, 1, 3, &v)))
		return st;
	m->max_failures = (int)v;
	if ((long)m->timeout_ms * m->max_failures > POPC_MAP_SILENCE_MAX_MS) {
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
	if ((st = get_int(c, K_DRIVE_ENABLE_TIMEOUT, 0, 60000, 1, 500, &v)))
		return st;
	m->enable_timeout_ms = (int)v;
	if ((st = get_int(c, K_DRIVE_WATCHDOG, 0, 600000, 1, 0, &v)))
		return st;
	m->watchdog_ms = (int)v;

	if ((st = get_int(c, K_POS_REG, 0, 65535, 0, 0, &v)))
		return st;
	m->pos.reg = (int)v;
	if ((st = get_enum(c, K_POS_TABLE, read_tables, 0, &e)))
		return st;
	m->pos.table = (popc_reg_table)e;
	if ((st = get_enum(c, K_POS_TYPE, type_names, -1, &e)))
		return st;
	m->pos.type = (popc_reg_type)e;
	if ((st = get_enum(c, K_POS_ORDER, orders, 0, &e)))
		return st;
	m->pos.order = (popc_word_order)e;
	if ((st = position_scale(c, &m->pos.counts_per_m)))
		return st;
	/* soft limits are part of the always-on supervisor: no map goes without */
	if (!c->at[K_POS_MIN] || !c->at[K_POS_MAX])
		return missing(c, c->at[K_POS_MIN] ? K_POS_MAX : K_POS_MIN,
			       "the position soft limits soft_min_m and soft_max_m are required "
			       "(safety is always on)");
	if ((st = get_num(c, K_POS_MIN, -1e3, 1e3, 0, 0, &m->pos.soft_min_m)) ||
	    (st = get_num(c, K_POS_MAX, -1e3, 1e3, 0, 0, &m->pos.soft_max_m)))
		return st;
	if (m->pos.soft_min_m >= m->pos.soft_max_m) {
		char what[96];
		snprintf(what, sizeof what, "soft_max_m must be above soft_min_m = %g (line %d)",
			 m->pos.soft_min_m, c->at[K_POS_MIN]);
		return bad(c, K_POS_MAX, what);
	}

	if ((st = get_int(c, K_CMD_REG, 0, 65535, 0, 0, &v)))
		return st;
	m->cmd.reg = (int)v;
	if (c->at[K_CMD_TABLE] && strcmp(c->value[K_CMD_TABLE], "holding") != 0)
		return bad(c, K_CMD_TABLE, "the command must be a holding register (written with FC06/16/23)");
	if ((st = get_enum(c, K_CMD_TYPE, type_names, -1, &e)))
		return st;
	m->cmd.type = (popc_reg_type)e;
	if ((st = get_enum(c, K_CMD_ORDER, orders, 0, &e)))
		return st;
	m->cmd.order = (popc_word_order)e;
	if ((st = command_scale(c, &m->cmd.newton_per_unit)))
		return st;
	if (!c->at[K_CMD_LIMIT])
		return missing(c, K_CMD_LIMIT, "the force clamp is not optional");
	if ((st = get_num(c, K_CMD_LIMIT, 0, 1e6, 1, 0, &m->cmd.limit_N)))
		return st;
	/* the clamp must be representable: limit_N in command units within the type */
	uint16_t w[4];
	if (popc_reg_encode(m->cmd.limit_N / m->cmd.newton_per_unit, m->cmd.type, m->cmd.order, w) ||
	    ((m->cmd.type == POPC_REG_UINT16 || m->cmd.type == POPC_REG_UINT32)))
		return bad(c, K_CMD_LIMIT,
			   m->cmd.type == POPC_REG_UINT16 || m->cmd.type == POPC_REG_UINT32
				   ? "an unsigned command type cannot carry a force of either sign"
				   : "limit_N in command units does not fit the command type");
	if (m->cmd.limit_N / m->cmd.newton_per_unit < 1.0)
		return bad(c, K_CMD_LIMIT, "limit_N is below one command unit (newton_per_unit)");

	if ((st = get_int(c, K_EN_REG, 0, 65535, 0, 0, &v)))
		return st;
	m->enable.reg = (int)v;
	if ((st = get_enum(c, K_EN_TABLE, enable_tables, 0, &e)))
		return st;
	if (e == POPC_TABLE_INPUT)
		return bad(c, K_EN_TABLE, "enable must be writable: holding or coil");
	m->enable.table = (popc_reg_table)e;
	if ((st = enable_words(c, m)))
		return st;
	if ((st = get_int(c, K_EN_OFF, 0, 0xFFFF, 0, 0, &v)))
		return st;
	m->enable.off = (uint16_t)v;
	if (m->enable.table == POPC_TABLE_COIL) {
		if (m->enable.n_on != 1 || m->enable.on[0] > 1 || m->enable.off > 1)
			return bad(c, K_EN_ON, "a coil enable takes on = 1 (or 0) and off = 0 (or 1)");
	}
	if (m->enable.off == m->enable.on[m->enable.n_on - 1])
		return bad(c, K_EN_OFF, "off must differ from the last on word");

	if ((st = get_int(c, K_ST_REG, 0, 65535, 0, 0, &v)))
		return st;
	m->status.reg = (int)v;
	if ((st = get_enum(c, K_ST_TABLE, read_tables, 0, &e)))
		return st;
	m->status.table = (popc_reg_table)e;
	if ((st = get_int(c, K_ST_READY, 0, 0xFFFF, 1, 0, &v)))
		return st;
	m->status.ready_mask = (uint16_t)v;
	if ((st = get_int(c, K_ST_FAULT, 1, 0xFFFF, 0, 0, &v)))
		return st;
	m->status.fault_mask = (uint16_t)v;
	if (m->status.ready_mask & m->status.fault_mask)
		return bad(c, K_ST_FAULT, "shares bits with ready_mask");

	/* registers that would step on each other */
	int npos = popc_reg_type_words(m->pos.type), ncmd = popc_reg_type_words(m->cmd.type);
	if (m->pos.reg + npos > 65536)
		return bad(c, K_POS_REG, "the value runs past register 65535");
	if (m->cmd.reg + ncmd > 65536)
		return bad(c, K_CMD_REG, "the value runs past register 65535");
	if (m->pos.table == POPC_TABLE_HOLDING && overlap(m->pos.reg, npos, m->cmd.reg, ncmd))
		return bad(c, K_CMD_REG, "overlaps the position registers");
	if (m->enable.table == POPC_TABLE_HOLDING && overlap(m->enable.reg, 1, m->cmd.reg, ncmd))
		return bad(c, K_EN_REG, "overlaps the command registers");
	if (m->enable.table == POPC_TABLE_HOLDING && m->pos.table == POPC_TABLE_HOLDING &&
	    overlap(m->enable.reg, 1, m->pos.reg, npos))
		return bad(c, K_EN_REG, "overlaps the position registers");
	if (m->status.table == m->pos.table && overlap(m->status.reg, 1, m->pos.reg, npos))
		return bad(c, K_ST_REG, "overlaps the position registers");
	if (m->status.table == POPC_TABLE_HOLDING && overlap(m->status.reg, 1, m->cmd.reg, ncmd))
		return bad(c, K_ST_REG, "overlaps the command registers");
	/* popc would read back its own enable word as the drive's status: with
	 * on = 1 and ready_mask = 1 a drive that never enabled would look ready */
	if (m->status.table == POPC_TABLE_HOLDING && m->enable.table == POPC_TABLE_HOLDING &&
	    m->status.reg == m->enable.reg)
		return bad(c, K_ST_REG, "is the enable register (the status must be the drive's own word)");
	if (m->fc23 && m->pos.table != POPC_TABLE_HOLDING)
		return bad(c, K_DRIVE_FC23, "FC23 reads holding registers; the position is an input register");
	return sequence_register(c, m);
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
		int st = popc_error_set(err, POPC_ERR_INVALID, "%s: cannot open the register map: %s", path,
					strerror(errno));
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
