/* Scene keys, defaults, INI loading, --set overrides and the resolved dump.
 * Every key is declared once, in scene_keys[] below. */
#include "popc/scene/scene.h"

#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "popc/scene/data_path.h"
#include "popc/scene/delay_trace.h"
#include "popc/scene/ini_lines.h"
#include "popc/util/numfmt.h"
#include "popc/util/parse.h"
#include "popc/util/text.h"
#include "popc/core/channel.h"
#include "popc/core/velocity.h"

typedef enum { KEY_DOUBLE, KEY_INT, KEY_ENUM, KEY_STRING } key_type;

typedef struct scene_key {
	const char *section, *key;
	key_type type;
	size_t offset;
	double min, max;          /* inclusive range, for numbers */
	int min_open;             /* 1: the range is (min, max] */
	const char *unit;
	const char *const *names; /* KEY_ENUM: NULL-terminated names, index = value */
	const char *help;
	const char *def;          /* the default, as a scene file spells it (set_key reads it) */
	int declared_only;        /* physics modelled only when declared: written (resolved
				   * scene, log header) only when not 0, so that a scene
				   * without it keeps its bytes; ADMITTANCE_ONLY: only in a
				   * scene with device.causality = admittance; WRITTEN_FOR_EB:
				   * a key of energy-bounding, written only when that is the
				   * variant, so that every other variant's log keeps its bytes;
				   * TELEOP_ONLY: only in a scene with teleop.architecture
				   * not off (every one-port scene keeps its bytes);
				   * TELEOP_USED: a teleoperation key written only when
				   * not at its default (0, the first name, empty), so
				   * every teleoperation log before it keeps its bytes;
				   * DRIFT_ONLY: with teleop.drift not off */
} scene_key;

/* declared_only's values beside 0 (always written) and 1 (written when not 0) */
enum { ADMITTANCE_ONLY = 2, WRITTEN_FOR_EB = 3, TELEOP_ONLY = 4, TELEOP_USED = 5, DRIFT_ONLY = 6,
       PP_ONLY = 7 };

static const char *const axis_names[] = {"sim", "modbus", NULL};
static const char *const off_on_names[] = {"off", "on", NULL};
static const char *const jitter_model_names[] = {"uniform", "walk", NULL};

#define OFF(field) offsetof(popc_scene, field)
#define NUM(sec, k, field, def, lo, hi, open, unit, help) \
	{sec, k, KEY_DOUBLE, OFF(field), lo, hi, open, unit, NULL, help, def, 0}
#define NUM_DECLARED(sec, k, field, lo, hi, unit, help) \
	{sec, k, KEY_DOUBLE, OFF(field), lo, hi, 0, unit, NULL, help, "0", 1}
#define NUM_ADM(k, field, def, lo, hi, open, unit, help) \
	{"admittance", k, KEY_DOUBLE, OFF(field), lo, hi, open, unit, NULL, help, def, ADMITTANCE_ONLY}
#define NUM_TELE(sec, k, field, def, lo, hi, open, unit, help) \
	{sec, k, KEY_DOUBLE, OFF(field), lo, hi, open, unit, NULL, help, def, TELEOP_ONLY}
#define NUM_PP(k, field, def, lo, hi, open, unit, help) \
	{"teleop", k, KEY_DOUBLE, OFF(field), lo, hi, open, unit, NULL, help, def, PP_ONLY}
#define INT_TELE(sec, k, field, def, lo, hi, unit, help) \
	{sec, k, KEY_INT, OFF(field), lo, hi, 0, unit, NULL, help, def, TELEOP_ONLY}
/* one direction of the channel (core/channel.h), [forward] or [backward] */
#define CHANNEL_KEYS(sec, dir, seed0)                                                             \
	INT_TELE(sec, "delay_ticks", dir.delay_ticks, "0", 0, POPC_CHANNEL_MAX_DELAY_TICKS, "periods", \
		 "constant delay of every packet"),                                                \
	INT_TELE(sec, "jitter_ticks", dir.jitter_ticks, "0", 0, POPC_CHANNEL_MAX_DELAY_TICKS,      \
		 "periods", "plus a whole number uniform in [0, jitter_ticks] a packet"),          \
	NUM_TELE(sec, "loss", dir.loss, "0", 0, 0.999, 0, "", "probability a packet is lost "     \
		 "(the receiver holds the last)"),                                                  \
	{sec, "in_order", KEY_ENUM, OFF(dir.in_order), 0, 0, 0, "", off_on_names,                   \
	 "on: first sent, first delivered (TCP); off: jitter reorders (UDP)", "on", TELEOP_ONLY},  \
	INT_TELE(sec, "seed", dir.seed, seed0, 0, 2147483647.0, "",                                  \
		 "seed of the loss and jitter draws (splitmix64)"),                                    \
	{sec, "delay_s", KEY_DOUBLE, OFF(dir.delay_s), 0, 100, 0, "s", NULL,                       \
	 "constant delay in seconds, a whole number of periods (instead of delay_ticks)", "0",      \
	 TELEOP_USED},                                                                             \
	{sec, "jitter_s", KEY_DOUBLE, OFF(dir.jitter_s), 0, 100, 0, "s", NULL,                     \
	 "jitter in seconds, a whole number of periods (instead of jitter_ticks)", "0",            \
	 TELEOP_USED},                                                                             \
	{sec, "jitter_model", KEY_ENUM, OFF(dir.jitter_model), 0, 0, 0, "", jitter_model_names,    \
	 "uniform: each packet's jitter drawn anew; walk: a random walk of +-1 tick a packet "    \
	 "within [0, jitter]", "uniform", TELEOP_USED},                                             \
	{sec, "trace", KEY_STRING, OFF(dir.trace), 0, 0, 0, "path", NULL,                          \
	 "file of delays, one a packet, repeated (instead of the delay and jitter keys)", "",       \
	 TELEOP_USED}

static const scene_key scene_keys[] = {
	NUM("run", "duration", duration_s, "5", 0, 1e7, 1, "s", "simulated time"),
	NUM("run", "rate", rate_Hz, "1000", 1, 1e6, 0, "Hz", "control rate 1/T"),
	{"run", "delay_ticks", KEY_INT, OFF(delay_ticks), 0, POPC_SCENE_MAX_DELAY_TICKS, 0, "periods", NULL,
	 "loop delay: the command of tick k acts over period k + delay_ticks", "0", 0},

	NUM("operator", "mass", op_mass_kg, "0.1", 0, 1e3, 0, "kg", "hand mass M_HO"),
	NUM("operator", "damping", op_damping_Nspm, "0.5", 0, 1e6, 0, "N s/m", "hand damping B_HO"),
	NUM("operator", "stiffness", op_stiffness_Npm, "50", 0, 1e9, 0, "N/m", "hand stiffness K_HO"),
	{"operator", "intent", KEY_ENUM, OFF(intent), 0, 0, 0, "", popc_intent_kind_names,
	 "what the operator wants: x_d(t) or a force", "ramp", 0},
	NUM("operator", "x0", op_x0_m, "-0.0065", -1e3, 1e3, 0, "m", "rest position of the hand (start of x_d)"),
	NUM("operator", "t0", op_t0_s, "0.1", 0, 1e7, 0, "s", "start of the ramp, force or sine"),
	NUM("operator", "speed", op_speed_mps, "0.045", 0, 1e3, 1, "m/s", "ramp speed"),
	NUM("operator", "x_end", op_x_end_m, "0.02", -1e3, 1e3, 0, "m", "ramp end position"),
	NUM("operator", "force", op_force_N, "1", -1e6, 1e6, 0, "N", "force intent: held force"),
	NUM("operator", "force_rate", op_force_rate_Nps, "10", 0, 1e9, 1, "N/s", "force intent: rise rate"),
	NUM("operator", "amplitude", op_amplitude_m, "0.005", 0, 1e3, 0, "m", "sine amplitude"),
	NUM("operator", "frequency", op_frequency_Hz, "1", 0, 1e5, 0, "Hz", "sine frequency"),
	{"operator", "table", KEY_STRING, OFF(op_table), 0, 0, 0, "path", NULL,
	 "table intent: CSV of t,value rows (relative to the scene file; on the command "
	 "line, to the working directory)", "", 0},
	{"operator", "table_quantity", KEY_ENUM, OFF(op_table_quantity), 0, 0, 0, "", popc_table_quantity_names,
	 "table intent: the value column is x_d (m) or an exogenous force (N)", "position", 0},

	NUM("device", "mass", dev_mass_kg, "0.2", 0, 1e3, 0, "kg", "device mass M_HI"),
	NUM("device", "damping", dev_damping_Nspm, "0", 0, 1e6, 0, "N s/m", "device damping B_HI"),
	NUM("device", "stiffness", dev_stiffness_Npm, "0", 0, 1e9, 0, "N/m", "device stiffness K_HI"),
	NUM_DECLARED("device", "coulomb", dev_coulomb_N, 0, 1e6, "N",
		     "Coulomb friction F_c: -F_c sign(v) while sliding (0: none)"),
	NUM_DECLARED("device", "stiction", dev_stiction_N, 0, 1e6, "N",
		     "static friction F_s >= F_c: at v = 0 stuck while |net force| <= F_s (0: = F_c)"),
	{"device", "causality", KEY_ENUM, OFF(causality), 0, 0, 0, "", popc_causality_names,
	 "impedance (motion in, force out) or admittance (force in, motion out; [admittance], "
	 "docs/ADMITTANCE.md)", "impedance", 1},

	{"environment", "kind", KEY_ENUM, OFF(env_kind), 0, 0, 0, "", popc_environment_kind_names,
	 "unilateral wall or bilateral spring", "wall", 0},
	NUM("environment", "stiffness", env_stiffness_Npm, "1000", 0, 1e9, 0, "N/m", "K_e"),
	NUM("environment", "damping", env_damping_Nspm, "0", 0, 1e6, 0, "N s/m", "B_e (wall damping)"),
	NUM("environment", "position", env_position_m, "0", -1e3, 1e3, 0, "m", "wall surface / spring rest"),

	NUM("encoder", "resolution", enc_resolution_m, "1e-5", 0, 1, 1, "m", "delta: x_meas = delta floor(x/delta)"),

	{"controller", "variant", KEY_ENUM, OFF(variant), 0, 0, 0, "", popc_variant_names,
	 "PO/PC variant", "ref-energy", 0},
	NUM("controller", "pc_bound", pc_bound_N, "5", 0, 1e6, 1, "N", "bound on |f_pc|"),
	{"controller", "ignore_mode", KEY_ENUM, OFF(ignore_mode), 0, 0, 0, "", popc_ignore_mode_names,
	 "Table I Prev_fc: undo f_c(k-1) (Fig. 7) or literal f_e(k) (docs/TABLE1.md)", "undo", 0},
	{"controller", "foaw_window", KEY_INT, OFF(foaw_window), 1, POPC_FOAW_MAX_WINDOW, 0,
	 "samples", NULL, "filtered-velocity: longest FOAW window", "16", 0},
	NUM("controller", "foaw_noise", foaw_noise_m, "0", 0, 1, 0, "m",
	    "filtered-velocity: FOAW noise band d (0: the encoder resolution)"),
	{"controller", "reversal_count", KEY_INT, OFF(reversal_count), 1, POPC_REVERSAL_MAX_COUNT, 0,
	 "", NULL, "pc-off-reversals: reversals of the count direction that turn the PC off ...", "4", 0},
	{"controller", "reversal_window", KEY_INT, OFF(reversal_window), 1, 1e7, 0, "ticks", NULL,
	 "pc-off-reversals: ... when they fall within this many ticks", "100", 0},
	{"controller", "po_window", KEY_INT, OFF(po_window), 1, POPC_PO_MAX_WINDOW, 0, "ticks", NULL,
	 "windowed-po: the PO sums W - E_ref over the last po_window ticks", "25", 0},
	NUM("controller", "po_velocity_floor", po_velocity_floor_mps, "0.01", 0, 1e3, 0, "m/s",
	    "windowed-po: no PC below this measured speed |dx| / T"),
	NUM("controller", "po_damping_max", po_damping_max_Nspm, "8", 0, 1e9, 0, "N s/m",
	    "windowed-po: bound on the PC's damping |f_pc| / |v|"),
	{"controller", "eb_margin", KEY_DOUBLE, OFF(eb_margin), 0, 1, 0, "", NULL,
	 "energy-bounding: K_b = (1 - eb_margin) 2 b / T, strictly inside Colgate and Schenkel's "
	 "line (docs/ANALYSIS.md)", "0.5", WRITTEN_FOR_EB},

	{"admittance", "variant", KEY_ENUM, OFF(adm_variant), 0, 0, 0, "",
	 popc_admittance_variant_names, "parallel PC variant (docs/ADMITTANCE.md)", "parallel-pc",
	 ADMITTANCE_ONLY},
	NUM_ADM("virtual_mass", adm_virtual_mass_kg, "0.5", 0, 1e3, 0, "kg",
		"VE mass m_v (0: a damper, then virtual_damping > 0)"),
	NUM_ADM("virtual_damping", adm_virtual_damping_Nspm, "2", 0, 1e6, 0, "N s/m", "VE damping b_v"),
	NUM_ADM("pc_velocity_bound", adm_pc_velocity_bound_mps, "0.5", 0, 1e3, 1, "m/s",
		"bound on the parallel PC's |v_pc|"),
	{"admittance", "servo", KEY_ENUM, OFF(adm_servo), 0, 0, 0, "", popc_servo_kind_names,
	 "the device's inner loop: position (K_p, K_v) or velocity (K_v) servo", "position",
	 ADMITTANCE_ONLY},
	NUM_ADM("servo_stiffness", adm_servo_stiffness_Npm, "3000", 0, 1e9, 0, "N/m",
		"position servo gain K_p"),
	NUM_ADM("servo_damping", adm_servo_damping_Nspm, "40", 0, 1e6, 0, "N s/m",
		"servo velocity gain K_v"),
	NUM_ADM("force_resolution", adm_force_resolution_N, "0.01", 0, 1e3, 1, "N",
		"force sensor resolution r, N per count: f = r round(f_s / r)"),
	NUM_ADM("force_noise", adm_force_noise_N, "0", 0, 1e3, 0, "N",
		"standard deviation of the sensor's Gaussian noise (0: none)"),
	{"admittance", "force_noise_seed", KEY_INT, OFF(adm_force_noise_seed), 0, 2147483647.0, 0, "",
	 NULL, "seed of the sensor noise (splitmix64)", "1", ADMITTANCE_ONLY},

	{"teleop", "architecture", KEY_ENUM, OFF(tele_arch), 0, 0, 0, "",
	 popc_teleop_architecture_names,
	 "off (one port) or bilateral teleoperation: the device above is the master, "
	 "[environment] is the slave's (docs/TELEOPERATION.md)", "off", 1},
	{"teleop", "link", KEY_ENUM, OFF(tele_link), 0, 0, 0, "", popc_teleop_link_names,
	 "channel ([forward], [backward]) or direct (received in the tick it is sent)", "channel",
	 TELEOP_ONLY},
	{"teleop", "tdpa", KEY_ENUM, OFF(tele_tdpa), 0, 0, 0, "", off_on_names,
	 "the two-port passivity controllers: impedance PC at the master, admittance PC at the "
	 "slave (off: observed only)", "on", TELEOP_ONLY},
	NUM_TELE("teleop", "master_pc_bound", tele_master_bound_N, "100", 0, 1e6, 1, "N",
		 "bound on the master PC's force |d|"),
	NUM_TELE("teleop", "slave_pc_bound", tele_slave_bound_mps, "10", 0, 1e3, 1, "m/s",
		 "bound on the slave PC's velocity |d|"),
	{"teleop", "drift", KEY_ENUM, OFF(tele_drift), 0, 0, 0, "", popc_drift_law_names,
	 "the slave's position-drift compensation within the observer's energy: off, "
	 "artigas2010 or coelho2018 (docs/TELEOPERATION.md)", "off", TELEOP_USED},
	{"teleop", "drift_max_velocity", KEY_DOUBLE, OFF(tele_drift_max_mps), 0, 1e3, 1, "m/s", NULL,
	 "bound on the drift compensation's velocity |v_dc|", "0.5", DRIFT_ONLY},
	{"teleop", "drift_ratio", KEY_DOUBLE, OFF(tele_drift_ratio), 0, 10, 1, "", NULL,
	 "coelho2018: |v_dc| at most this times the proposed slave velocity", "0.5", DRIFT_ONLY},
	{"teleop", "excess", KEY_DOUBLE, OFF(tele_excess_J), 0, 1e3, 0, "J", NULL,
	 "passivity excess: energy each side may deliver beyond what it received (0: none)", "0",
	 TELEOP_USED},
	NUM_PP("coupling_stiffness", tele_coupling_K_Npm, "1000", 0, 1e9, 0, "N/m",
	       "position-position: each side's coupling spring K_c to the remote position"),
	NUM_PP("coupling_damping", tele_coupling_B_Nspm, "20", 0, 1e6, 0, "N s/m",
	       "position-position: each side's coupling damper B_c to the remote velocity"),
	NUM_PP("slave_pc_force_bound", tele_slave_bound_N, "100", 0, 1e6, 1, "N",
	       "position-position: bound on the slave PC's force |d|"),
	NUM_TELE("slave", "mass", slave_mass_kg, "0.2", 0, 1e3, 1, "kg", "slave device mass"),
	NUM_TELE("slave", "damping", slave_damping_Nspm, "0", 0, 1e6, 0, "N s/m", "slave device damping"),
	{"slave", "servo", KEY_ENUM, OFF(slave_servo), 0, 0, 0, "", popc_servo_kind_names,
	 "the slave's inner loop: position (K_p, K_v) or velocity (K_v) servo", "position",
	 TELEOP_ONLY},
	NUM_TELE("slave", "servo_stiffness", slave_servo_stiffness_Npm, "1000", 0, 1e9, 0, "N/m",
		 "position servo gain K_p"),
	NUM_TELE("slave", "servo_damping", slave_servo_damping_Nspm, "40", 0, 1e6, 1, "N s/m",
		 "servo velocity gain K_v"),
	NUM_TELE("slave", "force_resolution", slave_force_resolution_N, "0.01", 0, 1e3, 1, "N",
		 "force sensor resolution, N per count"),
	{"slave", "rate", KEY_DOUBLE, OFF(slave_rate_Hz), 0, 1e9, 0, "Hz", NULL,
	 "the slave's local loop rate, N x run.rate (N whole, 1 to 1000): contact, servo and "
	 "plant in N sub-ticks a tick; 0: run.rate", "0", TELEOP_USED},
	CHANNEL_KEYS("forward", fwd, "1"),
	CHANNEL_KEYS("backward", bwd, "2"),

	{"integrator", "method", KEY_ENUM, OFF(integrator), 0, 0, 0, "", popc_integrator_names,
	 "plant integration", "exact", 0},
	{"integrator", "substeps", KEY_INT, OFF(substeps), 1, 1e6, 0, "", NULL,
	 "fixed-step integrators: steps per control period", "100", 0},

	{"axis", "kind", KEY_ENUM, OFF(axis), 0, 0, 0, "", axis_names,
	 "sim (the plant above) or modbus (a servo drive)", "sim", 0},
	{"axis", "map", KEY_STRING, OFF(axis_map), 0, 0, 0, "path", NULL,
	 "modbus: register map file (relative as operator.table)", "", 0},
	{"axis", "connect", KEY_STRING, OFF(axis_connect), 0, 0, 0, "uri", NULL,
	 "modbus: " POPC_URI_NOTATION, "", 0},
};

#define N_KEYS (sizeof scene_keys / sizeof scene_keys[0])

static int set_key(popc_scene *s, const scene_key *k, const char *value, const char *where,
		   const char *option, popc_error *err);

/* The paper's scene (seed Sec. III) with the ramp of README, "Scenes": every
 * key's default from the table, read as a scene file's value would be, so a
 * default is in its key's range by construction. */
static int set_defaults(popc_scene *s, popc_error *err)
{
	memset(s, 0, sizeof *s);
	int bad = 0;
	for (size_t i = 0; i < N_KEYS; i++) {
		popc_error e;
		int st = set_key(s, &scene_keys[i], scene_keys[i].def, "default ", NULL, &e);
		if (st && !bad) {
			bad = st;
			popc_error_set(err, st, "%s", e.msg);
		}
	}
	return bad;
}

void popc_scene_defaults(popc_scene *s)
{
	/* a default outside its own key's range is a wrong table, which
	 * popc_scene_defaults_check finds (tests/unit/test_scene.c): the library
	 * does not abort */
	(void)set_defaults(s, NULL);
	s->data_path[0] = '\0';
}

int popc_scene_set_data_path(popc_scene *s, const char *data_path, const char *what,
			     popc_error *err)
{
	if (!data_path)
		data_path = "";
	size_t len = strlen(data_path);
	if (len >= sizeof s->data_path)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: the data path is %zu characters long; at most %d",
				      what ? what : "data path", len, POPC_PATH_MAX - 1);
	memcpy(s->data_path, data_path, len + 1);
	return 0;
}

int popc_scene_defaults_check(popc_error *err)
{
	popc_scene s;
	return set_defaults(&s, err);
}

static const scene_key *find_key(const char *section, const char *key, int *section_known)
{
	*section_known = 0;
	for (size_t i = 0; i < N_KEYS; i++) {
		if (strcmp(scene_keys[i].section, section) != 0)
			continue;
		*section_known = 1;
		if (strcmp(scene_keys[i].key, key) == 0)
			return &scene_keys[i];
	}
	return NULL;
}

/* operator.table, axis.map, forward.trace, backward.trace: files, made
 * absolute by resolve_relative() */
static int is_path_key(const scene_key *k)
{
	return k->type == KEY_STRING && strcmp(k->unit, "path") == 0;
}

static int resolve_relative(char *field, const char *scene_path, const char *key, int is_map,
			    const char *data_path, popc_error *err);

/* resolve_relative's is_map for path key k: 1 axis.map (drives/), 2 a
 * channel's trace (traces/), 0 operator.table (never looked up) */
static int path_lookup(const scene_key *k)
{
	if (k->offset == offsetof(popc_scene, axis_map))
		return 1;
	return k->offset == offsetof(popc_scene, fwd.trace) || k->offset == offsetof(popc_scene, bwd.trace)
		       ? 2
		       : 0;
}

static void describe_range(const scene_key *k, char *buf, size_t cap)
{
	if (k->type == KEY_ENUM) {
		size_t len = 0;
		buf[0] = '\0';
		for (int i = 0; k->names[i]; i++)
			len += (size_t)snprintf(buf + len, len < cap ? cap - len : 0, "%s%s",
						i ? "|" : "one of ", k->names[i]);
	} else if (k->type == KEY_STRING) {
		snprintf(buf, cap, "a %s", k->unit);
	} else {
		snprintf(buf, cap, "%s%g, %g]%s%s", k->min_open ? "(" : "[", k->min, k->max,
			 k->unit[0] ? " " : "", k->unit);
	}
}

/* The name a message gives key k (see set_key) and its allowed range. */
/* "1000N/m", "5 s", "2kHz", "3 µm": the length of the leading number when a
 * unit follows it (after blanks, a letter, '/', '%' or a non-ASCII byte such
 * as µ's), else 0. Only to name the mistake: such a value is refused either
 * way. */
static size_t number_with_unit(const char *value)
{
	size_t n = strspn(value, "+-0123456789.eE");
	for (; n > 0; n--) {
		const unsigned char *u = (const unsigned char *)value + n;
		while (*u == ' ' || *u == '\t')
			u++;
		/* not units: hex ("0x10"), a cut exponent ("5e", "5e+") */
		int hex = (*u == 'x' || *u == 'X') && u == (const unsigned char *)value + n &&
			  value[n - 1] == '0';
		int exponent = (*u == 'e' || *u == 'E') && (u[1] == '\0' || u[1] == '+' || u[1] == '-' ||
							 isdigit(u[1]));
		double v;
		if ((isalpha(*u) || *u == '/' || *u == '%' || *u >= 0x80) && !hex && !exponent &&
		    popc_parse_double_span(value, value + n, &v) == POPC_PARSE_OK)
			return n;
	}
	return 0;
}

static void describe_key(const scene_key *k, const char *where, const char *option, char *range,
			 size_t range_cap, char *who, size_t who_cap)
{
	describe_range(k, range, range_cap);
	if (option)
		snprintf(who, who_cap, "%s", option);
	else
		snprintf(who, who_cap, "%s%s.%s", where, k->section, k->key);
}

/* Why a string value cannot be written to a scene file and read back, or
 * NULL. The resolved scene is written as one (popc scene show, a sweep's
 * runs/<id>/scene.ini) and read with libinih, so "key = value" must fit
 * libinih's line (INI_MAX_LINE - 1 characters without the newline; longer
 * lines are refused, ini_lines.h), hold no line break, and no ';' at its start
 * or after a blank (libinih's inline comment: the rest would be dropped). */
static int unwritable(const scene_key *k, const char *value, char *why, size_t cap)
{
	if (value[strcspn(value, "\r\n")]) {
		snprintf(why, cap, "has a line break");
		return 1;
	}
	for (const char *p = strchr(value, ';'); p; p = strchr(p + 1, ';'))
		if (p == value || p[-1] == ' ' || p[-1] == '\t') {
			snprintf(why, cap, "has a ';' at its start or after a blank (a scene file "
					   "reads it as a comment)");
			return 1;
		}
	if (strlen(k->key) + 3 + strlen(value) > INI_MAX_LINE - 1) {
		snprintf(why, cap, "is too long for a line of a scene file (\"%s = ...\" holds at most %d "
				   "characters)", k->key, INI_MAX_LINE - 1);
		return 1;
	}
	return 0;
}

/* Sets key k from text. Messages name "<where><section>.<key> = <value>", or,
 * with option (a command-line option of its own, as popc run --variant),
 * "<option> <value>": the name the user typed. */
static int set_key(popc_scene *s, const scene_key *k, const char *value, const char *where,
		   const char *option, popc_error *err)
{
	/* the key's name and allowed range for messages, formatted only when one
	 * is needed: a sweep sets its --vary keys on every run (snprintf here
	 * was 16 % of a sweep's per-run CPU, docs/BENCHMARKS.md section 6) */
	char range[160], who[200];
#define DESCRIBE_KEY() describe_key(k, where, option, range, sizeof range, who, sizeof who)
	const char *sep = option ? " " : " = ";
	char *field = (char *)s + k->offset;
	switch (k->type) {
	case KEY_DOUBLE:
	case KEY_INT: {
		/* a number as everywhere (popc/util/parse.h); an int key's value is a
		 * whole number, exact from its digits ("2.0" is 2, "2.5" is not) */
		double v = 0.0;
		long long whole = 0;
		popc_parse_status ps = k->type == KEY_INT
					       ? popc_parse_ll_text(value, LLONG_MIN, LLONG_MAX, &whole)
					       : popc_parse_double_text(value, &v);
		if (ps != POPC_PARSE_OK)
			DESCRIBE_KEY();
		if (k->type == KEY_INT && ps == POPC_PARSE_OVERFLOW)
			return popc_error_set(err, POPC_ERR_INVALID, "%s%s%s: out of range; allowed %s",
					      who, sep, value, range);
		if (ps == POPC_PARSE_NOT_WHOLE)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s%s%s: not a whole number; allowed %s", who, sep, value,
					      range);
		size_t num_len = ps == POPC_PARSE_INVALID ? number_with_unit(value) : 0;
		const char *unit_text = value + num_len;
		while (num_len && (*unit_text == ' ' || *unit_text == '\t'))
			unit_text++;
		if (num_len)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s%s'%s': units are not accepted ('%s' after the number): "
					      "give the number alone, in %s; allowed %s",
					      who, sep, value, unit_text,
					      k->unit[0] ? k->unit : "the key's unit", range);
		if (ps != POPC_PARSE_OK)
			return popc_error_set(err, POPC_ERR_INVALID, "%s%s'%s': %s; allowed %s", who,
					      sep, value,
					      ps == POPC_PARSE_OVERFLOW
						      ? "not a finite number (above the largest double, 1.8e308)"
					      : ps == POPC_PARSE_UNDERFLOW
						      ? "below the smallest double (4.9e-324): it would read as 0"
						      : "not a finite number",
					      range);
		if (k->type == KEY_INT)
			v = (double)whole;
		int below = k->min_open ? !(v > k->min) : !(v >= k->min);
		if (below || !(v <= k->max)) {
			DESCRIBE_KEY();
			return popc_error_set(err, POPC_ERR_INVALID, "%s%s%s: out of range; allowed %s",
					      who, sep, value, range);
		}
		if (k->type == KEY_INT)
			*(int *)(void *)field = (int)whole;
		else
			*(double *)(void *)field = v;
		return 0;
	}
	case KEY_ENUM:
		for (int i = 0; k->names[i]; i++) {
			if (strcmp(k->names[i], value) == 0) {
				if (k->offset == offsetof(popc_scene, axis))
					snprintf(s->axis, sizeof s->axis, "%s", k->names[i]);
				else
					*(int *)(void *)field = i;
				return 0;
			}
		}
		DESCRIBE_KEY();
		return popc_error_set(err, POPC_ERR_INVALID, "%s%s'%s': unknown value; allowed %s", who,
				      sep, value, range);
	case KEY_STRING:
		DESCRIBE_KEY(); /* a path is set once per scene, not per tick or run */
		if (strlen(value) >= POPC_PATH_MAX)
			return popc_error_set(err, POPC_ERR_INVALID, "%s: longer than %d characters", who,
					      POPC_PATH_MAX - 1);
		if (unwritable(k, value, range, sizeof range))
			return popc_error_set(err, POPC_ERR_INVALID, "%s%s'%s': %s", who, sep, value,
					      range);
		snprintf(field, POPC_PATH_MAX, "%s", value);
		return 0;
	}
	return POPC_ERR_INVALID;
#undef DESCRIBE_KEY
}

static int unknown_key(const char *section, const char *key, int section_known, const char *where,
		       popc_error *err)
{
	if (!section_known)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%sunknown section [%s]; sections are run, operator, device, "
				      "environment, encoder, controller, admittance, integrator, axis",
				      where, section);
	char keys[512];
	size_t len = 0;
	keys[0] = '\0';
	for (size_t i = 0; i < N_KEYS; i++)
		if (strcmp(scene_keys[i].section, section) == 0 && len < sizeof keys)
			len += (size_t)snprintf(keys + len, sizeof keys - len, "%s%s", len ? ", " : "",
						scene_keys[i].key);
	return popc_error_set(err, POPC_ERR_INVALID, "%sunknown key %s.%s; [%s] has: %s", where, section,
			      key, section, keys);
}

/* Copies text without the blanks around it, as inih reads a file's names and
 * values; -1 if it does not fit out. */
static int trimmed(const char *text, size_t len, char *out, size_t cap)
{
	const char *end = text + len;
	popc_trim_blanks(&text, &end);
	len = (size_t)(end - text);
	if (len >= cap)
		return -1;
	memcpy(out, text, len);
	out[len] = '\0';
	return 0;
}

/* How scene_set's messages name the assignment: "--set section.key", or the
 * option given. */
static void set_who(char *who, size_t cap, const char *option, const char *sec, const char *name)
{
	snprintf(who, cap, "%s%s%s%s", option ? option : "--set ", option ? "" : sec,
		 option ? "" : ".", option ? "" : name);
}

/* section and key without the blanks around them into sec and name (64
 * bytes each); -1 when one is too long */
static int trimmed_names(const char *section, const char *key, char *sec, char *name)
{
	return trimmed(section, strlen(section), sec, 64) || trimmed(key, strlen(key), name, 64)
		       ? -1
		       : 0;
}

/* value without the blanks around it into val (POPC_PATH_MAX bytes), or the
 * message that it is too long, naming sec.name (or option) */
static int trimmed_value(const char *value, char *val, const char *option, const char *sec,
			 const char *name, popc_error *err)
{
	if (!trimmed(value, strlen(value), val, POPC_PATH_MAX))
		return 0;
	char who[200];
	set_who(who, sizeof who, option, sec, name);
	return popc_error_set(err, POPC_ERR_INVALID, "%s: value longer than %d characters", who,
			      POPC_PATH_MAX - 1);
}

/* The rest of scene_set once key k is found and the value trimmed (val; sec
 * and name: the key's names as given, trimmed, for messages). */
static int set_found(popc_scene *s, const scene_key *k, const char *sec, const char *name,
		     const char *val, const char *option, popc_error *err)
{
	/* who is named in a message only: formatted when one may follow (a
	 * sweep sets its varied keys for every run, and this snprintf was a
	 * tenth of a sweep's own instructions, docs/BENCHMARKS.md section 6) */
	char who[200];
	int st = set_key(s, k, val, "--set ", option, err);
	if (is_path_key(k))
		set_who(who, sizeof who, option, sec, name);
	if (!st && is_path_key(k))
		st = resolve_relative((char *)s + k->offset, NULL, who, path_lookup(k), s->data_path,
				      err);
	char why[160];
	if (!st && is_path_key(k) && unwritable(k, (char *)s + k->offset, why, sizeof why))
		st = popc_error_set(err, POPC_ERR_INVALID,
				    "%s: the path from the working directory, %s, %s", who,
				    (char *)s + k->offset, why);
	return st;
}

/* popc_scene_set and popc_scene_set_option: option NULL for --set */
static int scene_set(popc_scene *s, const char *section, const char *key, const char *value,
		     const char *option, popc_error *err)
{
	/* blanks around a name or value count as in a file: " 5" and "5 " are 5 */
	char sec[64], name[64];
	if (trimmed_names(section, key, sec, name))
		return popc_error_set(err, POPC_ERR_INVALID, "--set %s.%s: name too long", section, key);
	/* a value too long is said before an unknown key */
	char val[POPC_PATH_MAX];
	int st = trimmed_value(value, val, option, sec, name, err);
	if (st)
		return st;
	int section_known;
	const scene_key *k = find_key(sec, name, &section_known);
	if (!k)
		return unknown_key(sec, name, section_known, "--set: ", err);
	return set_found(s, k, sec, name, val, option, err);
}

int popc_scene_key_index(const char *section, const char *key)
{
	char sec[64], name[64];
	if (trimmed_names(section, key, sec, name))
		return -1;
	int section_known;
	const scene_key *k = find_key(sec, name, &section_known);
	return k ? (int)(k - scene_keys) : -1;
}

int popc_scene_set_index(popc_scene *s, int index, const char *value, popc_error *err)
{
	if (index < 0 || (size_t)index >= N_KEYS)
		return popc_error_set(err, POPC_ERR_INVALID, "scene key index %d: no such key", index);
	const scene_key *k = &scene_keys[index];
	char val[POPC_PATH_MAX];
	int st = trimmed_value(value, val, NULL, k->section, k->key, err);
	return st ? st : set_found(s, k, k->section, k->key, val, NULL, err);
}

int popc_scene_set(popc_scene *s, const char *section, const char *key, const char *value,
		   popc_error *err)
{
	return scene_set(s, section, key, value, NULL, err);
}

int popc_scene_set_option(popc_scene *s, const char *option, const char *section, const char *key,
			  const char *value, popc_error *err)
{
	return scene_set(s, section, key, value, option, err);
}

int popc_scene_key_is_path(const char *section, const char *key)
{
	int section_known;
	const scene_key *k = find_key(section, key, &section_known);
	return k && is_path_key(k);
}

int popc_scene_set_assignment(popc_scene *s, const char *assignment, popc_error *err)
{
	const char *eq = strchr(assignment, '=');
	const char *dot = strchr(assignment, '.');
	if (!eq || !dot || dot > eq || dot == assignment || dot + 1 == eq)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "--set '%s': expected section.key=value (e.g. run.duration=10)",
				      assignment);
	char section[64], key[64];
	size_t ls = (size_t)(dot - assignment), lk = (size_t)(eq - dot - 1);
	if (ls >= sizeof section || lk >= sizeof key)
		return popc_error_set(err, POPC_ERR_INVALID, "--set '%s': name too long", assignment);
	memcpy(section, assignment, ls);
	section[ls] = '\0';
	memcpy(key, dot + 1, lk);
	key[lk] = '\0';
	return popc_scene_set(s, section, key, eq + 1, err);
}

/* ---- INI loading -------------------------------------------------------- */

typedef struct load_ctx {
	popc_scene *s;
	const char *path;
	popc_error *err;
	int status;
	int status_line;      /* the line of the handler's error */
	int seen_line[N_KEYS]; /* the line of each key given, 0: not given */
	FILE *f;
	int line;     /* lines read so far: the real line number (ini_lines.h) */
	int too_long; /* line `line` does not fit libinih's buffer */
	int max_chars; /* the longest line that fits */
} load_ctx;

/* A "[section]" line: libinih calls the handler for keys only, so an unknown
 * section without keys ("[nosuch]" alone, or a misspelt "[contoller]" before
 * another section) passed unseen; refused here with the message of an unknown
 * section with keys. The name as libinih takes it: from '[' to the first ']'
 * (a line without one is libinih's malformed line). */
static void check_section_line(load_ctx *c, const char *line)
{
	if (line[0] != '[')
		return;
	const char *end = strchr(line + 1, ']');
	char name[64];
	if (!end || (size_t)(end - line - 1) >= sizeof name)
		return;
	memcpy(name, line + 1, (size_t)(end - line - 1));
	name[end - line - 1] = '\0';
	for (size_t i = 0; i < N_KEYS; i++)
		if (strcmp(scene_keys[i].section, name) == 0)
			return;
	c->status = unknown_key(name, "", 0, "", c->err);
}

/* libinih's reader: stops at the first handler error (inih reports that
 * line) and at a line too long for libinih's buffer (a longer line would be
 * parsed in pieces: the tail of a comment could set a key). */
static char *scene_read_line(char *str, int num, void *stream)
{
	load_ctx *c = stream;
	if (c->status)
		return NULL;
	c->max_chars = num - 1;
	char *r = popc_ini_read_line(str, num, c->f, &c->line, &c->too_long);
	/* a CR-only file is one long line: its start (in str) says why */
	if ((r || c->too_long == 1) && popc_ini_line_has_bare_cr(str)) {
		c->too_long = 0;
		c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s", POPC_INI_BARE_CR_WHY);
	}
	else if (r)
		check_section_line(c, r);
	if (c->status) {
		c->status_line = c->line;
		return NULL;
	}
	return r;
}

static int scene_ini_handler(void *user, const char *section, const char *name, const char *value)
{
	load_ctx *c = user;
	if (c->status)
		return 1; /* keep the first error only; inih reports its line */
	int section_known;
	const scene_key *k = find_key(section, name, &section_known);
	if (!k) {
		c->status = unknown_key(section, name, section_known, "", c->err);
		c->status_line = c->line;
		return 0;
	}
	size_t idx = (size_t)(k - scene_keys);
	if (c->seen_line[idx]) {
		c->status = popc_error_set(c->err, POPC_ERR_INVALID, "%s.%s given twice (first on line %d)",
					   section, name, c->seen_line[idx]);
		c->status_line = c->line;
		return 0;
	}
	c->seen_line[idx] = c->line;
	c->status = set_key(c->s, k, value, "", NULL, c->err);
	if (c->status)
		c->status_line = c->line;
	return c->status ? 0 : 1;
}

/* One rule for the path keys (operator.table, axis.map): a relative path is
 * relative to where it was written, the scene file's directory for a path in
 * a scene file (scene_path), the working directory for one given on the
 * command line (popc_scene_set, scene_path NULL; --set, --vary, --map). Either
 * way it is made absolute when it is read (the working directory before a
 * relative scene path), so that the resolved scene, written to a log header
 * or a sweep's run directory, names the same file from any directory. */
static int resolve_relative(char *field, const char *scene_path, const char *key, int is_map,
			    const char *data_path, popc_error *err)
{
	/* key: "operator.table" in a scene file, the option's name otherwise
	 * ("--set operator.table", "--map") */
	if (!field[0] || field[0] == '/')
		return 0;
	/* axis.map: a bare name that is not a file where it points ("generic",
	 * "cia402-lohi.ini") is an installed drive map (data_path.h). Found nowhere,
	 * it stays relative as before: the map's reader then names the path, and
	 * only when an axis.kind = modbus run reads it. */
	if (is_map) { /* 1: a drive map, 2: a delay trace (path_lookup) */
		char dir[POPC_PATH_MAX] = "", found[POPC_PATH_MAX];
		const char *slash = scene_path ? strrchr(scene_path, '/') : NULL;
		if (slash)
			snprintf(dir, sizeof dir, "%.*s", (int)(slash - scene_path), scene_path);
		popc_error lookup_err;
		if (popc_data_find(is_map == 2 ? POPC_DATA_TRACES : POPC_DATA_DRIVES, field, slash ? dir : NULL, data_path, found,
				   sizeof found, &lookup_err) == 1) {
			memcpy(field, found, strlen(found) + 1);
			return 0;
		}
	}
	char cwd[POPC_PATH_MAX] = "";
	if ((!scene_path || scene_path[0] != '/') && !getcwd(cwd, sizeof cwd))
		cwd[0] = '\0'; /* then relative to the working directory, as given */
	const char *slash = scene_path ? strrchr(scene_path, '/') : NULL;
	int dir_len = slash ? (int)(slash - scene_path) : 0;
	char out[POPC_PATH_MAX];
	int n = snprintf(out, sizeof out, "%s%s%.*s%s%s", cwd, cwd[0] && cwd[1] ? "/" : "", dir_len,
			 slash ? scene_path : "", dir_len ? "/" : "", field);
	if (n < 0 || (size_t)n >= sizeof out)
		return scene_path ? popc_error_set(err, POPC_ERR_INVALID,
						   "%s: %s = %s: the path from the scene's directory "
						   "is longer than %d characters",
						   scene_path, key, field, POPC_PATH_MAX - 1)
				  : popc_error_set(err, POPC_ERR_INVALID,
						   "%s: the path from the working directory is longer "
						   "than %d characters: %s",
						   key, POPC_PATH_MAX - 1, field);
	memcpy(field, out, (size_t)n + 1);
	return 0;
}

int popc_scene_load(popc_scene *s, const char *path, popc_error *err)
{
	/* a bare name not in the working directory: an installed scene */
	char found[POPC_PATH_MAX];
	int looked = popc_data_find(POPC_DATA_SCENES, path, NULL, s->data_path, found, sizeof found,
				    err);
	if (looked < 0)
		return looked;
	if (looked == 1)
		path = found;
	FILE *f = fopen(path, "r");
	if (!f)
		return popc_error_set(err, POPC_ERR_INVALID, "%s: cannot open scene: %s", path,
				      strerror(errno));
	char table_before[POPC_PATH_MAX], map_before[POPC_PATH_MAX];
	memcpy(table_before, s->op_table, sizeof table_before);
	memcpy(map_before, s->axis_map, sizeof map_before);
	load_ctx c = {.s = s, .path = path, .err = err, .f = f};
	int line = ini_parse_stream(scene_read_line, &c, scene_ini_handler, &c);
	if (line == 0 && c.status) /* refused by the reader, which libinih does not see */
		line = c.status_line;
	int read_failed = ferror(f), read_errno = errno;
	fclose(f);
	if (line < 0)
		return popc_error_set(err, POPC_ERR_IO, "%s: cannot read", path);
	if (read_failed && !c.status) /* e.g. a directory: fopen succeeds, reading fails */
		return popc_error_set(err, POPC_ERR_INVALID, "%s: cannot read scene: %s", path,
				      strerror(read_errno));
	if (c.too_long == 2 && line == 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%d: a NUL byte in the line (a scene is a text file)", path,
				      c.line);
	if (c.too_long && line == 0) /* an earlier error (line > 0) is named first */
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s:%d: line longer than %d characters (libinih's limit)", path,
				      c.line, c.max_chars);
	if (line > 0) {
		/* libinih goes on after a malformed line and reports the first
		 * error's line: the handler's message is only for its own line */
		char msg[POPC_ERROR_MSG_MAX];
		if (c.status && c.status_line == line)
			snprintf(msg, sizeof msg, "%s", err ? err->msg : "");
		else
			snprintf(msg, sizeof msg, "malformed line (expected [section], key = value, "
						  "or a ; or # comment)");
		return popc_error_set(err, POPC_ERR_INVALID, "%s:%d: %s", path, line, msg);
	}
	int st = 0;
	if (strcmp(table_before, s->op_table) != 0)
		st = resolve_relative(s->op_table, path, "operator.table", 0, s->data_path, err);
	if (!st && strcmp(map_before, s->axis_map) != 0)
		st = resolve_relative(s->axis_map, path, "axis.map", 1, s->data_path, err);
	/* a channel's trace: resolved when this file gave it */
	for (size_t i = 0; !st && i < N_KEYS; i++) {
		const scene_key *k = &scene_keys[i];
		char name[80];
		snprintf(name, sizeof name, "%s.%s", k->section, k->key);
		if (is_path_key(k) && path_lookup(k) == 2 && c.seen_line[i])
			st = resolve_relative((char *)s + k->offset, path, name, 2, s->data_path, err);
	}
	if (st)
		return st;
	/* resolved, a path must still be one a scene file can hold */
	for (size_t i = 0; i < N_KEYS; i++) {
		const scene_key *k = &scene_keys[i];
		char why[160];
		if (is_path_key(k) && c.seen_line[i] &&
		    unwritable(k, (char *)s + k->offset, why, sizeof why))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s:%d: %s.%s: the path from the scene's directory, %s, %s",
					      path, c.seen_line[i], k->section, k->key,
					      (char *)s + k->offset, why);
	}
	snprintf(s->source, sizeof s->source, "%s", path);
	return 0;
}

/* What an admittance scene needs (docs/ADMITTANCE.md): a VE that moves (a
 * mass, or a damper when massless), a servo that holds the device, and only
 * what this phase models: the simulated axis, no loop delay, no friction. */
static int validate_admittance(const popc_scene *s, const char *src, popc_error *err)
{
	if (s->adm_virtual_mass_kg == 0.0 && s->adm_virtual_damping_Nspm == 0.0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: admittance.virtual_mass = 0 kg needs admittance.virtual_damping "
				      "> 0 N s/m (a massless VE is a damper, v = f / b_v); allowed "
				      "virtual_mass > 0, or virtual_damping > 0",
				      src);
	if (s->adm_servo == POPC_SERVO_POSITION && !(s->adm_servo_stiffness_Npm > 0.0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: admittance.servo = position needs admittance.servo_stiffness "
				      "> 0 N/m (K_p; or admittance.servo = velocity)",
				      src);
	if (!(s->adm_servo_damping_Nspm > 0.0) && s->adm_servo == POPC_SERVO_VELOCITY)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: admittance.servo = velocity needs admittance.servo_damping > 0 "
				      "N s/m (K_v)",
				      src);
	/* axis.kind = modbus: the register map's command.mode must match
	 * admittance.servo, which the Modbus axis checks when it loads the map
	 * (issue 25; modbus_axis.c) */
	if (s->delay_ticks != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: device.causality = admittance needs run.delay_ticks = 0 (a "
				      "delayed velocity command is not modelled yet)",
				      src);
	if (s->dev_coulomb_N != 0.0 || s->dev_stiction_N != 0.0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: device.causality = admittance needs device.coulomb = 0 and "
				      "device.stiction = 0 (the force sensor model has no friction yet)",
				      src);
	return 0;
}

/* What a teleoperation scene needs (docs/TELEOPERATION.md): an impedance
 * master (simulated; axis.kind = modbus makes the slave a drive, whose
 * register map's command.mode must match slave.servo: register_map.c), its
 * delays in the channel rather than in run.delay_ticks, a servo that holds
 * the slave. */
static int validate_teleop(const popc_scene *s, const char *src, popc_error *err)
{
	if (s->causality != POPC_CAUSALITY_IMPEDANCE)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.architecture = %s needs device.causality = impedance (the "
				      "master; the slave is [slave])",
				      src, popc_teleop_architecture_names[s->tele_arch]);
	if (s->delay_ticks != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.architecture = %s needs run.delay_ticks = 0 (the delays "
				      "are forward.delay_ticks and backward.delay_ticks)",
				      src, popc_teleop_architecture_names[s->tele_arch]);
	if (s->dev_coulomb_N != 0.0 || s->dev_stiction_N != 0.0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.architecture = %s needs device.coulomb = 0 and "
				      "device.stiction = 0 (not modelled in a teleoperation scene yet)",
				      src, popc_teleop_architecture_names[s->tele_arch]);
	if (s->slave_servo == POPC_SERVO_POSITION && !(s->slave_servo_stiffness_Npm > 0.0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: slave.servo = position needs slave.servo_stiffness > 0 N/m (K_p; "
				      "or slave.servo = velocity)",
				      src);
	if (popc_scene_slave_substeps(s) < 1)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: slave.rate = %g Hz is not a whole multiple of run.rate = %g "
				      "Hz; allowed 0 (run.rate) or N x run.rate with N whole, 1 to %d",
				      src, s->slave_rate_Hz, s->rate_Hz, POPC_SLAVE_MAX_SUBSTEPS);
	if (s->tele_arch == POPC_TELEOP_POSITION_POSITION && !(s->tele_coupling_K_Npm > 0.0) &&
	    !(s->tele_coupling_B_Nspm > 0.0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.architecture = position-position needs "
				      "teleop.coupling_stiffness > 0 N/m or teleop.coupling_damping > 0 "
				      "N s/m (no coupling: master and slave would not interact)",
				      src);
	/* position-position commands the slave a force (sim_slave_axis.c); a
	 * drive takes a position or a velocity, and the drift laws correct a
	 * velocity command (tdpa_drift.h) */
	if (s->tele_arch == POPC_TELEOP_POSITION_POSITION && strcmp(s->axis, "sim") != 0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.architecture = position-position needs axis.kind = sim "
				      "(its slave is commanded a force; a Modbus slave drive takes a "
				      "position or a velocity: position-force)",
				      src);
	if (s->tele_arch == POPC_TELEOP_POSITION_POSITION && s->tele_drift != POPC_DRIFT_OFF)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.drift = %s needs teleop.architecture = position-force "
				      "(it corrects the slave's velocity command; position-position's "
				      "couplings pull the positions together)",
				      src, popc_drift_law_names[s->tele_drift]);
	const popc_scene_channel *dir[2] = {&s->fwd, &s->bwd};
	const char *name[2] = {"forward", "backward"};
	for (int i = 0; i < 2; i++) {
		int delay, jitter; /* from the tick keys or the seconds keys (delay_trace.h) */
		int st = popc_scene_channel_ticks(s, dir[i], name[i], &delay, &jitter, err);
		if (st)
			return st;
		if ((long long)delay + jitter > POPC_CHANNEL_MAX_DELAY_TICKS)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %s.delay_ticks + %s.jitter_ticks = %lld; allowed at "
					      "most %d",
					      src, name[i], name[i], (long long)delay + jitter,
					      POPC_CHANNEL_MAX_DELAY_TICKS);
		if (dir[i]->jitter_model != 0 && jitter == 0)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %s.jitter_model = walk needs %s.jitter_ticks (or "
					      "jitter_s) > 0: the range it walks in",
					      src, name[i], name[i]);
		if (dir[i]->trace[0] && (delay || jitter || dir[i]->jitter_model))
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %s.trace and %s's delay (%d ticks), jitter (%d ticks) "
					      "or jitter_model: give the trace, or the delay and jitter",
					      src, name[i], name[i], delay, jitter);
		/* the trace read now, so that a bad one is refused before any work
		 * (exit 2), naming its file and line */
		popc_delay_trace tr;
		if (dir[i]->trace[0] && (st = popc_delay_trace_load(dir[i]->trace, s->rate_Hz, &tr, err)))
			return st;
		if (dir[i]->trace[0])
			popc_delay_trace_free(&tr);
	}
	return 0;
}

int popc_scene_validate(const popc_scene *s, popc_error *err)
{
	const char *src = s->source[0] ? s->source : "scene";
	if (!(s->op_mass_kg + s->dev_mass_kg > 0))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: operator.mass + device.mass must be > 0 kg", src);
	if (s->intent == POPC_INTENT_RAMP && s->op_x_end_m == s->op_x0_m)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: operator.x_end must differ from operator.x0 for a ramp", src);
	if (s->intent == POPC_INTENT_TABLE && !s->op_table[0])
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: operator.intent = table needs operator.table (a CSV file)", src);
	if (s->intent == POPC_INTENT_SINE && s->op_frequency_Hz * popc_scene_period_s(s) > 0.25)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: operator.frequency = %g Hz is above a quarter of run.rate",
				      src, s->op_frequency_Hz);
	/* a run shorter than half a control period would make no tick at all
	 * (popc_scene_ticks rounds) and succeed having simulated nothing */
	if (popc_scene_ticks(s) < 1)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: run.duration = %g s at run.rate = %g Hz is %g control "
				      "periods, which rounds to no tick; allowed run.duration >= %g s "
				      "(half a period) at this rate",
				      src, s->duration_s, s->rate_Hz, s->duration_s * s->rate_Hz,
				      0.5 * popc_scene_period_s(s));
	if (popc_scene_ticks(s) > 4000000000LL)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: run.duration * run.rate = %.0f ticks; at most 4e9", src,
				      s->duration_s * s->rate_Hz);
	if (s->dev_stiction_N > 0 && s->dev_stiction_N < s->dev_coulomb_N)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: device.stiction = %g N is below device.coulomb = %g N; allowed "
				      "device.stiction >= device.coulomb, or 0 (static friction equal to "
				      "the Coulomb friction)",
				      src, s->dev_stiction_N, s->dev_coulomb_N);
	if (s->causality == POPC_CAUSALITY_ADMITTANCE) {
		int st = validate_admittance(s, src, err);
		if (st)
			return st;
	}
	/* a one-port scene has no network port to compensate or grant an excess */
	if (s->tele_arch == POPC_TELEOP_OFF && s->tele_drift != POPC_DRIFT_OFF)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.drift = %s needs teleop.architecture = position-force "
				      "(a one-port scene has no slave to compensate)",
				      src, popc_drift_law_names[s->tele_drift]);
	if (s->tele_arch == POPC_TELEOP_OFF && s->tele_excess_J != 0.0)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.excess = %g J needs teleop.architecture = position-force "
				      "(a one-port scene has no network port)",
				      src, s->tele_excess_J);
	if (s->tele_arch != POPC_TELEOP_OFF) {
		int st = validate_teleop(s, src, err);
		if (st)
			return st;
	}
	if (strcmp(s->axis, "modbus") == 0 && (!s->axis_map[0] || !s->axis_connect[0]))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: axis.kind = modbus needs axis.map and axis.connect", src);
	/* Positions travel as integer counts in doubles (encoder.h): every
	 * position the run may reach must be a count below 2^53. The reach is the
	 * simulated axis' divergence bound (src/axes/sim_axis.c): 10 x the largest
	 * position key + 1 m. */
	double x_keys = fmax(fabs(s->op_x0_m), fabs(s->env_position_m));
	if (s->intent == POPC_INTENT_RAMP)
		x_keys = fmax(x_keys, fabs(s->op_x_end_m));
	if (s->intent == POPC_INTENT_SINE)
		x_keys = fmax(x_keys, fabs(s->op_x0_m) + s->op_amplitude_m);
	double reach_m = 10.0 * x_keys + 1.0, counts_max = 9007199254740992.0; /* 2^53 */
	if (!(reach_m / s->enc_resolution_m <= counts_max))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: encoder.resolution = %g m is too fine: positions up to %g m "
				      "(10 x the largest of |operator.x0|, |operator.x_end|, "
				      "|environment.position| + 1 m) would exceed 2^53 counts; use "
				      "encoder.resolution >= %.3g m",
				      src, s->enc_resolution_m, reach_m, reach_m / counts_max * 1.001);
	return 0;
}

/* ---- output ------------------------------------------------------------- */

/* Whether the resolved scene writes key k: a declared-only key when it is not
 * 0 (a number) or not its first name (an enum), an admittance key in an
 * admittance scene only, an energy-bounding key with that variant only;
 * every other key always. */
static int key_written(const popc_scene *s, const scene_key *k)
{
	const char *field = (const char *)s + k->offset;
	if (k->declared_only == ADMITTANCE_ONLY)
		return s->causality == POPC_CAUSALITY_ADMITTANCE;
	if (k->declared_only == WRITTEN_FOR_EB)
		return s->variant == POPC_VARIANT_ENERGY_BOUNDING;
	if (k->declared_only == TELEOP_ONLY)
		return s->tele_arch != POPC_TELEOP_OFF;
	if (k->declared_only == DRIFT_ONLY)
		return s->tele_arch != POPC_TELEOP_OFF && s->tele_drift != POPC_DRIFT_OFF;
	if (k->declared_only == TELEOP_USED && s->tele_arch == POPC_TELEOP_OFF)
		return 0;
	if (k->declared_only == TELEOP_USED && k->type == KEY_STRING)
		return field[0] != '\0';
	if (k->declared_only == PP_ONLY)
		return s->tele_arch == POPC_TELEOP_POSITION_POSITION;
	if (k->declared_only && k->type == KEY_ENUM)
		return *(const int *)(const void *)field != 0;
	if (k->declared_only)
		return *(const double *)(const void *)field != 0.0;
	return 1;
}

void popc_scene_write(const popc_scene *s, FILE *f, const char *prefix)
{
	const char *section = "";
	for (size_t i = 0; i < N_KEYS; i++) {
		const scene_key *k = &scene_keys[i];
		const char *field = (const char *)s + k->offset;
		if (!key_written(s, k))
			continue;
		/* a section's name before its first written key: [admittance] is
		 * left out whole from an impedance scene */
		if (strcmp(section, k->section) != 0) {
			section = k->section;
			fprintf(f, "%s[%s]\n", prefix, section);
		}
		switch (k->type) {
		case KEY_DOUBLE: {
			char num[POPC_DOUBLE_TEXT_MAX + 1];
			popc_format_double(*(const double *)(const void *)field, num);
			fprintf(f, "%s%s = %s\n", prefix, k->key, num);
			break;
		}
		case KEY_INT:
			fprintf(f, "%s%s = %d\n", prefix, k->key, *(const int *)(const void *)field);
			break;
		case KEY_ENUM:
			if (k->offset == offsetof(popc_scene, axis))
				fprintf(f, "%s%s = %s\n", prefix, k->key, s->axis);
			else
				fprintf(f, "%s%s = %s\n", prefix, k->key,
					k->names[*(const int *)(const void *)field]);
			break;
		case KEY_STRING:
			fprintf(f, "%s%s = %s\n", prefix, k->key, field);
			break;
		}
	}
}

int popc_scene_to_text(const popc_scene *s, char **text, size_t *len, popc_error *err)
{
	*text = NULL;
	*len = 0;
	FILE *f = open_memstream(text, len);
	if (!f)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	popc_scene_write(s, f, "");
	if (fclose(f) != 0) {
		free(*text);
		*text = NULL;
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	return 0;
}

void popc_scene_print_keys(FILE *f)
{
	popc_scene d;
	popc_scene_defaults(&d);
	for (size_t i = 0; i < N_KEYS; i++) {
		const scene_key *k = &scene_keys[i];
		char range[160], def[64];
		describe_range(k, range, sizeof range);
		const char *field = (const char *)&d + k->offset;
		switch (k->type) {
		case KEY_DOUBLE: popc_format_double(*(const double *)(const void *)field, def); break;
		case KEY_INT: snprintf(def, sizeof def, "%d", *(const int *)(const void *)field); break;
		case KEY_ENUM:
			snprintf(def, sizeof def, "%s",
				 k->offset == offsetof(popc_scene, axis)
					 ? d.axis
					 : k->names[*(const int *)(const void *)field]);
			break;
		case KEY_STRING: snprintf(def, sizeof def, "%s", field[0] ? field : "(none)"); break;
		}
		char name[80];
		snprintf(name, sizeof name, "%s.%s", k->section, k->key);
		fprintf(f, "  %-26s default %-10s allowed %s\n      %s\n", name, def, range, k->help);
	}
}

double popc_scene_period_s(const popc_scene *s)
{
	return 1.0 / s->rate_Hz;
}

long long popc_scene_ticks(const popc_scene *s)
{
	/* round, so that 5 s at 1 kHz is 5000 ticks despite 5 * 1000 rounding */
	return llround(s->duration_s * s->rate_Hz);
}

int popc_scene_slave_substeps(const popc_scene *s)
{
	if (s->slave_rate_Hz == 0.0)
		return 1;
	const double r = s->slave_rate_Hz / s->rate_Hz, n = nearbyint(r);
	if (!(fabs(r - n) <= 1e-9 * n) || n < 1.0 || n > POPC_SLAVE_MAX_SUBSTEPS)
		return 0;
	return (int)n;
}
