/* End-fit FOAW velocity estimator (velocity.h). */
#include "popc/velocity.h"

#include <math.h>
#include <string.h>

void popc_foaw_init(popc_foaw *f, int max_window, double noise_m, double period_s)
{
	memset(f, 0, sizeof *f);
	if (max_window < 1)
		max_window = 1;
	if (max_window > POPC_FOAW_MAX_WINDOW)
		max_window = POPC_FOAW_MAX_WINDOW;
	f->max_window = max_window;
	f->noise_m = noise_m;
	f->period_s = period_s;
}

/* x(k - i), i = 0 .. filled - 1 */
static inline double back(const popc_foaw *f, int i)
{
	int idx = f->head - i;
	if (idx < 0)
		idx += POPC_FOAW_MAX_WINDOW + 1;
	return f->x[idx];
}

double popc_foaw_update(popc_foaw *f, double x_m)
{
	f->head = (f->head + 1) % (POPC_FOAW_MAX_WINDOW + 1);
	f->x[f->head] = x_m;
	if (f->filled < f->max_window + 1)
		f->filled++;
	if (f->filled < 2)
		return 0.0;
	/* Janabi-Sharifi et al. (2000), end-fit FOAW: grow n while the line through
	 * x(k-n) and x(k) stays within +-d of every sample x(k-j), 0 < j < n. */
	double best = (x_m - back(f, 1)) / f->period_s;
	for (int n = 2; n < f->filled; n++) {
		double slope = (x_m - back(f, n)) / n; /* per sample */
		int ok = 1;
		for (int j = 1; j < n && ok; j++)
			if (fabs(x_m - slope * j - back(f, j)) > f->noise_m)
				ok = 0;
		if (!ok)
			break;
		best = slope / f->period_s;
	}
	return best;
}
