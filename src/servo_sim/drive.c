/* popc-servo-sim's drive model (drive.h). */
#include "drive.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "popc/util/numfmt.h"

/* Every protocol address exists, so any register map fits (the Modbus data
 * model has 65536 addresses per table, Application Protocol V1.1b3, 4.4). */
#define TABLE_SIZE 65536

static uint16_t *table_of(servo_drive *d, popc_reg_table t)
{
	return t == POPC_TABLE_INPUT ? d->mb->tab_input_registers : d->mb->tab_registers;
}

static void record(servo_drive *d, const char *text)
{
	snprintf(d->record[d->n_record % DRIVE_RECORD_MAX], sizeof d->record[0], "%s", text);
	d->n_record++;
}

/* Position and status registers from the plant and the drive state. */
static void refresh(servo_drive *d)
{
	const popc_register_map *m = &d->map;
	double v;
	/* a reversed map: the drive counts the other way (popc negates back) */
	double sign = m->pos.reversed ? -1.0 : 1.0;
	if (d->passthrough && m->pos.type != POPC_REG_FLOAT32 && m->pos.type != POPC_REG_FLOAT64)
		v = sign * (double)d->smp.count; /* exactly the simulated encoder's count */
	else if (m->pos.type == POPC_REG_FLOAT32 || m->pos.type == POPC_REG_FLOAT64)
		v = sign * d->smp.x_true_m * m->pos.counts_per_m;
	else
		v = floor(sign * d->smp.x_true_m * m->pos.counts_per_m); /* the drive's own encoder */
	popc_reg_encode(v, m->pos.type, m->pos.order, table_of(d, m->pos.table) + m->pos.reg);
	if (d->servo) {
		/* the sensor's reading, its count (and noise) included: the count
		 * itself when the unit is the scene's resolution, else the force
		 * n r in the register's unit */
		double r = d->fs_resolution_N, n = (double)d->smp.force_count;
		double f = d->fs_passthrough && m->sensor.type != POPC_REG_FLOAT32 &&
					   m->sensor.type != POPC_REG_FLOAT64
				   ? n
				   : n * r / m->sensor.newton_per_unit;
		if (m->sensor.type != POPC_REG_FLOAT32 && m->sensor.type != POPC_REG_FLOAT64)
			f = nearbyint(f);
		popc_reg_encode(m->sensor.reversed ? -f : f, m->sensor.type, m->sensor.order,
				table_of(d, m->sensor.table) + m->sensor.reg);
		/* a position-mode drive's set point follows its actual position
		 * while it is disabled (as CiA 402 drives' does): popc reads it
		 * back at start and holds exactly there */
		if (m->cmd.mode == POPC_CMD_POSITION && !d->enabled) {
			double u = d->smp.x_true_m * m->cmd.counts_per_m;
			if (m->cmd.type != POPC_REG_FLOAT32 && m->cmd.type != POPC_REG_FLOAT64)
				u = nearbyint(u);
			popc_reg_encode(m->cmd.reversed ? -u : u, m->cmd.type, m->cmd.order,
					d->mb->tab_registers + m->cmd.reg);
		}
	}
	uint16_t status = 0;
	if (d->enabled && !d->fault && !d->never_ready)
		status |= m->status.ready_mask;
	if (d->fault)
		status |= m->status.fault_mask;
	table_of(d, m->status.table)[m->status.reg] = status;
}

void drive_set_fault(servo_drive *d, const char *why, int permanent)
{
	if (!d->fault)
		snprintf(d->fault_why, sizeof d->fault_why, "%s", why);
	d->fault = 1;
	d->fault_permanent |= permanent;
	d->enabled = 0;
	refresh(d);
}

/* The velocity command of the coming period for a servo-mode drive: the
 * velocity set point, or the interpolation from the position command the
 * servo tracks now to the set point, (x_set - x_c) / T (the set point is
 * reached at the period's end, then held). A disabled or faulted drive
 * holds its position command (velocity 0: the simulated servo stays on,
 * as a drive's holding brake would keep the axis). */
static double servo_velocity(const servo_drive *d)
{
	if (!d->enabled || d->fault)
		return 0.0;
	if (d->map.cmd.mode == POPC_CMD_VELOCITY)
		return d->cmd_value;
	return (d->cmd_value - d->smp.x_cmd_m) / popc_scene_period_s(&d->scene);
}

/* One control period with the command now in force. */
static int advance(servo_drive *d)
{
	double f_dev = d->enabled && !d->fault ? d->cmd_value : 0.0;
	popc_error err;
	/* the device receives -f_c (README, "The plant"), so f_c = -f_dev;
	 * exact. A servo-mode drive's plant takes the velocity command. */
	double cmd = d->servo ? servo_velocity(d) : -f_dev;
	if (d->plant->ops->exchange(d->plant, cmd, &d->smp, &err) != 0) {
		fprintf(stderr, "popc-servo-sim: %s\n", err.msg);
		drive_set_fault(d, "plant diverged", 1);
		return -1;
	}
	d->k++;
	return 0;
}

void drive_tick(servo_drive *d, int64_t now_ns)
{
	if (d->watchdog_ms > 0 && d->enabled && !d->fault &&
	    now_ns - d->last_cmd_ns > (int64_t)d->watchdog_ms * 1000000) {
		fprintf(stderr, "popc-servo-sim: watchdog: no command for %d ms: fault, zero torque\n",
			d->watchdog_ms);
		drive_set_fault(d, "watchdog", 0);
	}
	if (d->lockstep || !d->clock_running)
		return;
	long long target = (now_ns - d->origin_ns) / d->period_ns;
	int moved = 0;
	while (d->k < target) {
		if (advance(d) != 0)
			break;
		moved = 1;
	}
	if (moved)
		refresh(d);
}

static void enable_write(servo_drive *d, uint16_t value, int64_t now_ns)
{
	const popc_register_map *m = &d->map;
	char text[64];
	snprintf(text, sizeof text, "enable 0x%04x", value);
	record(d, text);
	if (value == m->enable.off) {
		d->enabled = 0;
		/* a disabled position drive forgets its set point: enabled
		 * again without a new one, it holds where it is */
		if (m->cmd.mode == POPC_CMD_POSITION)
			d->cmd_value = d->smp.x_cmd_m;
		if (d->fault && !d->fault_permanent) /* a latched fault clears on disable */
			d->fault = 0;
	} else if (value == m->enable.on[m->enable.n_on - 1]) {
		if (!d->fault) {
			d->enabled = 1;
			d->last_cmd_ns = now_ns;
			if (!d->clock_running) {
				d->clock_running = 1;
				d->origin_ns = now_ns - d->k * d->period_ns;
			}
		}
	} else {
		d->enabled = 0; /* an intermediate word of an enable sequence */
	}
	refresh(d);
}

/* Registers [addr, addr + n) were written with the big-endian words at p. */
static int register_write(servo_drive *d, int addr, int n, const uint8_t *p, int64_t now_ns)
{
	const popc_register_map *m = &d->map;
	int ncmd = popc_reg_type_words(m->cmd.type), cmd_hit = 0, seq_hit = 0;
	uint16_t seq = 0;
	for (int i = 0; i < n; i++) {
		int r = addr + i;
		uint16_t v = (uint16_t)(p[2 * i] << 8 | p[2 * i + 1]);
		if (r >= m->cmd.reg && r < m->cmd.reg + ncmd) {
			d->mb->tab_registers[r] = v;
			cmd_hit = 1;
		} else if (r == m->cmd.seq_reg) {
			d->mb->tab_registers[r] = v;
			seq_hit = 1;
			seq = v;
		} else if (m->enable.table == POPC_TABLE_HOLDING && r == m->enable.reg) {
			d->mb->tab_registers[r] = v;
			enable_write(d, v, now_ns);
		}
	}
	/* a new command, unless its sequence value repeats the last one (a
	 * retry); a write without the sequence register counts as new */
	int repeat = seq_hit && d->have_seq && seq == d->last_seq;
	if (seq_hit) {
		d->have_seq = 1;
		d->last_seq = seq;
	}
	if (!cmd_hit)
		return 0;
	if (repeat)
		d->seq_repeats++;
	/* real time: the periods before this write ran with the old command */
	drive_tick(d, now_ns);
	double units = popc_reg_decode(d->mb->tab_registers + m->cmd.reg, m->cmd.type, m->cmd.order);
	/* a reversed map: the register holds minus the command (exact negation) */
	units = m->cmd.reversed ? -units : units;
	d->cmd_value = m->cmd.mode == POPC_CMD_FORCE	? units * m->cmd.newton_per_unit
		       : m->cmd.mode == POPC_CMD_VELOCITY ? units * m->cmd.m_per_s_per_unit
							  : units / m->cmd.counts_per_m;
	d->last_cmd_ns = now_ns;
	d->commands++;
	/* the force, then the register's words as they came over the wire
	 * (register order): a zero force must arrive as all-zero words, never
	 * a float's -0.0 (8000 0000), which a drive's firmware would have to
	 * know for zero */
	char text[sizeof d->record[0]], num[POPC_DOUBLE_TEXT_MAX + 1];
	popc_format_double(d->cmd_value + 0.0, num); /* -0 is written 0 */
	int used = snprintf(text, sizeof text, "command %s [", num);
	for (int i = 0; i < ncmd && used > 0 && (size_t)used < sizeof text; i++)
		used += snprintf(text + used, sizeof text - (size_t)used, "%s%04x", i ? " " : "",
				 (unsigned)d->mb->tab_registers[m->cmd.reg + i]);
	if (used > 0 && (size_t)used < sizeof text)
		snprintf(text + used, sizeof text - (size_t)used, "]");
	record(d, text);
	int st = 0;
	/* the force above is taken either way (a retry carries the same one); the
	 * plant advances once per command */
	if (d->lockstep && d->enabled && !d->fault && !repeat)
		st = advance(d);
	refresh(d);
	return st;
}

static int be16(const uint8_t *p)
{
	return p[0] << 8 | p[1];
}

/* The registers a write request sets: [*addr, *addr + *n) from the words at
 * *p. Returns 0 for a request that writes no register (or a malformed one,
 * which modbus_reply answers with an exception). */
static int write_span(const uint8_t *q, int len, int hl, int *addr, int *n, const uint8_t **p)
{
	if (len < hl + 5)
		return 0;
	switch (q[hl]) {
	case MODBUS_FC_WRITE_SINGLE_REGISTER:
		*addr = be16(q + hl + 1);
		*n = 1;
		*p = q + hl + 3;
		return 1;
	case MODBUS_FC_WRITE_MULTIPLE_REGISTERS:
		*addr = be16(q + hl + 1);
		*n = be16(q + hl + 3);
		*p = q + hl + 6;
		return *n >= 1 && *n <= MODBUS_MAX_WRITE_REGISTERS && *addr + *n <= TABLE_SIZE &&
		       hl + 6 + 2 * *n <= len;
	case MODBUS_FC_WRITE_AND_READ_REGISTERS:
		if (len < hl + 10)
			return 0;
		*addr = be16(q + hl + 5);
		*n = be16(q + hl + 7);
		*p = q + hl + 10;
		return *n >= 1 && *n <= MODBUS_MAX_WR_WRITE_REGISTERS && *addr + *n <= TABLE_SIZE &&
		       hl + 10 + 2 * *n <= len;
	default:
		return 0;
	}
}

long long drive_command_of(const servo_drive *d, const uint8_t *q, int len, int hl)
{
	const popc_register_map *m = &d->map;
	int addr, n;
	const uint8_t *p;
	if (!write_span(q, len, hl, &addr, &n, &p))
		return 0;
	int ncmd = popc_reg_type_words(m->cmd.type);
	if (addr + n <= m->cmd.reg || addr >= m->cmd.reg + ncmd)
		return 0; /* the command register is not written */
	if (m->cmd.seq_reg >= addr && m->cmd.seq_reg < addr + n && d->have_seq) {
		int i = m->cmd.seq_reg - addr;
		if ((uint16_t)(p[2 * i] << 8 | p[2 * i + 1]) == d->last_seq)
			return 0; /* a retry of the last command */
	}
	return d->commands - d->seq_repeats + 1;
}

int drive_apply_request(servo_drive *d, const uint8_t *q, int len, int hl, int64_t now_ns)
{
	if (len < hl + 5)
		return 0;
	if (q[hl] == MODBUS_FC_WRITE_SINGLE_COIL) {
		if (d->map.enable.table == POPC_TABLE_COIL && be16(q + hl + 1) == d->map.enable.reg)
			enable_write(d, be16(q + hl + 3) == 0xFF00 ? 1 : 0, now_ns);
		return 0;
	}
	int addr, n;
	const uint8_t *p;
	if (!write_span(q, len, hl, &addr, &n, &p))
		return 0;
	return register_write(d, addr, n, p, now_ns);
}

/* A teleoperation scene's slave: popc run's simulated slave, at rest where
 * popc run's simulated master starts (its true position at tick 0, as
 * run_teleop.c places it), no hand on it: so that a lockstep run with the
 * drive as the slave equals the simulated run. */
static int teleop_slave_create(servo_drive *d, const popc_scene *scene, popc_error *err)
{
	popc_axis *master = NULL;
	popc_axis_sample sm;
	memset(&sm, 0, sizeof sm);
	int st = popc_sim_axis_create(&master, scene, err);
	if (!st && !(st = master->ops->start(master, err)))
		st = master->ops->sample(master, &sm, err);
	popc_axis_destroy(&master);
	return st ? st : popc_sim_slave_axis_create(&d->plant, scene, sm.x_true_m, err);
}

int drive_init(servo_drive *d, const popc_register_map *map, const popc_scene *scene, int lockstep,
	       popc_error *err)
{
	memset(d, 0, sizeof *d);
	d->map = *map;
	d->scene = *scene;
	d->lockstep = lockstep;
	d->watchdog_ms = map->watchdog_ms;
	d->passthrough = popc_register_map_counts_are_scene_counts(map, scene->enc_resolution_m);
	d->period_ns = llround(1e9 * popc_scene_period_s(scene));
	if (d->period_ns < 1)
		d->period_ns = 1;
	d->servo = map->cmd.mode != POPC_CMD_FORCE;
	popc_servo_kind kind;
	const char *key;
	popc_register_map_scene_servo(scene, &kind, &d->fs_resolution_N, &key);
	d->fs_passthrough = popc_register_map_sensor_is_scene_counts(map, d->fs_resolution_N);
	/* a servo-mode drive moves the admittance-type device of the scene
	 * (the same plant, servo and sensor as popc run's simulated axis), or
	 * a teleoperation scene's slave (popc run's simulated slave) */
	int st = d->servo && scene->tele_arch != POPC_TELEOP_OFF ? teleop_slave_create(d, scene, err)
		 : d->servo ? popc_sim_admittance_axis_create(&d->plant, scene, err)
			    : popc_sim_axis_create(&d->plant, scene, err);
	if (st)
		return st;
	if ((st = d->plant->ops->start(d->plant, err)) || (st = d->plant->ops->sample(d->plant, &d->smp, err))) {
		popc_axis_destroy(&d->plant);
		return st;
	}
	d->mb = modbus_mapping_new(TABLE_SIZE, 0, TABLE_SIZE, TABLE_SIZE);
	if (!d->mb) {
		popc_axis_destroy(&d->plant);
		return popc_error_set(err, POPC_ERR_NOMEM, "cannot allocate the register tables");
	}
	if (map->cmd.mode == POPC_CMD_POSITION)
		d->cmd_value = d->smp.x_cmd_m; /* enabled without a set point: hold */
	refresh(d);
	return 0;
}

void drive_free(servo_drive *d)
{
	if (d->mb)
		modbus_mapping_free(d->mb);
	d->mb = NULL;
	popc_axis_destroy(&d->plant);
}

void drive_write_record(const servo_drive *d, FILE *f)
{
	long long first = d->n_record > DRIVE_RECORD_MAX ? d->n_record - DRIVE_RECORD_MAX : 0;
	for (long long i = first; i < d->n_record; i++)
		fprintf(f, "%s\n", d->record[i % DRIVE_RECORD_MAX]);
}
