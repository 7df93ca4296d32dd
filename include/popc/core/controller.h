/* The passivity observer (PO) and passivity controller (PC) variants of
 * the paper (seed eq. 3, Table I; README, "Controller variants"), series PC
 * in impedance causality.
 *
 * A control tick k takes the measured position (count and metres) and gives
 * the command f_c(k) = f_e(k) + f_pc(k). The observer half (W, E_ref) is a
 * separate step so that popc-analyze can recompute W and E_ref from a log's
 * columns with exactly the code and floating-point operations that ran online. */
#ifndef POPC_CONTROLLER_H
#define POPC_CONTROLLER_H

#include "popc/core/environment.h"
#include "popc/core/velocity.h"
#include "popc/util/error.h"

typedef enum popc_variant {
	POPC_VARIANT_NONE,
	POPC_VARIANT_PO_PC,
	POPC_VARIANT_REF_ENERGY,
	POPC_VARIANT_FILTERED_VELOCITY,
	POPC_VARIANT_IGNORE,
	POPC_VARIANT_HOLD,
	POPC_VARIANT_IMPROVED,
	POPC_VARIANT_PC_OFF_REVERSALS, /* ref-energy, PC off after repeated reversals (seed Sec. VI) */
	POPC_VARIANT_ENERGY_BOUNDING,  /* Kim and Ryu 2004: ZOH energy <= physical damping's */
	POPC_VARIANT_WINDOWED_PO,      /* PO over the last N samples, velocity floor, damping bound */
	POPC_VARIANT_COUNT
} popc_variant;

/* The variants' names in scenes, logs and on the command line (README,
 * "Controller variants"; stable), index = value, NULL-terminated. */
extern const char *const popc_variant_names[];
const char *popc_variant_name(popc_variant v);
int popc_variant_from_name(const char *name, popc_variant *out);

/* Table I's "Prev_fc = f_c(k)" (docs/TABLE1.md): undo (the scene default)
 * stores f_c(k-1), so that a one-count reversal removes exactly the previous
 * step's PO increment and W returns to E(k-1) as in the paper's Fig. 7
 * derivation; literal reads it as printed, the VE force f_e(k) stored before
 * the PC is added. */
typedef enum popc_ignore_mode { POPC_IGNORE_LITERAL, POPC_IGNORE_UNDO } popc_ignore_mode;
extern const char *const popc_ignore_mode_names[];

/* Controller events, OR-ed into the log's `flags` column. */
enum popc_flag {
	POPC_FLAG_ACTIVE = 1,    /* f_pc != 0 */
	POPC_FLAG_HOLD = 2,      /* f_pc held while no count moved (Table I, first branch) */
	POPC_FLAG_IGNORE = 4,    /* one-count reversal: produced energy ignored (Table I) */
	POPC_FLAG_CLAMP = 8,     /* f_pc clamped to +-pc_bound */
	POPC_FLAG_GUARD = 16,    /* a non-finite PC force was replaced by 0 */
	POPC_FLAG_LIMIT = 32,    /* f_c clamped to the axis' force limit: f_c != f_e + f_pc */
	POPC_FLAG_PC_OFF = 64,   /* pc-off-reversals: PC turned off by the reversal rule */
	POPC_FLAG_BOUND = 128,   /* energy-bounding / windowed-po: the energy or damping bound cut f_pc */
};

/* The scene's limits on the reversal count (pc-off-reversals) and the PO
 * window (windowed-po): the ranges of controller.reversal_count and
 * controller.po_window (popc-scene(5)). The controller itself takes any
 * length: popc_controller_create sizes its rings from its configuration. */
#define POPC_REVERSAL_MAX_COUNT 64
#define POPC_PO_MAX_WINDOW 4096

/* One control tick as logged. */
typedef struct popc_tick {
	double t_s;
	double x_m;           /* measured position */
	long long count;      /* encoder counts */
	double v_mps;         /* velocity the controller used */
	double f_e_N, f_pc_N, f_c_N;
	double W_J, E_ref_J;
	unsigned flags;
} popc_tick;

/* PO and reference energy state (seed eq. 3, Table I; README, "Controller variants"). */
typedef struct popc_observer {
	popc_variant variant;
	popc_ignore_mode ignore_mode;
	int started;
	double x_prev_m;
	long long count_prev;
	double f_e_prev_N, f_c_prev_N;
	/* W(k) and E_ref(k), rounded to double: what the controller and the log use. */
	double W_J, E_ref_J;
	/* Compensated (Neumaier / Kahan-Babuska) sums behind W_J and E_ref_J: the
	 * exact running sum is *_sum_J + *_comp_J to within a few units in the
	 * last place over any number of ticks (tests/perf/test_observer_precision.c),
	 * where a plain sum loses about sqrt(ticks) ulps. W_J = W_sum_J + W_comp_J. */
	double W_sum_J, W_comp_J, E_ref_sum_J, E_ref_comp_J;
	/* Table I memory: the last step on which a count moved */
	long long prev_dcount;
	double prev_dx_m, prev_fc_N;
} popc_observer;

/* What the observer step found, for the PC that follows. */
typedef struct popc_observation {
	double dx_m;          /* displacement the PO used: x(k) - x(k-1), or v T (filtered) */
	long long dcount;
	unsigned flags;       /* POPC_FLAG_IGNORE */
} popc_observation;

void popc_observer_init(popc_observer *o, popc_variant variant, popc_ignore_mode mode);

/* Observer update at tick k from the measured position, the controller's
 * velocity (used by filtered-velocity only), the period and the VE force f_e(k).
 * Updates W(k) and E_ref(k). */
void popc_observer_update(popc_observer *o, double x_m, long long count, double v_mps,
			  double period_s, double f_e_N, popc_observation *obs);

/* Stores the command f_c(k) that was sent (needed by W(k+1)) and Table I's
 * Prev_fc when a count moved. */
void popc_observer_commit(popc_observer *o, const popc_observation *obs, double f_e_N,
			  double f_c_N);

/* Whether a and b step by the same rule: from the same state and inputs
 * (and, for filtered-velocity, the same period) update and commit give both
 * the same bits. The variant decides only the branch (filtered velocity,
 * Table I's reversal, or seed eq. 3), the Table I mode only where Table I is
 * used. */
int popc_observer_same_rule(const popc_observer *a, const popc_observer *b);

typedef struct popc_controller_config {
	popc_variant variant;
	double pc_bound_N;
	double force_limit_N;  /* the axis' command limit |f_c| <= limit; 0: none */
	popc_ignore_mode ignore_mode;
	double resolution_m;
	double period_s;
	int foaw_window;
	double foaw_noise_m;
	/* pc-off-reversals: the PC is off at tick k when at least reversal_count
	 * count-direction reversals fall in the ticks (k - reversal_window, k] */
	int reversal_count, reversal_window_ticks;
	/* energy-bounding: the physical damping b (operator + device) that
	 * dissipates at least b dx^2 / T per period */
	double damping_Nspm;
	/* energy-bounding: K_b = (1 - eb_margin) 2 b / T (docs/ANALYSIS.md) */
	double eb_margin;
	/* windowed-po: window length, velocity floor, damping bound */
	int po_window_ticks;
	double po_velocity_floor_mps, po_damping_max_Nspm;
	popc_environment env;
} popc_controller_config;

typedef struct popc_controller {
	popc_controller_config cfg;
	popc_observer obs;
	popc_foaw foaw;
	double f_pc_prev_N;
	int started;
	long long tick;              /* ticks stepped before this one */
	/* pc-off-reversals: ticks of the last reversal_count reversals (a ring
	 * of reversal_count entries; none for the other variants) */
	long long *reversal_tick;
	int n_reversals, reversal_next, last_dir;
	/* windowed-po: per-tick increments of W - E_ref (a ring of
	 * po_window_ticks entries; none for the other variants) and their
	 * compensated sum over the window */
	double *po_inc_J;
	int po_n, po_next;
	double po_sum_J, po_comp_J;
} popc_controller;

/* Makes a controller for cfg in one allocation: the struct and the rings its
 * variant uses, each of the length cfg gives (reversal_count and
 * po_window_ticks, at least 1), so that a tick never allocates. 0, or
 * POPC_ERR_NOMEM with a message naming the bytes asked for (*out NULL). */
int popc_controller_create(const popc_controller_config *cfg, popc_controller **out,
			   popc_error *err);

/* Frees what popc_controller_create made; takes NULL. */
void popc_controller_free(popc_controller *c);

/* One control tick: fills every field of *out but t_s. f_c is always finite
 * when x_m is finite. */
void popc_controller_step(popc_controller *c, long long count, double x_m, popc_tick *out);

#endif
