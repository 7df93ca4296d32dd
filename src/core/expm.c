/* Matrix exponential for the small dense matrices of the exact plant step. */
#include <math.h>
#include <string.h>

#include "popc/core/plant.h"

#define NMAX 12

void popc_matmul(int n, const double *a, const double *b, double *out)
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

/* Diagonal balancing (Parlett and Reinsch 1969, radix 2, as LAPACK's dgebal
 * and Numerical Recipes' balanc): finds powers of two d_i such that
 * B = D^-1 A D has each off-diagonal row and column norm within a factor 2 of
 * each other, and scales a into B in place (exact: powers of two, each kept
 * within 2^+-500 so that d_i / d_j is finite). Returns the d_i in d;
 * expm(A) = D expm(B) D^-1.
 *
 * Why: a plant's A h mixes units, [[0, h], [-K/M h, -B/M h]]. For a stiff
 * light hand (K/M = 1e15 1/s^2, T = 1 ms) its 1-norm is 1e12 while the motion
 * turns by w T = 3e4 rad a period: scaling and squaring then squares 41 times
 * a matrix whose eigenvectors have condition number w = 3e7, and det(Phi),
 * which is exactly e^(-B/M h) <= 1, came out 1 + 1e-6: the "exact" step grew
 * the free motion by that much every period, and an undamped hand with no
 * contact ran to the divergence bound, blamed on the physics. Balanced, the
 * 2 x 2 block is a rotation of norm w h, squared 16 times. */
static void balance(int n, double *a, double *d)
{
	for (int i = 0; i < n; i++)
		d[i] = 1.0;
	for (int sweep = 0, done = 0; !done && sweep < 64; sweep++) {
		done = 1;
		for (int i = 0; i < n; i++) {
			double c = 0.0, r = 0.0;
			for (int j = 0; j < n; j++)
				if (j != i) {
					c += fabs(a[j * n + i]);
					r += fabs(a[i * n + j]);
				}
			if (c == 0.0 || r == 0.0)
				continue; /* an input state (a zero row) or a free one: nothing to even */
			double g = r / 2.0, f = 1.0, sum = c + r;
			while (c < g && d[i] * f < 0x1p500) {
				f *= 2.0;
				c *= 4.0;
			}
			g = r * 2.0;
			while (c >= g && d[i] * f > 0x1p-500) {
				f /= 2.0;
				c /= 4.0;
			}
			if ((c + r) / f < 0.95 * sum) {
				done = 0;
				d[i] *= f;
				for (int j = 0; j < n; j++) {
					a[i * n + j] /= f; /* row i of D^-1 A D */
					a[j * n + i] *= f; /* column i */
				}
			}
		}
	}
}

double popc_norm1(int n, const double *a)
{
	double norm = 0.0;
	for (int j = 0; j < n; j++) {
		double col = 0.0;
		for (int i = 0; i < n; i++)
			col += fabs(a[i * n + j]);
		if (col > norm)
			norm = col;
	}
	return norm;
}

int popc_expm(int n, const double *a_in, double *out)
{
	if (n < 1 || n > NMAX)
		return POPC_ERR_INVALID;
	/* Pade [6/6] coefficients c_j = (2q-j)! q! / ((2q)! j! (q-j)!), q = 6. */
	static const double c[7] = {1.0,          1.0 / 2.0,     5.0 / 44.0,      1.0 / 66.0,
				    1.0 / 792.0,  1.0 / 15840.0, 1.0 / 665280.0};
	/* theta_6 of Higham (2005), Table 2.3: the [6/6] approximant has backward
	 * error below the unit roundoff for ||A||_1 <= 0.54. */
	const double theta6 = 0.54;
	double a[NMAX * NMAX], d[NMAX];
	int nn = n * n;
	memcpy(a, a_in, sizeof(double) * (size_t)nn);
	for (int i = 0; i < n; i++)
		d[i] = 1.0;
	double norm = popc_norm1(n, a);
	if (!isfinite(norm))
		return POPC_ERR_NUMERIC;
	/* Balanced only when squarings follow: below theta6 the approximant alone
	 * is within the unit roundoff, and a step that needs no squaring (the
	 * paper's scene at 1 kHz: ||A T|| = 0.17) keeps its bits. */
	if (norm > theta6) {
		balance(n, a, d);
		norm = popc_norm1(n, a);
	}
	int s = 0;
	if (norm > theta6)
		s = (int)ceil(log2(norm / theta6));
	double scale = ldexp(1.0, -s);
	double x[NMAX * NMAX], p[NMAX * NMAX], num[NMAX * NMAX], den[NMAX * NMAX];
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
			popc_matmul(n, p, x, p);
	}
	if (solve(n, den, num) != 0)
		return POPC_ERR_NUMERIC;
	for (int i = 0; i < s; i++)
		popc_matmul(n, num, num, num);
	for (int i = 0; i < n; i++) /* expm(A) = D expm(D^-1 A D) D^-1 */
		for (int j = 0; j < n; j++)
			out[i * n + j] = num[i * n + j] * (d[i] / d[j]);
	/* the squarings overflow when ||A|| is far beyond what double precision
	 * can exponentiate (e^||A|| past 1e308, or cancellation between huge
	 * entries): report it rather than hand back inf or NaN */
	for (int i = 0; i < nn; i++)
		if (!isfinite(out[i]))
			return POPC_ERR_NUMERIC;
	return 0;
}
