/* The energy the plant's damping dissipates over a step, exactly (to
 * rounding) for the exact method's input class:
 *
 *     D = integral over [0, h) of B v(tau)^2 dtau = z^T Q z,
 *     z = [y, v, u0, u1, uc, us]   (state and input of the step, plant.h)
 *
 * with B = operator.damping + device.damping, the damping of the plant
 * M x'' = u - B x' - K x. v(tau) = e_v e^(A tau) z for the augmented matrix A
 * of the exact step, so Q = B times the integral of e^(A^T tau) e_v e_v^T
 * e^(A tau) over [0, h), computed once per step length by Van Loan's block
 * exponential (C. Van Loan, "Computing integrals involving the matrix
 * exponential", IEEE Trans. Automatic Control 23(3), 1978, Theorem 1):
 *
 *     expm([[-A^T, e_v e_v^T], [0, A]] h) = [[F, G], [0, e^(A h)]],
 *     integral = e^(A h)^T G,
 *
 * on h / 2^s with ||A||_1 h / 2^s <= 1/2 (the -A^T block grows as e^(+B/M h):
 * kept near 1), then doubled s times, I(2h) = I(h) + Phi(h)^T I(h) Phi(h).
 *
 * With the true port energy E_port this gives the energy balance of the
 * operator's port: E_port + D = (work of the operator's input u) - (change of
 * the plant's kinetic and spring energy), the energy the virtual environment
 * and the plant's damping together took in. Colgate and Schenkel's passivity
 * condition (b > K T / 2 + |B|) is a statement about this sum (docs/MAPS.md). */
#ifndef POPC_PLANT_DISSIPATION_H
#define POPC_PLANT_DISSIPATION_H

#include "popc/core/plant.h"

typedef struct popc_plant_dissipation {
	int n;              /* 4 (affine input) or 6 (with the sine input) */
	double d[6];        /* Q's diagonal, J per (unit of z)^2 */
	double u[6][6];     /* 2 Q[i][j] for j > i (0 elsewhere): the form's cross terms */
} popc_plant_dissipation;

/* Computes Q for steps of h_s of the plant cfg (any method: the form is that
 * of the exact trajectory; friction is not part of it). Returns 0, or
 * POPC_ERR_NUMERIC when the block exponential is not finite (a plant too
 * stiff for double precision at this h; the form must then not be used). */
int popc_plant_dissipation_init(popc_plant_dissipation *d, const popc_plant_config *cfg,
				double h_s);

/* D of one exact step from state st with input u (>= 0: a quadratic form of
 * a positive semidefinite matrix, its rounding clamped at 0). Horner-like by
 * rows, z_i (q_ii z_i + sum over j > i of 2 q_ij z_j), written out for the
 * affine input (n = 4, every tick of a ramp) so that it costs ten products
 * beside the tick's dependency chain, not a loop. */
static inline double popc_plant_dissipated_J(const popc_plant_dissipation *d,
					      const popc_plant_state *st, const popc_plant_input *u)
{
	const double y = st->x_m, v = st->v_mps, a = u->u0_N, b = u->u1_Nps;
	double r0 = d->d[0] * y + ((d->u[0][1] * v + d->u[0][2] * a) + d->u[0][3] * b);
	double r1 = d->d[1] * v + (d->u[1][2] * a + d->u[1][3] * b);
	double r2 = d->d[2] * a + d->u[2][3] * b;
	double r3 = d->d[3] * b;
	double e = (y * r0 + v * r1) + (a * r2 + b * r3);
	if (d->n == 6) {
		const double c = u->uc_N, s = u->us_N;
		double r4 = d->d[4] * c + d->u[4][5] * s, r5 = d->d[5] * s;
		double cross = (y * (d->u[0][4] * c + d->u[0][5] * s) + v * (d->u[1][4] * c + d->u[1][5] * s)) +
			       (a * (d->u[2][4] * c + d->u[2][5] * s) + b * (d->u[3][4] * c + d->u[3][5] * s));
		e += cross + (c * r4 + s * r5);
	}
	return e > 0.0 ? e : 0.0;
}

#endif
