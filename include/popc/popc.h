/* libpopc: popc's validated PO/PC as a library, for a device's own control
 * loop (docs/LIBRARY.md is the reference: ownership, threads, real time,
 * the ABI policy).
 *
 * The one public header, and the only one installed: opaque handles made by
 * a create function and freed by a free function, sizes the library knows
 * and the caller need not, plain C types and a few small structs whose
 * layout is part of the ABI. Every name is popc_lib_* or POPC_LIB_*, apart
 * from the export macro POPC_API, so that the internal headers
 * (popc/<layer>/x.h, never installed) may be included beside this one.
 *
 * The layer is thin: each function calls the internal functions the programs
 * call (popc run, popc-analyze), so a tick through the library gives the
 * bits the programs log. Compiles as C and as C++ (tests/lib/test_lib_cxx.cpp). */
#ifndef POPC_POPC_H
#define POPC_POPC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What the library exports: it is built with -fvisibility=hidden, so only
 * the functions marked here are in its dynamic symbol table
 * (src/lib/popc.symbols lists them; a test compares). */
#if defined(__GNUC__) || defined(__clang__)
#define POPC_API __attribute__((visibility("default")))
#else
#define POPC_API
#endif

/* The API version (not popc's release): MAJOR is the soname's number and
 * changes only when a function or a public struct changes incompatibly;
 * MINOR counts additions. */
#define POPC_LIB_API_VERSION_MAJOR 1
#define POPC_LIB_API_VERSION_MINOR 3
#define POPC_LIB_API_VERSION_PATCH 0
#define POPC_LIB_API_VERSION_INT(major, minor, patch) (((major) << 16) | ((minor) << 8) | (patch))
#define POPC_LIB_API_VERSION                                                                        \
	POPC_LIB_API_VERSION_INT(POPC_LIB_API_VERSION_MAJOR, POPC_LIB_API_VERSION_MINOR,             \
				 POPC_LIB_API_VERSION_PATCH)

/* The API version of the library loaded at run time (POPC_LIB_API_VERSION_INT
 * form): a program built against MAJOR.MINOR runs with any library of the
 * same MAJOR and a MINOR at least as large. */
POPC_API unsigned popc_lib_api_version(void);
/* popc's release ("0.1.0"), as `popc --version` prints it. */
POPC_API const char *popc_lib_version(void);

/* Status of every fallible call: 0 or one of these (the values of popc's
 * internal popc_status; README's exit-code table maps them). */
enum {
	POPC_LIB_OK = 0,
	POPC_LIB_ERR_INVALID = -1,     /* bad input: a scene key or value, a file's content */
	POPC_LIB_ERR_IO = -2,          /* a file or stream error */
	POPC_LIB_ERR_NOMEM = -3,
	POPC_LIB_ERR_NUMERIC = -4,     /* non-finite or diverging numbers */
	POPC_LIB_ERR_COMM = -5,        /* communication with an axis */
	POPC_LIB_ERR_SAFETY = -6,
	POPC_LIB_ERR_INTERRUPTED = -7,
	POPC_LIB_ERR_DIVERGED = -8,    /* the simulated closed loop diverged */
};

/* The message of a failed call: names the file, line, key and allowed range
 * where those apply. err may be NULL in every call. */
#define POPC_LIB_ERROR_MSG_MAX 512
typedef struct popc_lib_error {
	char msg[POPC_LIB_ERROR_MSG_MAX];
} popc_lib_error;

/* ---- scenes: every parameter of a run (popc-scene(5)) ---- */

typedef struct popc_lib_scene popc_lib_scene;

/* A scene holding every default (the paper's scene). */
POPC_API int popc_lib_scene_create(popc_lib_scene **out, popc_lib_error *err);
/* Reads a scene file over s, as `popc run SCENE` does: a name without '/'
 * that is no file here is looked up in the data directories (the scene's
 * data path, below; by default the installed share/popc alone), so "paper"
 * is the installed paper scene. */
POPC_API int popc_lib_scene_load(popc_lib_scene *s, const char *path, popc_lib_error *err);
/* The data directories that popc_lib_scene_load and the key axis.map look a
 * bare name up in, as POPC_DATA_PATH gives them to popc run: DIR[:DIR...],
 * an empty entry standing for the installed share/popc; NULL or "": that
 * alone (the default). The library reads no environment: a program that
 * honours POPC_DATA_PATH passes getenv("POPC_DATA_PATH"). A name is looked
 * up when it is loaded or set: set the data path first. At most 1023
 * characters, else POPC_LIB_ERR_INVALID (s unchanged). (API 1.2) */
POPC_API int popc_lib_scene_set_data_path(popc_lib_scene *s, const char *data_path,
					  popc_lib_error *err);
/* One key, as `--set section.key=value`: key is "section.key". */
POPC_API int popc_lib_scene_set(popc_lib_scene *s, const char *key, const char *value,
				popc_lib_error *err);
/* The cross-key checks; the create functions below call it too. */
POPC_API int popc_lib_scene_validate(const popc_lib_scene *s, popc_lib_error *err);
/* The control period T = 1 / run.rate (s), and the ticks of a run (t = 0,
 * T, ..., run.duration: one more than duration / T). */
POPC_API double popc_lib_scene_period_s(const popc_lib_scene *s);
POPC_API long long popc_lib_scene_tick_count(const popc_lib_scene *s);
/* Frees s (NULL: nothing). */
POPC_API void popc_lib_scene_free(popc_lib_scene *s);

/* ---- one control tick, as the log has it ---- */

typedef struct popc_lib_tick {
	double t_s;          /* k T */
	double x_m;          /* measured position: count x encoder.resolution */
	long long count;     /* encoder count */
	double v_mps;        /* velocity the controller used */
	double f_e_N;        /* virtual environment force */
	double f_pc_N;       /* passivity controller force */
	double f_c_N;        /* the command: f_e + f_pc (clamped to a force limit) */
	double W_J;          /* passivity observer energy */
	double E_ref_J;      /* reference energy */
	unsigned flags;      /* POPC_LIB_FLAG_* */
} popc_lib_tick;

/* The bits of popc_lib_tick.flags (the log's flags column). */
enum {
	POPC_LIB_FLAG_ACTIVE = 1,    /* f_pc != 0 */
	POPC_LIB_FLAG_HOLD = 2,      /* f_pc held while no count moved */
	POPC_LIB_FLAG_IGNORE = 4,    /* one-count reversal: produced energy ignored */
	POPC_LIB_FLAG_CLAMP = 8,     /* f_pc clamped to controller.pc_bound */
	POPC_LIB_FLAG_GUARD = 16,    /* a non-finite PC force was replaced by 0 */
	POPC_LIB_FLAG_LIMIT = 32,    /* f_c clamped to the force limit */
	POPC_LIB_FLAG_PC_OFF = 64,   /* pc-off-reversals turned the PC off */
	POPC_LIB_FLAG_BOUND = 128,   /* an energy or damping bound cut f_pc */
};

/* ---- the controller: a port with a causality ---- */

/* Impedance: a position count in, a force out. Admittance (API 1.1): a
 * force count in, a velocity command out (docs/ADMITTANCE.md). */
typedef enum popc_lib_causality {
	POPC_LIB_CAUSALITY_IMPEDANCE = 0,
	POPC_LIB_CAUSALITY_ADMITTANCE = 1,
} popc_lib_causality;

typedef struct popc_lib_port popc_lib_port;

/* The virtual environment and PO/PC of scene s (controller.variant, every
 * variant; environment.*; encoder.resolution; run.rate), in impedance
 * causality. force_limit_N > 0 clamps |f_c| to it (POPC_LIB_FLAG_LIMIT), as
 * popc run does for a drive's limit; 0: none. Allocates; s may be freed
 * after. */
POPC_API int popc_lib_port_create_impedance(const popc_lib_scene *s, double force_limit_N,
					    popc_lib_port **out, popc_lib_error *err);
POPC_API popc_lib_causality popc_lib_port_causality(const popc_lib_port *p);
/* Tick k: the encoder count sampled at t = k T in, every field of *out
 * filled; out->f_c_N is the force to apply until the next tick (the device
 * receives -f_c: f_c > 0 pushes towards negative x). Finite whatever the
 * count. Real-time safe: no allocation, lock or system call. */
POPC_API void popc_lib_port_step(popc_lib_port *p, long long count, popc_lib_tick *out);
POPC_API void popc_lib_port_free(popc_lib_port *p);

/* What an admittance tick adds to popc_lib_tick (the admittance log's own
 * columns; API 1.1). */
typedef struct popc_lib_admittance_tick {
	long long f_count;   /* the force sensor's count n(k) */
	double f_meas_N;     /* f = n r (admittance.force_resolution) */
	double x_ve_m;       /* the VE's position after its step */
	double v_ve_mps;     /* the VE's velocity */
	double v_pc_mps;     /* the parallel PC's correction beta f */
	double v_c_mps;      /* the command: v_ve + v_pc, held over the period */
} popc_lib_admittance_tick;

/* The VE (admittance.virtual_mass, _damping; environment.*), admittance
 * observer and parallel PC (admittance.variant, every variant) of scene s,
 * which must have device.causality = admittance. Allocates; s may be freed
 * after. (API 1.1) */
POPC_API int popc_lib_port_create_admittance(const popc_lib_scene *s, popc_lib_port **out,
					     popc_lib_error *err);
/* Tick k of an admittance port: the position count and the force count
 * sampled at t = k T in (the VE starts at rest at tick 0's measured
 * position); *out as the admittance log's common columns (v_mps the
 * velocity command v_c; f_e_N the VE's environment
 * force; f_pc_N = f_c_N = E_ref_J = 0; W_J and flags the admittance
 * observer's) and *adm (may be NULL) its own. v_c is finite whatever the
 * counts. Real-time safe. On an impedance port, and popc_lib_port_step on an
 * admittance port: every field 0 (no motion, no force) and the port's state
 * unchanged. (API 1.1) */
POPC_API void popc_lib_port_step_admittance(popc_lib_port *p, long long count,
					    long long force_count, popc_lib_tick *out,
					    popc_lib_admittance_tick *adm);

/* ---- the observer alone: W and E_ref from recorded ticks ---- */

typedef struct popc_lib_observer popc_lib_observer;

/* The PO of scene s's variant (controller.variant, controller.ignore_mode,
 * run.rate), as popc-analyze energy recomputes it. */
POPC_API int popc_lib_observer_create(const popc_lib_scene *s, popc_lib_observer **out,
				      popc_lib_error *err);
/* One recorded tick in (its x_m, count, v_mps, f_e_N and f_c_N are read),
 * W(k) and E_ref(k) out (either pointer may be NULL). Real-time safe. */
POPC_API void popc_lib_observer_step(popc_lib_observer *o, const popc_lib_tick *in, double *W_J,
				     double *E_ref_J);
POPC_API void popc_lib_observer_free(popc_lib_observer *o);

/* ---- the simulated device: plant, operator, encoder (for simulation) ---- */

typedef struct popc_lib_sim popc_lib_sim;

typedef struct popc_lib_sample {
	long long count;     /* the encoder's count */
	double x_true_m;     /* the plant's true position */
	double E_port_J;     /* true energy into the port so far (the log's E_port) */
} popc_lib_sample;

/* The simulated axis of scene s (operator.*, device.*, encoder.*,
 * integrator.*), started; *first gets the sample of tick 0. */
POPC_API int popc_lib_sim_create(const popc_lib_scene *s, popc_lib_sim **out,
				 popc_lib_sample *first, popc_lib_error *err);
/* Applies f_c_N (the port's f_c) for one period and samples tick k + 1.
 * A non-finite f_c_N is refused (POPC_LIB_ERR_INVALID, the device left as
 * it was). Fails (POPC_LIB_ERR_NUMERIC, POPC_LIB_ERR_DIVERGED) when the integrator or
 * the closed loop goes unstable; err says which and when. No allocation. */
POPC_API int popc_lib_sim_exchange(popc_lib_sim *sim, double f_c_N, popc_lib_sample *next,
				   popc_lib_error *err);
POPC_API void popc_lib_sim_free(popc_lib_sim *sim);

/* popc_lib_sim_create with options (API 1.3): POPC_LIB_SIM_NO_PORT_ENERGY
 * leaves E_port unmade, E_port_J 0 in every sample, for a loop that does not
 * log it (the compensated sum is some 20 instructions of a tick, which
 * popc run -q does not make either); every other field the same bits. Other
 * bits: POPC_LIB_ERR_INVALID. */
enum {
	POPC_LIB_SIM_NO_PORT_ENERGY = 1,
};
POPC_API int popc_lib_sim_create_options(const popc_lib_scene *s, unsigned options,
					 popc_lib_sim **out, popc_lib_sample *first,
					 popc_lib_error *err);

/* Tick k of a simulated impedance loop in one call: the port's step on
 * smp->count (the device's sample of tick k), *out filled as
 * popc_lib_port_step fills it, then the device's exchange of out->f_c_N,
 * *smp becoming the sample of tick k + 1: the bits of the two calls, with
 * fewer checks and copies between them. The last tick of a run, whose
 * command no period follows, is popc_lib_port_step alone. Fails as
 * popc_lib_sim_exchange does (the port stepped, *smp unchanged), and with
 * POPC_LIB_ERR_INVALID, nothing stepped, when the port or the device is
 * admittance-type. No allocation. (API 1.3) */
POPC_API int popc_lib_sim_tick(popc_lib_port *p, popc_lib_sim *sim, popc_lib_sample *smp,
			       popc_lib_tick *out, popc_lib_error *err);

/* The simulated admittance-type device of scene s (operator.*, device.*,
 * admittance.servo*, the force sensor; device.causality = admittance),
 * started; *first gets tick 0's sample. Its exchange takes the velocity
 * command v_c (the admittance port's v_c_mps). The handle is freed by
 * popc_lib_sim_free; popc_lib_sim_exchange refuses it, as
 * popc_lib_sim_exchange_admittance refuses an impedance device
 * (POPC_LIB_ERR_INVALID). (API 1.1) */
typedef struct popc_lib_admittance_sample {
	long long count;       /* the position encoder's count */
	long long force_count; /* the force sensor's count */
	double x_true_m;       /* the device's true position */
	double x_cmd_m;        /* the position command the servo tracks from this tick */
} popc_lib_admittance_sample;

POPC_API int popc_lib_sim_create_admittance(const popc_lib_scene *s, popc_lib_sim **out,
					    popc_lib_admittance_sample *first, popc_lib_error *err);
/* Applies v_c_mps for one period and samples tick k + 1; a non-finite v_c is
 * refused (the device left as it was). No allocation. (API 1.1) */
POPC_API int popc_lib_sim_exchange_admittance(popc_lib_sim *sim, double v_c_mps,
					      popc_lib_admittance_sample *next, popc_lib_error *err);

/* The virtual environment's force at x_m, v_mps, and the encoder's count of
 * x_m (*ok = 0 where it has none: not finite, beyond 2^53 counts). */
POPC_API double popc_lib_environment_force(const popc_lib_scene *s, double x_m, double v_mps);
POPC_API long long popc_lib_encoder_count(const popc_lib_scene *s, double x_m, int *ok);

/* ---- a whole run, as `popc run SCENE --log LOG` ---- */

/* Runs scene s on its axis (axis.kind) and writes the log to log_path ("-":
 * standard output; NULL: none): the same file popc run writes. */
POPC_API int popc_lib_run(const popc_lib_scene *s, const char *log_path, popc_lib_error *err);

/* ---- logs: writing ---- */

/* Which optional columns a log has (the log's columns line): x_true and
 * E_port for a simulated axis, dt and rtt for a real one. */
enum {
	POPC_LIB_LOG_X_TRUE = 1,
	POPC_LIB_LOG_TIMING = 2,
};

typedef struct popc_lib_row {
	popc_lib_tick tick;
	double x_true_m, E_port_J; /* POPC_LIB_LOG_X_TRUE */
	double dt_s, rtt_s;        /* POPC_LIB_LOG_TIMING */
} popc_lib_row;

typedef struct popc_lib_log_writer popc_lib_log_writer;

/* Creates log_path ("-": standard output) and writes the header popc run
 * writes: provenance, source ("sim", "modbus" or "replay"), the scene. */
POPC_API int popc_lib_log_writer_open(popc_lib_log_writer **out, const char *log_path,
				      const popc_lib_scene *s, const char *source, unsigned columns,
				      popc_lib_error *err);
/* Buffered: no allocation after open; a write may block on the disk. A row
 * with a NaN or inf in a cell the log writes is refused (POPC_LIB_ERR_INVALID,
 * naming the column), the rows before it kept. */
POPC_API int popc_lib_log_write_row(popc_lib_log_writer *w, const popc_lib_row *row,
				    popc_lib_error *err);
/* Writes "# stop = STOP_REASON" (NULL: no line), flushes, closes and frees
 * w; returns the first error of the three. */
POPC_API int popc_lib_log_writer_close(popc_lib_log_writer *w, const char *stop_reason,
				       popc_lib_error *err);

/* ---- logs: reading (popc's own and recorded CSV logs) ---- */

typedef struct popc_lib_log_reader popc_lib_log_reader;

POPC_API int popc_lib_log_reader_open(popc_lib_log_reader **out, const char *log_path,
				      popc_lib_error *err);
POPC_API int popc_lib_log_reader_column_count(const popc_lib_log_reader *r);
POPC_API const char *popc_lib_log_reader_column_name(const popc_lib_log_reader *r, int i);
/* The header's "# key = value" lines, keys qualified ("run.rate"). */
POPC_API int popc_lib_log_reader_header_count(const popc_lib_log_reader *r);
POPC_API const char *popc_lib_log_reader_header_key(const popc_lib_log_reader *r, int i);
POPC_API const char *popc_lib_log_reader_header_value(const popc_lib_log_reader *r, int i);
/* The next row into values[0 .. column_count - 1], bit for bit the doubles
 * the writer formatted: 1, 0 at the end, or a negative status. */
POPC_API int popc_lib_log_reader_next(popc_lib_log_reader *r, double *values, popc_lib_error *err);
/* After the end: the log's "# stop = ..." reason ("" if none). */
POPC_API const char *popc_lib_log_reader_stop_reason(const popc_lib_log_reader *r);
POPC_API void popc_lib_log_reader_close(popc_lib_log_reader *r);

/* The scene a popc log was made with: the header's "# section.key = value"
 * lines applied over s (keys the header lacks keep s's values: start from
 * popc_lib_scene_create's defaults for the log's own scene), as
 * popc-analyze reads a log's scene. A key the header spells wrongly or out
 * of range: POPC_LIB_ERR_INVALID naming the file, its line and the key, s
 * unchanged; a recorded log without popc's header (no "# format", "# source"
 * lines) holds no scene: POPC_LIB_ERR_INVALID. (API 1.3) */
POPC_API int popc_lib_scene_from_log(popc_lib_scene *s, const popc_lib_log_reader *r,
				     popc_lib_error *err);

#ifdef __cplusplus
}
#endif

#endif
