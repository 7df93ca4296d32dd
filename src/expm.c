/* Matrix exponential for the small dense matrices of the exact plant step. */
#include <math.h>
#include <string.h>

#include "popc/plant.h"

#define NMAX 8

static void matmul(int n, const double *a, const double *b, double *out)
{
	double tmp[NMAX * NMAX];
	for (int i = 0; i < n; i++)
		for (int j = 0; j < n; j++) {
			double acc = 0.0;
			for (int k = 0; k < n; k++)
				acc += a[i * n + k] * b[k * n + j];
			tmp[i * n + j] = acc;
		}
	memcpy(out, tmp, sizeof(double) * (size_t)(n * n));
}

/* Solves D X = N for X (n x n) by Gaussian elimination with partial pivoting.
 * Returns -1 if D is singular (cannot happen for a Pade denominator within
 * the scaling bound, but checked). */
static int solve(int n, double *d, double *x)
{
	for (int c = 0; c < n; c++) {
		int piv = c;
		for (int r = c + 1; r < n; r++)
			if (fabs(d[r * n + c]) > fabs(d[piv * n + c]))
				piv = r;
		if (d[piv * n + c] == 0.0)
			return -1;
		if (piv != c)
			for (int j = 0; j < n; j++) {
				double t = d[c * n + j];
				d[c * n + j] = d[piv * n + j];
				d[piv * n + j] = t;
				t = x[c * n + j];
				x[c * n + j] = x[piv * n + j];
				x[piv * n + j] = t;
			}
		for (int r = c + 1; r < n; r++) {
			double f = d[r * n + c] / d[c * n + c];
			if (f == 0.0)
				continue;
			for (int j = c; j < n; j++)
				d[r * n + j] -= f * d[c * n + j];
			for (int j = 0; j < n; j++)
				x[r * n + j] -= f * x[c * n + j];
		}
	}
	for (int c = n - 1; c >= 0; c--)
		for (int j = 0; j < n; j++) {
			double acc = x[c * n + j];
			for (int k = c + 1; k < n; k++)
				acc -= d[c * n + k] * x[k * n + j];
			x[c * n + j] = acc / d[c * n + c];
		}
	return 0;
}

int popc_expm(int n, const double *a, double *out)
{
	if (n < 1 || n > NMAX)
		return POPC_ERR_INVALID;
	/* Pade [6/6] coefficients c_j = (2q-j)! q! / ((2q)! j! (q-j)!), q = 6. */
	static const double c[7] = {1.0,          1.0 / 2.0,     5.0 / 44.0,      1.0 / 66.0,
				    1.0 / 792.0,  1.0 / 15840.0, 1.0 / 665280.0};
	/* theta_6 of Higham (2005), Table 2.3: the [6/6] approximant has backward
	 * error below the unit roundoff for ||A||_1 <= 0.54. */
	const double theta6 = 0.54;
	double norm = 0.0;
	for (int j = 0; j < n; j++) {
		double col = 0.0;
		for (int i = 0; i < n; i++)
			col += fabs(a[i * n + j]);
		if (col > norm)
			norm = col;
	}
	if (!isfinite(norm))
		return POPC_ERR_NUMERIC;
	int s = 0;
	if (norm > theta6)
		s = (int)ceil(log2(norm / theta6));
	double scale = ldexp(1.0, -s);
	double x[NMAX * NMAX], p[NMAX * NMAX], num[NMAX * NMAX], den[NMAX * NMAX];
	int nn = n * n;
	for (int i = 0; i < nn; i++)
		x[i] = a[i] * scale;
	memset(num, 0, sizeof(double) * (size_t)nn);
	memset(den, 0, sizeof(double) * (size_t)nn);
	for (int i = 0; i < n; i++)
		num[i * n + i] = den[i * n + i] = 1.0;
	memcpy(p, x, sizeof(double) * (size_t)nn);
	for (int j = 1; j <= 6; j++) {
		double sign = (j % 2) ? -1.0 : 1.0;
		for (int i = 0; i < nn; i++) {
			num[i] += c[j] * p[i];
			den[i] += sign * c[j] * p[i];
		}
		if (j < 6)
			matmul(n, p, x, p);
	}
	if (solve(n, den, num) != 0)
		return POPC_ERR_NUMERIC;
	for (int i = 0; i < s; i++)
		matmul(n, num, num, num);
	memcpy(out, num, sizeof(double) * (size_t)nn);
	/* the squarings overflow when ||A|| is far beyond what double precision
	 * can exponentiate (e^||A|| past 1e308, or cancellation between huge
	 * entries): report it rather than hand back inf or NaN */
	for (int i = 0; i < nn; i++)
		if (!isfinite(out[i]))
			return POPC_ERR_NUMERIC;
	return 0;
}
