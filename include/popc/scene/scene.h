/* The scene: everything a run needs, read from an INI file, overridden by
 * --set section.key=value, validated, with every default explicit.
 *
 * Keys, their units, defaults and allowed ranges live in one table
 * (scene_keys[] in src/scene.c); popc_scene_defaults, popc_scene_load, popc_scene_set and
 * popc_scene_write all work from it, so a key is declared exactly once. */
#ifndef POPC_SCENE_H
#define POPC_SCENE_H

#include <stdio.h>

#include "popc/error.h"

#define POPC_PATH_MAX 1024
#define POPC_NAME_MAX 64

typedef enum popc_intent_kind {
	POPC_INTENT_RAMP,  /* hold x0 until t0, move at speed until x_end, hold */
	POPC_INTENT_FORCE, /* exogenous force: 0 until t0, rise at force_rate to force, hold */
	POPC_INTENT_TABLE, /* piecewise-linear x_d(t) or f(t) from a CSV file */
	POPC_INTENT_SINE,  /* x_d = x0 + amplitude sin(2 pi frequency (t - t0)) for t >= t0 */
} popc_intent_kind;

typedef enum popc_table_quantity { POPC_TABLE_POSITION, POPC_TABLE_FORCE } popc_table_quantity;

typedef enum popc_environment_kind {
	POPC_ENV_WALL,   /* unilateral: f_e = K_e (x - p) + B_e v for x >= p, else 0; f_e >= 0 */
	POPC_ENV_SPRING, /* bilateral: f_e = K_e (x - p) + B_e v */
} popc_environment_kind;

typedef enum popc_variant {
	POPC_VARIANT_NONE,
	POPC_VARIANT_PO_PC,
	POPC_VARIANT_REF_ENERGY,
	POPC_VARIANT_FILTERED_VELOCITY,
	POPC_VARIANT_IGNORE,
	POPC_VARIANT_HOLD,
	POPC_VARIANT_IMPROVED,
	POPC_VARIANT_COUNT
} popc_variant;

/* Table I's "Prev_fc = f_c(k)": literal reads it as the VE force f_e(k) stored
 * before the PC is added; undo stores f_c(k-1), so that a one-count reversal
 * removes exactly the previous step's PO increment. */
typedef enum popc_ignore_mode { POPC_IGNORE_LITERAL, POPC_IGNORE_UNDO } popc_ignore_mode;

typedef enum popc_integrator {
	POPC_INTEGRATOR_EXACT,       /* ZOH/FOH exact discretization, expm */
	POPC_INTEGRATOR_TRAPEZOID,   /* the paper's C program */
	POPC_INTEGRATOR_RK4,
	POPC_INTEGRATOR_SEMI_IMPLICIT_EULER,
	POPC_INTEGRATOR_EULER,
	POPC_INTEGRATOR_COUNT
} popc_integrator;

typedef struct popc_scene {
	/* [run] */
	double duration_s;
	double rate_Hz;
	/* [operator]: hand M_HO, B_HO, K_HO pulling the device towards x_d(t) */
	double op_mass_kg, op_damping_Nspm, op_stiffness_Npm;
	popc_intent_kind intent;
	double op_x0_m, op_t0_s, op_speed_mps, op_x_end_m;   /* ramp (x0, t0 also force/sine) */
	double op_force_N, op_force_rate_Nps;                 /* force */
	double op_amplitude_m, op_frequency_Hz;               /* sine */
	char op_table[POPC_PATH_MAX];                         /* table: CSV "t,value" */
	popc_table_quantity op_table_quantity;
	/* [device] */
	double dev_mass_kg, dev_damping_Nspm, dev_stiffness_Npm;
	/* [environment] */
	popc_environment_kind env_kind;
	double env_stiffness_Npm, env_damping_Nspm, env_position_m;
	/* [encoder] */
	double enc_resolution_m;
	/* [controller] */
	popc_variant variant;
	double pc_bound_N;
	popc_ignore_mode ignore_mode;
	int foaw_window;        /* FOAW: longest window, samples */
	double foaw_noise_m;    /* FOAW: noise band d; 0 means the encoder resolution */
	/* [integrator] */
	popc_integrator integrator;
	int substeps;
	/* [axis]: where the loop closes (sim or modbus); modbus details in the map */
	char axis[POPC_NAME_MAX];
	char axis_map[POPC_PATH_MAX];
	char axis_connect[POPC_PATH_MAX];

	/* not keys: where the scene came from, for messages and provenance */
	char source[POPC_PATH_MAX];
} popc_scene;

/* Fills s with every default (the paper's scene, DESIGN section 3). */
void popc_scene_defaults(popc_scene *s);

/* Reads an INI scene file on top of the current contents of s (call
 * popc_scene_defaults first). Unknown sections or keys, duplicate keys,
 * malformed numbers, NaN/inf and out-of-range values are errors naming
 * file:line, the key and the allowed range. A relative path (operator.table,
 * axis.map) is relative to the scene file's directory and made absolute.
 * Returns 0 or a negative popc_status. */
int popc_scene_load(popc_scene *s, const char *path, popc_error *err);

/* Applies one "section.key=value" override with the same validation. A
 * relative path (operator.table, axis.map) given this way is relative to the
 * working directory and made absolute, so that a resolved scene names the
 * same file from any directory. */
int popc_scene_set_assignment(popc_scene *s, const char *assignment, popc_error *err);
int popc_scene_set(popc_scene *s, const char *section, const char *key, const char *value,
		   popc_error *err);

/* As popc_scene_set, for a value given by a command-line option of its own
 * (popc run --variant for controller.variant): messages name the option the
 * user typed ("--variant 'x': unknown value; allowed one of none|...") rather
 * than "--set controller.variant". */
int popc_scene_set_option(popc_scene *s, const char *option, const char *section, const char *key,
			  const char *value, popc_error *err);

/* 1 when section.key names a file (operator.table, axis.map), else 0. */
int popc_scene_key_is_path(const char *section, const char *key);

/* Cross-key checks (ramp end beyond start, pc bound finite, ...). Call after
 * all loads and overrides. */
int popc_scene_validate(const popc_scene *s, popc_error *err);

/* Writes the resolved scene, every key, as INI. Each line starts with prefix
 * ("" for a scene file, "# " for a log header). Values are written so they read
 * back to the same double. */
void popc_scene_write(const popc_scene *s, FILE *f, const char *prefix);

/* The same text as popc_scene_write(s, f, ""), in a buffer the caller frees. */
int popc_scene_to_text(const popc_scene *s, char **text, size_t *len, popc_error *err);

/* Names used in files and on the command line. */
const char *popc_variant_name(popc_variant v);
int popc_variant_from_name(const char *name, popc_variant *out);
const char *popc_integrator_name(popc_integrator m);
int popc_integrator_from_name(const char *name, popc_integrator *out);

/* The control period T = 1 / rate (s), and the number of control ticks. */
double popc_scene_period_s(const popc_scene *s);
long long popc_scene_ticks(const popc_scene *s);

/* Key reference for --help and the README: one line per key with its unit,
 * default and allowed range. */
void popc_scene_print_keys(FILE *f);

#endif
