/* Virtual environments (impedance causality: position in, force out).
 * f_e > 0 pushes the device back towards negative x (the device receives -f_c). */
#ifndef POPC_ENVIRONMENT_H
#define POPC_ENVIRONMENT_H

typedef enum popc_environment_kind {
	POPC_ENV_WALL,   /* unilateral: f_e = K_e (x - p) + B_e v for x >= p, else 0; f_e >= 0 */
	POPC_ENV_SPRING, /* bilateral: f_e = K_e (x - p) + B_e v */
} popc_environment_kind;

/* Names in scenes ("wall", "spring"), index = value, NULL-terminated. */
extern const char *const popc_environment_kind_names[];

typedef struct popc_environment {
	popc_environment_kind kind;
	double stiffness_Npm, damping_Nspm, position_m;
} popc_environment;

/* Wall: f_e = max(0, K_e (x - p) + B_e v) for x >= p, else 0 (unilateral, never pulls).
 * Spring: f_e = K_e (x - p) + B_e v. Inline: it runs every tick, in the
 * controller and in the run's metrics. */
static inline double popc_environment_force(const popc_environment *e, double x_m, double v_mps)
{
	double pen = x_m - e->position_m;
	if (e->kind == POPC_ENV_WALL) {
		if (!(pen >= 0.0))
			return 0.0;
		double f = e->stiffness_Npm * pen;
		if (e->damping_Nspm != 0.0)
			f += e->damping_Nspm * v_mps;
		return f > 0.0 ? f : 0.0; /* a wall pushes, never pulls */
	}
	double f = e->stiffness_Npm * pen;
	if (e->damping_Nspm != 0.0)
		f += e->damping_Nspm * v_mps;
	return f;
}

/* Whether x is in contact (wall: x >= p; spring: always). */
static inline int popc_environment_in_contact(const popc_environment *e, double x_m)
{
	return e->kind == POPC_ENV_SPRING || x_m >= e->position_m;
}

#endif
