/* The simulated plant (README, "The plant"): the operator's hand and the device
 * as one rigid body,
 *
 *     M x'' = u(t) - B x' - K x,   M = M_HO + M_HI, B = B_HO + B_HI, K = K_HO + K_HI,
 *
 * driven over one step of length h by the generalized input force
 *
 *     u(t_k + tau) = u0 + u1 tau + us sin(w tau) + uc cos(w tau),  tau in [0, h),
 *
 * which holds the operator's pull K_HO x_d + B_HO x_d' (+ an exogenous force)
 * minus the zero-order-held command f_c(k). A piecewise-linear intent gives
 * u1 (first-order hold of x_d); a sine intent gives us, uc.
 *
 * The exact method steps with Phi = expm(A h) and the input columns of the
 * augmented matrix exponential (exact to rounding for this input class); the
 * fixed-step integrators use `substeps` steps per control period. */
#ifndef POPC_PLANT_H
#define POPC_PLANT_H

#include "popc/util/error.h"

typedef enum popc_integrator {
	POPC_INTEGRATOR_EXACT,       /* ZOH/FOH exact discretization, expm */
	POPC_INTEGRATOR_TRAPEZOID,   /* the paper's C program */
	POPC_INTEGRATOR_RK4,
	POPC_INTEGRATOR_SEMI_IMPLICIT_EULER,
	POPC_INTEGRATOR_EULER,
	POPC_INTEGRATOR_COUNT
} popc_integrator;

/* The names used in scenes, logs and on the command line, index = value,
 * NULL-terminated. */
extern const char *const popc_integrator_names[];
const char *popc_integrator_name(popc_integrator m);
int popc_integrator_from_name(const char *name, popc_integrator *out);

typedef struct popc_plant_state {
	double x_m;
	double v_mps;
} popc_plant_state;

typedef struct popc_plant_input {
	double u0_N, u1_Nps, us_N, uc_N;
} popc_plant_input;

typedef struct popc_plant_config {
	double mass_kg, damping_Nspm, stiffness_Npm;
	double omega_radps;        /* w of the sine input; 0 when the scene has none */
	popc_integrator method;
	int substeps;              /* >= 1; ignored by the exact method */
	double period_s;           /* control period T */
	/* Device friction (plant_friction.c), modelled only when one is > 0:
	 * Coulomb -coulomb_N sign(v) while sliding; at v = 0 the body sticks
	 * while |u(t) - K x| <= max(stiction_N, coulomb_N). Both 0: the linear
	 * plant above, bit for bit. */
	double coulomb_N, stiction_N;
} popc_plant_config;

/* Precomputed step of length h: x+ = Phi x + Gam u (exact) or the integrator's
 * own constants. Private fields; treat as opaque. */
typedef struct popc_plant_step_coeffs {
	double h_s;
	double phi[2][2];
	double gam[2][4];          /* columns for u0, u1, uc, us */
	double trap[2][2];         /* trapezoid: (I - hA/2)^-1 (I + hA/2), per substep */
	double trap_in[2];         /* trapezoid: (I - hA/2)^-1 b h/2 */
} popc_plant_step_coeffs;

typedef struct popc_plant {
	popc_plant_config cfg;
	popc_plant_step_coeffs full;   /* for h = T */
	int friction;                  /* cfg declares friction: steps go through plant_friction.c */
	int friction_subs;             /* exact: sub-intervals of T searched for v = 0 (>= 1) */
	popc_plant_step_coeffs sub;    /* exact with friction: the step of T / friction_subs */
} popc_plant;

/* One exact step with precomputed coefficients: x+ = Phi x + Gam u. Inline
 * because it is the whole plant cost of a long run (a dozen flops). The
 * operations and their order are those of popc_plant_step for the exact method,
 * so both give the same bits. */
static inline void popc_plant_step_exact(const popc_plant_step_coeffs *c, popc_plant_state *st,
					 const popc_plant_input *u)
{
	/* The input terms first, as two independent pairs, then the state terms:
	 * the next state waits for two products and two additions once x and v
	 * are known (not five additions), which is what bounds a chain of steps. */
	double in_x = (c->gam[0][0] * u->u0_N + c->gam[0][1] * u->u1_Nps) +
		      (c->gam[0][2] * u->uc_N + c->gam[0][3] * u->us_N);
	double in_v = (c->gam[1][0] * u->u0_N + c->gam[1][1] * u->u1_Nps) +
		      (c->gam[1][2] * u->uc_N + c->gam[1][3] * u->us_N);
	double x = st->x_m, v = st->v_mps;
	st->x_m = (c->phi[0][0] * x + c->phi[0][1] * v) + in_x;
	st->v_mps = (c->phi[1][0] * x + c->phi[1][1] * v) + in_v;
}

/* The largest rotation per control period, w_d T e^(-B T / (2 M)), that the
 * exact step accepts for an underdamped plant: 2^22 rad, where its error of
 * about 16 eps per radian (eps = 2^-52) reaches 2^-26, half the digits of
 * double precision (plant.c, underdamped_turn). */
#define POPC_PLANT_TURN_MAX_RAD 4194304.0

/* Validates the configuration (M > 0, B >= 0, K >= 0, finite, substeps >= 1;
 * K/M, B/M, 1/M and (K/M) T^2 finite, so that no step overflows before it
 * starts; for the exact method an underdamped plant turning at most
 * POPC_PLANT_TURN_MAX_RAD per period) and precomputes the full-period step.
 * An overdamped plant whose fast mode dies within the period (M/B far below
 * T) steps by a closed form (plant.c), where scaling and squaring lost the
 * slow mode. POPC_ERR_INVALID names the scene keys behind a bad value;
 * POPC_ERR_NUMERIC when the step matrices come out non-finite (a plant too
 * stiff for double precision). */
int popc_plant_init(popc_plant *p, const popc_plant_config *cfg, popc_error *err);

/* Advances the state by one control period T. With friction (p->friction)
 * the exact method splits the period where the velocity reaches zero and
 * holds a stuck body (plant_friction.c); the fixed-step ones apply the same
 * law per substep. */
void popc_plant_step(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u);

/* Advances the state by h in (0, T] (a period split at a profile breakpoint);
 * the exact method computes its matrices for h (a few microseconds). Returns
 * 0, or POPC_ERR_NUMERIC (state untouched) when those matrices are not finite. */
int popc_plant_step_h(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
		      double h_s);

/* Precomputes the step coefficients for h (used by popc_plant_step_h).
 * Returns 0, or POPC_ERR_NUMERIC when the matrix exponential fails or a
 * coefficient is not finite (the coefficients must then not be used). */
int popc_plant_coeffs(const popc_plant_config *cfg, double h_s, popc_plant_step_coeffs *c);

/* The step of h_s in (0, T] of a plant with friction (plant_friction.c);
 * popc_plant_step and popc_plant_step_h call it when p->friction. Returns 0 or
 * POPC_ERR_NUMERIC (state untouched) when a segment's matrices are not
 * finite. */
int popc_plant_friction_step(const popc_plant *p, popc_plant_state *st, const popc_plant_input *u,
			     double h_s);

/* The threshold of static friction: max(stiction_N, coulomb_N). */
double popc_plant_stick_N(const popc_plant_config *cfg);

/* The exact step's augmented matrix A (row major, n x n in a[0 .. n*n)),
 * unscaled: z = [x, v, y1, y2, p, q], z' = A z, with y1 = u0 + u1 tau the
 * affine input and p = uc cos(w tau) + us sin(w tau) the sine's (plant.c).
 * Returns n: 6 with the sine input, else 4. */
int popc_plant_augmented(const popc_plant_config *cfg, double a[36]);

/* Dense matrix exponential of an n x n matrix (n <= 12), row major, by scaling
 * and squaring with a [6/6] Pade approximant (Higham 2005, table 2.3: backward
 * error below 2^-53 for ||A|| / 2^s <= 0.54). A matrix that needs squarings
 * (||A||_1 > 0.54) is balanced first by a diagonal similarity of powers of two
 * (exact; Parlett-Reinsch), so that a stiff plant's mixed units do not
 * multiply the squarings' rounding (src/core/expm.c). Returns 0, POPC_ERR_INVALID
 * for n out of range, or POPC_ERR_NUMERIC when A or the result is not finite. */
int popc_expm(int n, const double *a, double *out);

/* The dense helpers of expm.c, for n x n row-major matrices (n <= 12):
 * out = a b (out may alias a or b), and the 1-norm (largest column sum). */
void popc_matmul(int n, const double *a, const double *b, double *out);
double popc_norm1(int n, const double *a);

#endif
