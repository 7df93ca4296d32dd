/* Compensated summation for the energies that run over millions of ticks
 * (W and E_ref of the passivity observer). */
#ifndef POPC_COMPENSATED_H
#define POPC_COMPENSATED_H

/* Adds the increment d to the compensated sum (sum, comp) and returns the
 * rounded value sum + comp. Knuth's branch-free TwoSum gives the exact
 * rounding error e of sum + d (Knuth, TAOCP vol. 2, 4.2.2, Theorem B); the
 * errors accumulate in comp (Neumaier 1974). Needs IEEE double arithmetic
 * without reassociation (no -ffast-math). */
static inline double popc_compensated_add(double *sum, double *comp, double d)
{
	double s = *sum, t = s + d;
	double z = t - s;
	double e = (s - (t - z)) + (d - z);
	*sum = t;
	*comp += e;
	return t + *comp;
}

#endif
