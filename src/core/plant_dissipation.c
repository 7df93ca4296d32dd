/* The damping's dissipation over a step as a quadratic form (plant_dissipation.h). */
#include "popc/core/plant_dissipation.h"

#include <math.h>
#include <string.h>

/* out = x^T (n x n, row major) */
static void transpose(int n, const double *x, double *out)
{
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n; j++)
			out[i * n + j] = x[j * n + i];
}

int popc_plant_dissipation_init(popc_plant_dissipation *d, const popc_plant_config *cfg,
				double h_s)
{
	memset(d, 0, sizeof *d);
	double a[36];
	int n = popc_plant_augmented(cfg, a);
	d->n = n;
	if (!(cfg->damping_Nspm > 0.0))
		return 0; /* no damping, no dissipation: Q = 0 exactly */
	const double norm = popc_norm1(n, a);
	/* h / 2^s with ||A||_1 h / 2^s <= 1/2 */
	int s = 0;
	double h = h_s;
	while (norm * h > 0.5 && s < 200) {
		h *= 0.5;
		s++;
	}
	/* Van Loan's block matrix [[-A^T, e_v e_v^T], [0, A]] h, 2n x 2n */
	const int n2 = 2 * n;
	double c[144] = {0}, e[144];
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n; j++) {
			c[i * n2 + j] = -a[j * n + i] * h;
			c[(n + i) * n2 + n + j] = a[i * n + j] * h;
		}
	c[1 * n2 + n + 1] = h; /* e_v e_v^T h: v is component 1 */
	if (popc_expm(n2, c, e) != 0)
		return POPC_ERR_NUMERIC;
	double phi[36], phi_t[36], g[36], integral[36], tmp[36];
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n; j++) {
			phi[i * n + j] = e[(n + i) * n2 + n + j];
			g[i * n + j] = e[i * n2 + n + j];
		}
	transpose(n, phi, phi_t);
	popc_matmul(n, phi_t, g, integral);
	for (int k = 0; k < s; k++) {
		/* I(2h) = I(h) + Phi^T I(h) Phi, Phi(2h) = Phi^2 */
		popc_matmul(n, integral, phi, tmp);
		popc_matmul(n, phi_t, tmp, tmp);
		for (int i = 0; i < n * n; i++)
			integral[i] += tmp[i];
		popc_matmul(n, phi, phi, phi);
		transpose(n, phi, phi_t);
	}
	const double b = cfg->damping_Nspm;
	for (int i = 0; i < n; i++)
		for (int j = i; j < n; j++) {
			/* the integral is symmetric: its two roundings averaged */
			double q = b * (0.5 * (integral[i * n + j] + integral[j * n + i]));
			if (!isfinite(q))
				return POPC_ERR_NUMERIC;
			if (j == i)
				d->d[i] = q;
			else
				d->u[i][j] = 2.0 * q;
		}
	return 0;
}
