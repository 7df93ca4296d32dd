/* End-fit FOAW velocity estimator (velocity.h). */
#include "popc/core/velocity.h"

#include <math.h>
#include <string.h>

/* Count differences up to 2^55 keep n * a - j * b (n, j <= 64) within 2^62:
 * no overflow. A larger jump inside a window is never a slow motion: the
 * window stops there (the shorter window is the estimate). */
#define FOAW_MAX_COUNT_DIFF (1LL << 55)

void popc_foaw_init(popc_foaw *f, int max_window, double noise_m, double resolution_m,
		    double period_s)
{
	memset(f, 0, sizeof *f);
	if (max_window < 1)
		max_window = 1;
	if (max_window > POPC_FOAW_MAX_WINDOW)
		max_window = POPC_FOAW_MAX_WINDOW;
	f->max_window = max_window;
	f->noise_m = noise_m;
	f->resolution_m = resolution_m;
	f->period_s = period_s;
	/* d = m delta, m whole: the scene gives d as text (3e-5 / 1e-5 =
	 * 2.9999999999999996), so "whole" is to 1e-9 relative */
	if (resolution_m > 0.0 && noise_m > 0.0) {
		double m = noise_m / resolution_m, mr = round(m);
		if (mr >= 1.0 && mr <= 4294967296.0 && fabs(m - mr) <= 1e-9 * mr)
			f->noise_counts = (long long)mr;
	}
}

static inline int ring_index(const popc_foaw *f, int i)
{
	int idx = f->head - i;
	return idx < 0 ? idx + POPC_FOAW_MAX_WINDOW + 1 : idx;
}

/* x(k - i) and c(k - i), i = 0 .. filled - 1 */
static inline double back_x(const popc_foaw *f, int i)
{
	return f->x[ring_index(f, i)];
}

static inline long long back_c(const popc_foaw *f, int i)
{
	return f->c[ring_index(f, i)];
}

static inline int within(long long d)
{
	return d >= -FOAW_MAX_COUNT_DIFF && d <= FOAW_MAX_COUNT_DIFF;
}

/* The longest window n whose end-fit line through c(k-n), c(k) stays within
 * m counts of every c(k-j), 0 < j < n: |n (c_k - c_{k-j}) - j (c_k - c_{k-n})|
 * <= n m, exact in integers. */
static int window_counts(const popc_foaw *f)
{
	const long long ck = back_c(f, 0), m = f->noise_counts;
	int best = 1;
	for (int n = 2; n < f->filled; n++) {
		long long b = ck - back_c(f, n);
		if (!within(b))
			break;
		int ok = 1;
		for (int j = 1; j < n && ok; j++) {
			long long a = ck - back_c(f, j);
			if (!within(a)) {
				ok = 0;
				break;
			}
			long long dev = n * a - j * b;
			ok = (dev < 0 ? -dev : dev) <= n * m;
		}
		if (!ok)
			break;
		best = n;
	}
	return best;
}

/* The same test in metres, for a band that is not a whole number of counts. */
static int window_metres(const popc_foaw *f)
{
	const double xk = back_x(f, 0);
	int best = 1;
	for (int n = 2; n < f->filled; n++) {
		double slope = (xk - back_x(f, n)) / n; /* per sample */
		int ok = 1;
		for (int j = 1; j < n && ok; j++)
			if (fabs(xk - slope * j - back_x(f, j)) > f->noise_m)
				ok = 0;
		if (!ok)
			break;
		best = n;
	}
	return best;
}

double popc_foaw_update(popc_foaw *f, long long count, double x_m)
{
	f->head = (f->head + 1) % (POPC_FOAW_MAX_WINDOW + 1);
	f->x[f->head] = x_m;
	f->c[f->head] = count;
	if (f->filled < f->max_window + 1)
		f->filled++;
	if (f->filled < 2)
		return 0.0;
	if (f->noise_counts > 0) {
		int n = window_counts(f);
		return (double)(count - back_c(f, n)) * f->resolution_m / n / f->period_s;
	}
	/* Janabi-Sharifi et al. (2000), end-fit FOAW: grow n while the line through
	 * x(k-n) and x(k) stays within +-d of every sample x(k-j), 0 < j < n. */
	int n = window_metres(f);
	return (x_m - back_x(f, n)) / n / f->period_s;
}
