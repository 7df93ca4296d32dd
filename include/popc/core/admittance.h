/* Admittance causality (port.h; docs/ADMITTANCE.md): the device measures the
 * force, the virtual environment (VE) returns a motion, and the passivity
 * observer and the parallel passivity controller of Hannaford and Ryu 2002
 * (Sec. III-C, eqs. 15-17) act on the velocity command.
 *
 * A control tick k reads the force count n(k) of the sensor, f(k) = n(k) r
 * (r: the resolution, N per count), and
 *
 *   1. steps the VE, m_v a + b_v v + f_env(x_v, v) = f(k), by semi-implicit
 *      Euler (v_VE(k) = v_v(k-1) + T a, x_v(k) = x_v(k-1) + T v_VE(k));
 *      f_env is the impedance environment (environment.h: the wall
 *      K_e (x_v - p)^+ + B_e v, or the spring) evaluated on the VE's own
 *      position; with m_v = 0 the VE is the damper v_VE = (f - f_env) / b_v;
 *   2. observes W-(k) = W(k-1) + f(k) v_VE(k) T (the energy into the VE if
 *      the VE's own velocity were sent);
 *   3. corrects, while W-(k) < 0 and f(k) != 0,
 *        v_pc(k) = beta f(k),  beta = -W-(k) / (T f(k)^2),
 *      bounded to |v_pc| <= the velocity bound;
 *   4. commands v_c(k) = v_VE(k) + v_pc(k), held over [kT, (k+1)T), and
 *      W(k) = W-(k) + f(k) v_pc(k) T = T sum_{j <= k} f(j) v_c(j).
 *
 * Sign convention: f > 0 pushes the device towards +x, v > 0 moves it there;
 * f v > 0 is power into the VE (absorbed), so a passive port keeps W >= 0. */
#ifndef POPC_ADMITTANCE_H
#define POPC_ADMITTANCE_H

#include <stdint.h>

#include "popc/core/environment.h"

/* The parallel PC variants, the duals of the seed's Table I. */
typedef enum popc_admittance_variant {
	POPC_ADMITTANCE_NONE,     /* the VE alone, W observed */
	POPC_ADMITTANCE_PARALLEL, /* the plain parallel PC (Hannaford and Ryu 2002, eq. 17) */
	POPC_ADMITTANCE_IGNORE,   /* one-count force reversals: their energy T dn r v_VE ignored */
	POPC_ADMITTANCE_HOLD,     /* v_pc held while the force count does not change */
	POPC_ADMITTANCE_IMPROVED, /* ignore and hold */
	POPC_ADMITTANCE_VARIANT_COUNT
} popc_admittance_variant;

/* Names in scenes and logs, index = value, NULL-terminated. */
extern const char *const popc_admittance_variant_names[];
const char *popc_admittance_variant_name(popc_admittance_variant v);

/* Flags of an admittance tick: the impedance controller's bits where the
 * event is the dual one (controller.h, enum popc_flag). */
enum popc_admittance_flag {
	POPC_ADM_FLAG_ACTIVE = 1, /* v_pc != 0 */
	POPC_ADM_FLAG_HOLD = 2,   /* v_pc held: the force count did not change */
	POPC_ADM_FLAG_IGNORE = 4, /* one-count force reversal: its energy ignored */
	POPC_ADM_FLAG_CLAMP = 8,  /* v_pc clamped to +-the velocity bound */
	POPC_ADM_FLAG_GUARD = 16, /* a non-finite velocity was replaced by 0 */
};

/* The force sensor: f = r n, n the nearest whole count (ties to even) of the
 * true force plus, when noise_N > 0, a Gaussian noise of that standard
 * deviation from a generator seeded by seed (splitmix64, Box-Muller): the
 * same seed, the same readings. */
typedef struct popc_force_sensor {
	double resolution_N, noise_N;
	uint64_t state;
	double spare;        /* Box-Muller's second normal deviate */
	int has_spare;
} popc_force_sensor;

void popc_force_sensor_init(popc_force_sensor *s, double resolution_N, double noise_N,
			    uint64_t seed);
/* The count read for the true force f_N (finite); saturates at +-2^52. */
long long popc_force_sensor_read(popc_force_sensor *s, double f_N);

/* The observer, shared with popc-analyze energy --check (the same code and
 * floating-point operations offline as online). */
typedef struct popc_admittance_observer {
	popc_admittance_variant variant;
	int started;
	long long n_prev, dn_prev; /* the last count, and the last change of it that was not 0 */
	double f_prev_N;
	double W_J, W_sum_J, W_comp_J;
} popc_admittance_observer;

typedef struct popc_admittance_observation {
	double W_minus_J; /* W-(k) */
	long long dn;     /* n(k) - n(k-1) (0 at tick 0) */
	unsigned flags;   /* POPC_ADM_FLAG_IGNORE */
} popc_admittance_observation;

void popc_admittance_observer_init(popc_admittance_observer *o, popc_admittance_variant v);
/* Step 2 from the count n, the force f = n r and the VE's velocity. */
void popc_admittance_observer_update(popc_admittance_observer *o, long long n, double f_N,
				     double v_ve_mps, double period_s,
				     popc_admittance_observation *ob);
/* Step 4: W(k) = W-(k) + f(k) v_pc(k) T. */
void popc_admittance_observer_commit(popc_admittance_observer *o, double f_N, double v_pc_mps,
				     double period_s);

typedef struct popc_admittance_config {
	popc_admittance_variant variant;
	double period_s;
	double force_resolution_N;
	double virtual_mass_kg, virtual_damping_Nspm;
	double pc_velocity_bound_mps;
	popc_environment env;     /* the VE's wall or spring, on the VE's position */
} popc_admittance_config;

/* One admittance tick as logged (the log's admittance columns). */
typedef struct popc_admittance_tick {
	long long n;              /* force count */
	double f_N;               /* f = n r */
	double x_ve_m, v_ve_mps;  /* the VE's position and velocity after its step */
	double f_env_N;           /* the VE's environment force at x_ve(k-1) */
	double v_pc_mps, v_c_mps; /* the PC's correction and the velocity command */
	double W_J;               /* W(k) */
	unsigned flags;
} popc_admittance_tick;

typedef struct popc_admittance_controller {
	popc_admittance_config cfg;
	popc_admittance_observer obs;
	double x_v_m, v_v_mps;    /* the VE's state */
	double v_pc_prev_mps;
} popc_admittance_controller;

/* The VE starts at rest at x0_m (the device's measured position). */
void popc_admittance_init(popc_admittance_controller *c, const popc_admittance_config *cfg,
			  double x0_m);

/* Steps 1-4 for the force count n; v_c is always finite. */
void popc_admittance_step(popc_admittance_controller *c, long long n, popc_admittance_tick *out);

/* The chatter detector's thresholds for an admittance run (docs/ANALYSIS.md,
 * "Admittance logs"), from the quantization. v_1, the velocity of one force
 * count r: the PC output that dissipates, at one count of force and within
 * one period T, the energy r^2 / K a one-count change stores in the VE's
 * spring K (docs/ADMITTANCE.md, "The duals of Table I"):
 *   v_1 = (r^2 / K) / (T r) = r / (K T);
 * a VE without a spring (K = 0): its own response to one count in one
 * period, r T / m_v, or r / b_v for a bare damper. The detector's PC scale
 * (its pc_bound) is POPC_ADMITTANCE_CHATTER_COUNTS v_1, so that its default
 * share, 5 %, is one count's velocity. Returns 0 for a configuration that
 * gives no finite positive v_1. */
#define POPC_ADMITTANCE_CHATTER_COUNTS 20.0
double popc_admittance_count_velocity_mps(double resolution_N, double stiffness_Npm,
					  double virtual_mass_kg, double virtual_damping_Nspm,
					  double period_s);

#endif
