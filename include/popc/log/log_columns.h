/* The columns of popc's CSV log (log.h), declared once.
 *
 * POPC_LOG_COLUMN_TABLE is the schema: one line per column, in the order of
 * the log. The writer's row, the column names line, the reader's lookup of
 * popc's own names, popc-analyze's --column and --scale names, the sweep's
 * chatter replay and `popc bench log` all expand or read it, so adding a
 * column is one line here, the popc_log_row field it reads, and its test
 * (tests/unit/test_log.c checks every column of the table round trip).
 *
 * COLUMN(ID, name, unit, fill, format, field, meaning):
 *   ID      suffix of the column's POPC_LOG_COLUMN_<ID> index
 *   name    the column name in the log, as a C identifier (#name is the text)
 *   unit    SI unit of the cells ("" for a count or a bit set)
 *   fill    which axes write it: ALWAYS, X_TRUE (an axis with a simulated true
 *           position), TIMING (a real axis' measured period and round trip)
 *           or ADMITTANCE (an admittance-type device: docs/ADMITTANCE.md)
 *           or TELEOP (a teleoperation scene's slave and network ports:
 *           docs/TELEOPERATION.md; the columns every log has are the master's)
 *           or SLAVE_TRUE (a teleoperation scene's simulated slave: a Modbus
 *           slave has no true position)
 *           -- the POPC_LOG_COL_<fill> bit an axis sets in its log_columns
 *   format  DOUBLE (shortest round-trip text), COUNT (signed integer) or
 *           FLAGS (unsigned bit set, POPC_FLAG_*)
 *   field   the popc_log_row member the cell holds
 *   meaning one line for documentation and help */
#ifndef POPC_LOG_COLUMNS_H
#define POPC_LOG_COLUMNS_H

#include <stddef.h>

#include "popc/core/admittance.h"
#include "popc/core/controller.h"

#define POPC_LOG_COLUMN_TABLE(COLUMN)                                                                        \
	COLUMN(T,      t,      "s",   ALWAYS, DOUBLE, tick.t_s,     "time since the start, k T")             \
	COLUMN(X,      x,      "m",   ALWAYS, DOUBLE, tick.x_m,     "measured position, count x resolution") \
	COLUMN(COUNT,  count,  "",    ALWAYS, COUNT,  tick.count,   "encoder count")                         \
	COLUMN(X_TRUE, x_true, "m",   X_TRUE, DOUBLE, x_true_m,     "true position of the simulated plant")  \
	COLUMN(V,      v,      "m/s", ALWAYS, DOUBLE, tick.v_mps,   "velocity the controller used")          \
	COLUMN(F_E,    f_e,    "N",   ALWAYS, DOUBLE, tick.f_e_N,   "virtual environment force")             \
	COLUMN(F_PC,   f_pc,   "N",   ALWAYS, DOUBLE, tick.f_pc_N,  "passivity controller force")            \
	COLUMN(F_C,    f_c,    "N",   ALWAYS, DOUBLE, tick.f_c_N,   "force command to the axis")             \
	COLUMN(W,      W,      "J",   ALWAYS, DOUBLE, tick.W_J,     "passivity observer energy")             \
	COLUMN(E_REF,  E_ref,  "J",   ALWAYS, DOUBLE, tick.E_ref_J, "reference energy")                      \
	COLUMN(FLAGS,  flags,  "",    ALWAYS, FLAGS,  tick.flags,   "controller events, POPC_FLAG_*")        \
	COLUMN(E_PORT, E_port, "J",   X_TRUE, DOUBLE, E_port_J,     "true energy into the VE port (ZOH)")    \
	COLUMN(DT,     dt,     "s",   TIMING, DOUBLE, dt_s,         "measured period of the tick")           \
	COLUMN(RTT,    rtt,    "s",   TIMING, DOUBLE, rtt_s,        "round trip of the axis transaction")    \
	COLUMN(F_COUNT, f_count, "",  ADMITTANCE, COUNT, adm.n,      "force sensor count (admittance)")       \
	COLUMN(F_MEAS, f_meas, "N",   ADMITTANCE, DOUBLE, adm.f_N,  "force reading, count x resolution")     \
	COLUMN(X_CMD,  x_cmd,  "m",   ADMITTANCE, DOUBLE, x_cmd_m,  "position command the servo tracks")     \
	COLUMN(V_VE,   v_ve,   "m/s", ADMITTANCE, DOUBLE, adm.v_ve_mps, "velocity of the admittance VE")     \
	COLUMN(V_PC,   v_pc,   "m/s", ADMITTANCE, DOUBLE, adm.v_pc_mps, "parallel PC velocity, beta f")   \
	COLUMN(XS,     xs,     "m",   TELEOP, DOUBLE, tele.xs_m,     "slave measured position")              \
	COLUMN(XS_TRUE, xs_true, "m", SLAVE_TRUE, DOUBLE, tele.xs_true_m, "slave true position")             \
	COLUMN(XS_CMD, xs_cmd, "m",   TELEOP, DOUBLE, tele.xs_cmd_m, "slave servo's position command")       \
	COLUMN(FS_COUNT, fs_count, "", TELEOP, COUNT, tele.fs_count, "slave force sensor count")             \
	COLUMN(FS,     fs,     "N",   TELEOP, DOUBLE, tele.fs_N,     "slave force reading (environment on slave)") \
	COLUMN(VS_RX,  vs_rx,  "m/s", TELEOP, DOUBLE, tele.vs_rx_mps, "master velocity the slave holds")     \
	COLUMN(VS_PC,  vs_pc,  "m/s", TELEOP, DOUBLE, tele.vs_pc_mps, "slave PC velocity")                   \
	COLUMN(VS_C,   vs_c,   "m/s", TELEOP, DOUBLE, tele.vs_c_mps, "slave velocity command")               \
	COLUMN(WS,     Ws,     "J",   TELEOP, DOUBLE, tele.Ws_J,     "slave observer before its PC")         \
	COLUMN(EM_IN,  Em_in,  "J",   TELEOP, DOUBLE, tele.Em_in_J,  "energy into the network at the master") \
	COLUMN(EM_OUT, Em_out, "J",   TELEOP, DOUBLE, tele.Em_out_J, "energy out of the network at the master") \
	COLUMN(EM_RX,  Em_rx,  "J",   TELEOP, DOUBLE, tele.Em_rx_J,  "slave's E_in as the master holds it")  \
	COLUMN(ES_IN,  Es_in,  "J",   TELEOP, DOUBLE, tele.Es_in_J,  "energy into the network at the slave") \
	COLUMN(ES_OUT, Es_out, "J",   TELEOP, DOUBLE, tele.Es_out_J, "energy out of the network at the slave") \
	COLUMN(ES_RX,  Es_rx,  "J",   TELEOP, DOUBLE, tele.Es_rx_J,  "master's E_in as the slave holds it")  \
	COLUMN(FWD_AGE, fwd_age, "",  TELEOP, COUNT, tele.fwd_age,   "ticks since the slave's held packet was sent (-1: none)") \
	COLUMN(BWD_AGE, bwd_age, "",  TELEOP, COUNT, tele.bwd_age,   "ticks since the master's held packet was sent (-1: none)") \
	COLUMN(XM_RX,  xm_rx,  "m",   DRIFT, DOUBLE, tele.xm_rx_m,   "master position the slave holds (0: none yet)") \
	COLUMN(VS_DC,  vs_dc,  "m/s", DRIFT, DOUBLE, tele.vs_dc_mps, "slave drift compensation velocity")

/* Which axes fill a column: the bits of an axis' log_columns. A column is
 * written when all its bits are in the log's set (ALWAYS has none). */
enum popc_log_columns {
	POPC_LOG_COL_ALWAYS = 0,
	POPC_LOG_COL_X_TRUE = 1,  /* simulated true position */
	POPC_LOG_COL_TIMING = 2,  /* dt (measured period) and rtt (Modbus transaction time) */
	POPC_LOG_COL_ADMITTANCE = 4, /* force count and reading, commanded motion, PC velocity */
	POPC_LOG_COL_TELEOP = 8,  /* the slave and both network ports (docs/TELEOPERATION.md) */
	/* a teleoperation scene's simulated slave: its true position (with
	 * TELEOP; a Modbus slave, axis.kind = modbus, has none) */
	POPC_LOG_COL_SLAVE_TRUE = 16,
	POPC_LOG_COL_DRIFT = 32,  /* with TELEOP: the slave's drift compensation (teleop.drift) */
};

typedef enum popc_log_cell_format {
	POPC_LOG_CELL_DOUBLE,     /* popc_format_double: shortest round trip */
	POPC_LOG_CELL_COUNT,      /* signed decimal integer */
	POPC_LOG_CELL_FLAGS,      /* unsigned decimal integer, a bit set */
} popc_log_cell_format;

/* A teleoperation tick's own cells (docs/TELEOPERATION.md, "The log"). */
typedef struct popc_teleop_row {
	double xs_m, xs_true_m, xs_cmd_m;
	long long fs_count;
	double fs_N;
	double vs_rx_mps, vs_pc_mps, vs_c_mps, Ws_J;
	double Em_in_J, Em_out_J, Em_rx_J, Es_in_J, Es_out_J, Es_rx_J;
	long long fwd_age, bwd_age;
	double xm_rx_m, vs_dc_mps; /* POPC_LOG_COL_DRIFT only */
} popc_teleop_row;

/* One row of the log: a controller tick and what the axis measured. */
typedef struct popc_log_row {
	popc_tick tick;
	double x_true_m;
	double E_port_J;          /* port_energy.h: E_port(k), with x_true_m */
	double dt_s, rtt_s;
	/* admittance causality only (POPC_LOG_COL_ADMITTANCE) */
	popc_admittance_tick adm;
	double x_cmd_m;
	/* teleoperation only (POPC_LOG_COL_TELEOP) */
	popc_teleop_row tele;
} popc_log_row;

/* POPC_LOG_COLUMN_T, POPC_LOG_COLUMN_X, ...: a column's index in the table. */
typedef enum popc_log_column_id {
#define POPC_LOG_COLUMN_ID_(ID, name, unit, fill, format, field, meaning) POPC_LOG_COLUMN_##ID,
	POPC_LOG_COLUMN_TABLE(POPC_LOG_COLUMN_ID_)
#undef POPC_LOG_COLUMN_ID_
	POPC_LOG_N_COLUMNS
} popc_log_column_id;

typedef struct popc_log_column {
	const char *name;
	const char *unit;
	const char *meaning;
	unsigned fill;                /* POPC_LOG_COL_* bits, 0: always */
	popc_log_cell_format format;
} popc_log_column;

/* The table as data, indexed by popc_log_column_id. */
extern const popc_log_column popc_log_columns[POPC_LOG_N_COLUMNS];

/* The longest column names line: every name and a comma after each. */
#define POPC_LOG_NAMES_LINE_MAX 256

/* Whether a column filled by `fill` is in a log of the column set `columns`. */
static inline int popc_log_column_written(unsigned fill, unsigned columns)
{
	return (fill & ~columns) == 0u;
}

/* The id of popc's column name (exact spelling), or -1. */
int popc_log_column_find(const char *name);

/* The position of column id in a log of the column set `columns` (0 for t),
 * or -1 when such a log has no such column. */
int popc_log_column_index(unsigned columns, popc_log_column_id id);

/* The column names line of a column set ("t,x,count,..."), without newline,
 * into buf (cap >= POPC_LOG_NAMES_LINE_MAX holds any); returns its length. */
size_t popc_log_column_names(unsigned columns, char *buf, size_t cap);

/* A column's cell of a row as a double (a count or flags converted), and a
 * double into it (for count and flags an integer the field can hold). */
double popc_log_row_get(const popc_log_row *r, popc_log_column_id id);
void popc_log_row_set(popc_log_row *r, popc_log_column_id id, double value);

#endif
