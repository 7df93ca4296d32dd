/* The scene: everything a run needs, read from an INI file, overridden by
 * --set section.key=value, validated, with every default explicit.
 *
 * Keys, their units, defaults and allowed ranges live in one table
 * (scene_keys[] in src/scene/scene.c); popc_scene_defaults, popc_scene_load, popc_scene_set and
 * popc_scene_write all work from it, so a key is declared exactly once. */
#ifndef POPC_SCENE_H
#define POPC_SCENE_H

#include <stdio.h>

#include "popc/core/admittance.h"
#include "popc/core/admittance_plant.h"
#include "popc/core/controller.h"
#include "popc/core/environment.h"
#include "popc/core/intent.h"
#include "popc/core/plant.h"
#include "popc/core/port.h"
#include "popc/core/teleop.h"
#include "popc/core/tdpa_drift.h"
#include "popc/util/error.h"

/* The connection URI notation of axis.connect (popc_modbus_uri), spelt the
 * same in every program's help and message: popc run --connect,
 * popc-servo-sim --listen, the scene key, the parser's errors. */
#define POPC_URI_NOTATION "tcp:HOST[:PORT] or rtu:DEVICE[:BAUD[:FORMAT]]"
#define POPC_URI_DEFAULTS "PORT 502, BAUD 19200, FORMAT 8E1 if left out"

#define POPC_PATH_MAX 1024
#define POPC_NAME_MAX 64
/* run.delay_ticks' upper end: the run keeps that many commands in a ring */
#define POPC_SCENE_MAX_DELAY_TICKS 1000

/* One direction of a teleoperation scene's channel ([forward] master to
 * slave, [backward] slave to master; core/channel.h) */
typedef struct popc_scene_channel {
	int delay_ticks, jitter_ticks;
	double loss;
	int in_order;
	int seed;
	/* written only when used (not 0, not empty): the delay and jitter in
	 * seconds (whole ticks at run.rate, docs/TELEOPERATION.md), a trace file
	 * of delays, the jitter's distribution (0 uniform, 1 a random walk) */
	double delay_s, jitter_s;
	char trace[POPC_PATH_MAX];
	int jitter_model;
} popc_scene_channel;

typedef struct popc_scene {
	/* [run] */
	double duration_s;
	double rate_Hz;
	int delay_ticks;        /* whole periods between a sample and its command taking effect */
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
	double dev_coulomb_N, dev_stiction_N;   /* friction; 0, 0: none (written only when declared) */
	popc_causality causality;               /* written only when admittance */
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
	int reversal_count;     /* pc-off-reversals: N reversals ... */
	int reversal_window;    /* ... within M ticks turn the PC off */
	int po_window;          /* windowed-po: ticks the PO sums over */
	double po_velocity_floor_mps, po_damping_max_Nspm; /* windowed-po */
	/* [admittance]: written only when device.causality = admittance */
	popc_admittance_variant adm_variant;
	double adm_virtual_mass_kg, adm_virtual_damping_Nspm;
	double adm_pc_velocity_bound_mps;
	popc_servo_kind adm_servo;
	double adm_servo_stiffness_Npm, adm_servo_damping_Nspm;
	double adm_force_resolution_N, adm_force_noise_N;
	int adm_force_noise_seed;
	double eb_margin;       /* energy-bounding: K_b = (1 - eb_margin) 2 b / T */
	/* [teleop], [slave], [forward], [backward]: written only when
	 * teleop.architecture is not off (docs/TELEOPERATION.md); the master is
	 * the impedance device above, the environment the slave's */
	popc_teleop_architecture tele_arch;
	popc_teleop_link tele_link;
	int tele_tdpa;                       /* 0 off, 1 on */
	double tele_master_bound_N;          /* |d| of the master's PC, a force */
	double tele_slave_bound_mps;         /* |d| of the slave's PC, a velocity */
	popc_drift_law tele_drift;           /* the slave's drift compensation (tdpa_drift.h) */
	double tele_drift_max_mps;           /* its |v_dc| bound */
	double tele_drift_ratio;             /* coelho2018: |v_dc| at most ratio |u| */
	double tele_excess_J;                /* each side's passivity excess E_0 (tdpa.h) */
	double tele_coupling_K_Npm;          /* position-position: each side's coupling K_c */
	double tele_coupling_B_Nspm;         /* ... and B_c */
	double tele_slave_bound_N;           /* position-position: |d| of the slave's PC, a force */
	double slave_mass_kg, slave_damping_Nspm;
	popc_servo_kind slave_servo;
	double slave_servo_stiffness_Npm, slave_servo_damping_Nspm;
	double slave_force_resolution_N;
	popc_scene_channel fwd, bwd;
	double slave_rate_Hz;                /* 0: run.rate; else N x run.rate (written when set) */
	/* [integrator] */
	popc_integrator integrator;
	int substeps;
	/* [axis]: where the loop closes (sim or modbus); modbus details in the map */
	char axis[POPC_NAME_MAX];
	char axis_map[POPC_PATH_MAX];
	char axis_connect[POPC_PATH_MAX];

	/* not keys: where the scene came from, for messages and provenance */
	char source[POPC_PATH_MAX];
	/* not a key: the data directories a bare scene or map name is looked up
	 * in (data_path.h), in POPC_DATA_PATH's syntax; empty: the built-in one
	 * alone. The caller sets it (popc_scene_set_data_path): the programs
	 * from POPC_DATA_PATH; the library layers read no environment. */
	char data_path[POPC_PATH_MAX];
} popc_scene;

/* Fills s with every default (the paper's scene: README, "Scenes"), the
 * data path empty (the built-in data directory alone). */
void popc_scene_defaults(popc_scene *s);

/* Sets the data directories that popc_scene_load and axis.map look bare
 * names up in (data_path.h): a ':'-separated list, an empty entry standing
 * for the built-in directory; NULL or "": the built-in one alone. what names
 * the list's origin in the message ("POPC_DATA_PATH"). POPC_ERR_INVALID
 * when it is longer than POPC_PATH_MAX - 1 characters (s unchanged). */
int popc_scene_set_data_path(popc_scene *s, const char *data_path, const char *what,
			     popc_error *err);
/* 0 when every key's default is in its key's range (the table is right),
 * else the first refusal's status and message: popc_scene_defaults itself
 * reports nothing, the tests call this. */
int popc_scene_defaults_check(popc_error *err);

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

/* A key set many times (a sweep's varied keys, for every run) is found once:
 * popc_scene_key_index gives section.key's place in the key table (-1: no
 * such key; popc_scene_set says why), and popc_scene_set_index sets it as
 * popc_scene_set(s, section, key, value, err) would: the same checks, the
 * same messages, the same scene. */
int popc_scene_key_index(const char *section, const char *key);
int popc_scene_set_index(popc_scene *s, int index, const char *value, popc_error *err);

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

/* The control period T = 1 / rate (s), and the number of control ticks. */
double popc_scene_period_s(const popc_scene *s);
long long popc_scene_ticks(const popc_scene *s);

/* The slave's sub-ticks a tick, N = slave.rate / run.rate (1 when slave.rate
 * is 0): its plant steps T / N (docs/TELEOPERATION.md, "Each side its own
 * rate"); 0 when slave.rate is no whole multiple within 1e-9 or N is beyond
 * POPC_SLAVE_MAX_SUBSTEPS. */
#define POPC_SLAVE_MAX_SUBSTEPS 1000
int popc_scene_slave_substeps(const popc_scene *s);

/* Key reference for --help and the README: one line per key with its unit,
 * default and allowed range. */
void popc_scene_print_keys(FILE *f);

#endif
