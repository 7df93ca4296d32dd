/* A servo drive's Modbus register map, read from an INI file (one file per
 * drive layout, data/drives/). docs/MODBUS.md: drives differ in word order,
 * units and enable/fault words, so the layout is data, never code.
 *
 *   [drive]    name, slave, fc23, timeout_ms, max_failures, enable_timeout_ms, watchdog_ms,
 *              rtu_frame_gap_ms, rs485, rts, rts_delay_us (RTU line)
 *   [position] register, table, type, word_order, counts_per_m | counts_per_rev + lead_m
 *              (+ gear), soft_min_m, soft_max_m (required: the soft limits are
 *              part of the always-on safety supervisor), direction
 *   [command]  mode (force | position | velocity), register, type, word_order,
 *              sequence_register (optional: a command sequence counter next to the
 *              command), direction; mode = force: newton_per_unit |
 *              percent_of_rated_per_unit + rated_torque_Nm + lead_m (+ gear), limit_N;
 *              position: counts_per_m (clamped to the soft limits); velocity:
 *              m_per_s_per_unit, limit_m_per_s
 *   [force_sensor] (mode = position or velocity only, then required) register,
 *              table, type, word_order, newton_per_unit, direction
 *   [enable]   register, table (holding | coil), on (up to 4 values, written in
 *              order), off
 *   [status]   register, table, ready_mask, fault_mask
 *
 * Addresses are zero-based protocol addresses. Word conversion is done here, by
 * hand: libmodbus 3.1.6's float getters and setters disagree and its
 * MODBUS_GET_INT32_FROM_INT16 is wrong for negative values; docs/MODBUS.md). */
#ifndef POPC_REGISTER_MAP_H
#define POPC_REGISTER_MAP_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "popc/util/error.h"
#include "popc/scene/scene.h"

typedef enum popc_reg_table {
	POPC_TABLE_HOLDING, /* FC03 read, FC06/FC16/FC23 write */
	POPC_TABLE_INPUT,   /* FC04 read only */
	POPC_TABLE_COIL,    /* FC05 write (enable only) */
} popc_reg_table;

typedef enum popc_reg_type {
	POPC_REG_INT16,
	POPC_REG_UINT16,
	POPC_REG_INT32,
	POPC_REG_UINT32,
	POPC_REG_FLOAT32,
	POPC_REG_FLOAT64, /* 4 registers: an exact command path (IEEE 754 binary64) */
} popc_reg_type;

typedef enum popc_word_order {
	POPC_WORDS_HI_LO, /* most significant word at the lowest address (AKD, ZLTECH) */
	POPC_WORDS_LO_HI, /* least significant word first (Delta ASDA, Kinco) */
} popc_word_order;

/* What the command register carries (issue 25): a force for an
 * impedance-type device, or the set point of a position or velocity servo
 * for an admittance-type device (docs/ADMITTANCE.md), which then reads the
 * hand's force from a force sensor register. */
typedef enum popc_cmd_mode {
	POPC_CMD_FORCE,
	POPC_CMD_POSITION,
	POPC_CMD_VELOCITY,
} popc_cmd_mode;
extern const char *const popc_cmd_mode_names[]; /* indexed by popc_cmd_mode, NULL-terminated */

#define POPC_MAP_ENABLE_MAX 4

/* Upper bound of timeout_ms x max_failures, ms: how long a silent link may
 * last before popc declares the communication lost. Until then the drive
 * holds the last command unsupervised, and a failing transaction delays the
 * safe stop (the range checks alone allowed 10 s x 100 = 1000 s). 2 s is
 * about the time an operator waits after ^C before reaching for the
 * emergency stop, and leaves room for slow links: the shipped maps need
 * 60-150 ms (20-50 ms x 3), and an RTU drive at 9600 baud, whose FC23
 * exchange takes about 40 ms on the wire, can have 500 ms x 4. (An RTU link
 * also drains the line for up to 4 timeouts after each failure.) */
#define POPC_MAP_SILENCE_MAX_MS 2000

typedef struct popc_register_map {
	char path[POPC_PATH_MAX];
	char name[128];
	int slave;                 /* 1..247 */
	int fc23;                  /* write the command and read the position in one transaction */
	int timeout_ms;            /* response (and byte) timeout */
	int max_failures;          /* failed transactions in a row before communication is lost */
	int enable_timeout_ms;     /* how long start() waits for the ready bits */
	int watchdog_ms;           /* the drive's command watchdog (popc-servo-sim), 0: off */
	/* RTU only (ignored over TCP): silence kept before each request on top of
	 * libmodbus' 3.5 characters, ms; RS-485 mode (TIOCSRS485); RTS control
	 * (0 none, 1 up, 2 down: libmodbus' MODBUS_RTU_RTS_*) and its delay, us
	 * (-1: libmodbus' default) */
	int rtu_frame_gap_ms;
	int rs485;
	int rts;
	int rts_delay_us;

	struct {
		int reg;
		popc_reg_table table;
		popc_reg_type type;
		popc_word_order order;
		double counts_per_m;   /* position value units per metre */
		double soft_min_m, soft_max_m; /* required, finite, min < max; popc's frame */
		int reversed;          /* 1: popc's position = -(register value / counts_per_m) */
	} pos;
	struct {
		popc_cmd_mode mode;
		int reg;
		popc_reg_type type;
		popc_word_order order;
		/* mode = force: */
		double newton_per_unit;
		double limit_N;        /* force clamp, always applied */
		/* mode = position: command units per metre (the position command
		 * is clamped to the soft limits); mode = velocity: m/s per
		 * command unit and the velocity clamp, always applied */
		double counts_per_m;
		double m_per_s_per_unit;
		double limit_m_per_s;
		int reversed;          /* 1: the register holds -(force on the device) / newton_per_unit */
		/* The command sequence register (a heartbeat / sign-of-life counter),
		 * -1: none. A uint16 holding register right before or right after
		 * the command, so that every command write carries it in the same
		 * transaction. popc writes a new value (the previous one + 1, modulo
		 * 65536) with every new command, and the same value again when it
		 * retries a transaction whose reply was lost: a drive (popc-servo-sim
		 * in lockstep) can tell a retry from a new command and act on each
		 * command once. */
		int seq_reg;
	} cmd;
	/* mode = position or velocity: the force the hand exerts on the device,
	 * F = register value x newton_per_unit (reversed: minus that) */
	struct {
		int reg;
		popc_reg_table table;
		popc_reg_type type;
		popc_word_order order;
		double newton_per_unit;
		int reversed;
	} sensor;
	struct {
		int reg;
		popc_reg_table table;
		int n_on;
		uint16_t on[POPC_MAP_ENABLE_MAX]; /* written in order; the last one means enabled */
		uint16_t off;
	} enable;
	struct {
		int reg;
		popc_reg_table table;
		uint16_t ready_mask;   /* ready when (status & ready_mask) == ready_mask */
		uint16_t fault_mask;   /* faulted when status & fault_mask != 0 */
	} status;
} popc_register_map;

/* Reads and validates a map file. Unknown or duplicate keys, bad values,
 * missing keys and inconsistent combinations (overlapping registers, two
 * scales given, a command that cannot reach limit_N, a derived scale that is
 * not finite and above 0, a conversion that is not finite or in range in
 * either direction for the commands |f| <= limit_N, the soft limits or any
 * value a register can hold: docs/MODBUS.md, "Derived scales") are rejected
 * with a message naming the file, the line (none when the problem is a
 * missing key) and the key (every key behind a derived scale, with its line). A line longer than the reader's buffer is refused with its
 * line number (libinih would split it and count the pieces as lines).
 * Single keys are checked first, in file order, then the rules between keys.
 * Returns 0 or a negative popc_status. */
int popc_register_map_load(popc_register_map *m, const char *path, popc_error *err);

/* The keys a map file may hold: one row each (src/axes/modbus/
 * register_map_keys.def), from which loading, the defaults, the range checks
 * and the listing below all come. */
typedef enum popc_map_value {
	POPC_MAP_TEXT,      /* any text (up to 127 characters) */
	POPC_MAP_INT,       /* an integer in [lo, hi]: decimal, or hexadecimal with 0x (a
			       leading zero is decimal: "0100" is 100, not octal 64) */
	POPC_MAP_NUMBER,    /* a decimal number in [lo, hi], or (lo, hi] with lo_open, as in
			       scenes: no hex floats, no inf or nan */
	POPC_MAP_CHOICE,    /* one of choices */
	POPC_MAP_WORDS,     /* 1 to POPC_MAP_ENABLE_MAX integers in [lo, hi], separated by
			       commas or blanks */
} popc_map_value;

typedef struct popc_map_key {
	const char *section, *key;
	popc_map_value type;
	double lo, hi;               /* INT, NUMBER, WORDS: the allowed range */
	int lo_open;                 /* NUMBER: lo itself is refused */
	const char *const *choices;  /* CHOICE: NULL-terminated; the index is the value */
	const char *default_text;    /* the value of an absent key, as a map would write it;
					NULL: none */
	const char *required;        /* NULL: optional; else an absent key is refused, and a
					non-empty text says why */
	const char *refusal;         /* CHOICE: the message for any other value, where "expected
					one of" would not say why (NULL: that message) */
	const char *unit;            /* NULL: none */
	const char *help;
	unsigned modes;              /* the command modes the key belongs to (bits
					POPC_MAP_MODE(popc_cmd_mode)), 0: every mode. In
					another mode the key is refused when given, and
					neither required nor defaulted when absent. */
} popc_map_key;
#define POPC_MAP_MODE(mode) (1u << (mode))

/* Row i of the table, in file order ([drive], [position], [command],
 * [force_sensor], [enable], [status]); NULL past the last row. */
const popc_map_key *popc_register_map_key(size_t i);

/* Every key with its default and allowed range, as popc scene keys lists a
 * scene's (popc-servo-sim --map-keys). */
void popc_register_map_print_keys(FILE *f);

/* The registers every command write covers: the command and, when the map
 * has one, the sequence register next to it. Sets *first to the lowest
 * address and returns the number of registers (1 to POPC_MAP_CMD_BLOCK_MAX). */
#define POPC_MAP_CMD_BLOCK_MAX 5
int popc_register_map_command_block(const popc_register_map *m, int *first);

/* Number of 16-bit registers a value of this type occupies (1, 2 or 4). */
int popc_reg_type_words(popc_reg_type t);
const char *popc_reg_type_name(popc_reg_type t);
/* The names of the types, indexed by popc_reg_type, NULL-terminated (a
 * map's position.type and command.type take them). */
extern const char *const popc_reg_type_names[];

/* Words -> value. Integer types are exact in a double (|v| < 2^53). */
double popc_reg_decode(const uint16_t *words, popc_reg_type t, popc_word_order o);

/* Value -> words. Integer types round to nearest and saturate at the type's
 * range; returns 1 when the value had to be saturated, else 0. */
int popc_reg_encode(double v, popc_reg_type t, popc_word_order o, uint16_t *words);

/* Whether the drive's position counts are the scene's encoder counts
 * (counts_per_m * resolution == 1 within 1e-9): then counts pass through
 * unchanged, and a run on the drive sees exactly the counts the simulated
 * encoder would give. */
int popc_register_map_counts_are_scene_counts(const popc_register_map *m, double resolution_m);

/* Whether the force sensor's units are the scene's force counts
 * (newton_per_unit == admittance.force_resolution within 1e-9): then an
 * integer sensor register holds the count itself, as position counts pass
 * through (popc-servo-sim writes it, popc reads it, unchanged). */
int popc_register_map_sensor_is_scene_counts(const popc_register_map *m, double resolution_N);

/* The map's command mode against the scene (issue 25): an impedance scene
 * commands a force (command.mode = force); an admittance scene commands the
 * set point of its device's servo (command.mode = admittance.servo, position
 * or velocity) and reads the hand's force from [force_sensor]. A mismatch is
 * POPC_ERR_INVALID naming the map and the key (popc run and popc-servo-sim
 * both refuse it, exit 2, before anything connects or listens). */
int popc_register_map_fits_scene(const popc_register_map *m, const popc_scene *s, popc_error *err);

/* The servo-mode device a drive is in scene s: an admittance scene's own
 * ([admittance]: servo, force_resolution), or a teleoperation scene's slave
 * ([slave]: the drive is the slave, the master stays simulated;
 * docs/TELEOPERATION.md). Returns 0 for a one-port impedance scene (the
 * drive commands a force), else 1 with *servo, *force_resolution_N and, for
 * messages, *servo_key ("admittance.servo" or "slave.servo"). */
int popc_register_map_scene_servo(const popc_scene *s, popc_servo_kind *servo,
				  double *force_resolution_N, const char **servo_key);

#endif
