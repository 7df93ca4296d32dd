/* popc-servo-sim's drive model: the registers of any register map around the
 * simulated plant of a scene (popc_sim_axis_create). Private to the program.
 *
 * - Position registers hold the plant's measured position in the map's type
 *   and scale; when the map's counts are the scene's encoder counts they hold
 *   exactly the count the simulated encoder gives, so a lockstep run equals
 *   the simulated run bit for bit.
 * - The command register holds the force on the device (the runner writes
 *   -f_c: the device receives -f_c, README, "The plant"); it acts only while the
 *   drive is enabled and not faulted.
 * - A servo-mode map (command.mode = position or velocity, issue 25): the
 *   plant is the scene's admittance-type device (popc_sim_admittance_axis_
 *   create: its servo loop and force sensor); the command register is the
 *   velocity set point, or the position set point reached by linear
 *   interpolation over the period; the force sensor register holds the
 *   sensor's reading in the map's type, scale and direction. In a
 *   teleoperation scene the plant is its slave instead (popc_sim_slave_
 *   axis_create: [slave]'s device against [environment], no hand, at rest
 *   where the simulated master starts), the drive being popc run's slave
 *   (axis.kind = modbus; docs/TELEOPERATION.md). While
 *   disabled a position drive's set point register reads its actual
 *   position, and the servo holds its position command.
 * - Lockstep: each command write while enabled advances the plant exactly one
 *   control period. With a command sequence register in the map, only a
 *   command whose sequence value differs from the last one written does: a
 *   repeated value is a retried transaction (its reply was lost), answered
 *   with the current state without advancing, so a run with a transient
 *   link fault stays equal to the simulated run. Without the register every
 *   command write advances (a retry advances the plant again). Real time:
 *   the plant follows the wall clock from the first enable, one period at a
 *   time with the command then in force (ZOH); the sequence is not used.
 * - Direction: a map's position.direction and command.direction = reversed
 *   hold minus the position and minus the force in the registers, as a drive
 *   whose motor turns the other way, so that popc, which negates them back,
 *   sees the same plant bit for bit.
 * - Watchdog: enabled and no command for watchdog_ms -> fault bit, zero force.
 *   A fault latches until the disable word is written (except a fault set
 *   with --start-faulted, which stays until the program ends). */
#ifndef POPC_SERVO_SIM_DRIVE_H
#define POPC_SERVO_SIM_DRIVE_H

#include <modbus.h>
#include <stdint.h>
#include <stdio.h>

#include "popc/axes/sim_axis.h"
#include "popc/axes/register_map.h"
#include "popc/scene/scene.h"

#define DRIVE_RECORD_MAX 8

typedef struct servo_drive {
	popc_register_map map;
	popc_scene scene;
	popc_axis *plant;
	popc_axis_sample smp;
	modbus_mapping_t *mb;
	int lockstep;
	int passthrough;
	int64_t period_ns;

	int enabled;
	int never_ready;           /* --never-ready: the ready bits never come (a stuck enable) */
	int fault, fault_permanent;
	char fault_why[128];
	double cmd_value;          /* the command as decoded: force on the device (N), or a
				      servo-mode drive's velocity (m/s) or position (m) set point */
	int servo;                 /* command.mode = position or velocity */
	int fs_passthrough;        /* the force sensor's unit is the scene's resolution */
	double fs_resolution_N;    /* that resolution: admittance.force_resolution, or a
				      teleoperation scene's slave.force_resolution */
	long long k;               /* control periods the plant has advanced */
	int clock_running;
	int64_t origin_ns;         /* real time: when the plant's clock started */
	int64_t last_cmd_ns;
	int watchdog_ms;

	long long commands;
	int have_seq;              /* a sequence value has been written (last_seq is valid) */
	uint16_t last_seq;
	long long seq_repeats;     /* command writes that repeated the last sequence value */
	char record[DRIVE_RECORD_MAX][96]; /* the last writes of command and enable, a ring */
	long long n_record;
} servo_drive;

int drive_init(servo_drive *d, const popc_register_map *map, const popc_scene *scene, int lockstep,
	       popc_error *err);
void drive_free(servo_drive *d);

/* Applies the writes of a request (FC05/06/16/23) before libmodbus builds the
 * reply, so that an FC23 reply carries the position after the command. query
 * and len are what modbus_receive returned; hl its header length. Returns 0,
 * or -1 when the plant diverged (the drive faults). */
int drive_apply_request(servo_drive *d, const uint8_t *query, int len, int hl, int64_t now_ns);

/* The number of the new command a request writes, counted from 1 over the
 * program's life (the start's zero force is command 1): the commands applied
 * so far plus one, or 0 when the request writes no command or repeats the
 * last sequence value (a retry, with the map's sequence register). A request
 * answered with an exception applies nothing, so its retry carries the same
 * number. Without a sequence register a retried command is a new one. */
long long drive_command_of(const servo_drive *d, const uint8_t *query, int len, int hl);

/* Time passes: the real-time plant catches up with the clock; the watchdog. */
void drive_tick(servo_drive *d, int64_t now_ns);

/* Sets a fault (fault injection, or --start-faulted when permanent). */
void drive_set_fault(servo_drive *d, const char *why, int permanent);

/* Writes the recorded last writes, oldest first, one per line. */
void drive_write_record(const servo_drive *d, FILE *f);

#endif
