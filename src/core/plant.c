/* The lumped plant M x'' = u(t) - B x' - K x: validation, setup and the step
 * matrices (plant.h); the steps themselves are in plant_step.c. */
#include "popc/core/plant.h"

#include <math.h>
#include <string.h>

#define POPC_TWO_PI 6.283185307179586476925286766559

const char *const popc_integrator_names[] = {"exact", "trapezoid", "rk4", "semi-implicit-euler",
					     "euler", NULL};

const char *popc_integrator_name(popc_integrator m)
{
	return (unsigned)m < POPC_INTEGRATOR_COUNT ? popc_integrator_names[m] : "?";
}

int popc_integrator_from_name(const char *name, popc_integrator *out)
{
	for (int i = 0; popc_integrator_names[i]; i++)
		if (strcmp(popc_integrator_names[i], name) == 0) {
			*out = (popc_integrator)i;
			return 0;
		}
	return POPC_ERR_INVALID;
}

/* ---- the overdamped stiff plant: closed form ------------------------------
 *
 * A light, damped plant (M/B far below T) has a fast mode lambda_f ~ -B/M
 * that dies within a step and a slow one lambda_s ~ -K/B that carries the
 * motion. Scaling and squaring keeps the backward error u ||A h|| of the
 * fast mode, so the slow eigenvalue of Phi comes out with a relative error of
 * about u |lambda_f / lambda_s| = u B^2 / (K M) (1e-16 x 5e14 = 5 % for
 * M = 1e-17 kg, B = 0.5 N s/m, K = 50 N/m): the rest position was 33 counts
 * (of 1e-5 m) off, and at 1e-20 kg |eigenvalue| >= 1 made the plant drift
 * (tests/perf/test_hard_cases.c, test_light_plant_grid).
 *
 * Real eigenvalues have a closed form. With the stable roots
 *     S = sqrt(B^2 - 4 K M),  lambda_f = -(B + S) / (2 M),  lambda_s = -2 K / (B + S)
 * (no difference of near-equal numbers; lambda_f - lambda_s = -S / M), every
 * function f of the 2 x 2 matrix A is f(A) = alpha I + beta A, with beta and
 * alpha the divided differences of f and of -lambda_other f over the two
 * eigenvalues (Cayley-Hamilton; Higham, Functions of Matrices, 2008, 1.2).
 * The step's matrices are such functions applied to b = [0, 1/M]:
 *     Phi      = e^(A h),
 *     u0 column: f0(A) b,   f0(l) = (e^(l h) - 1) / l          = h phi1(l h),
 *     u1 column: f1(A) b,   f1(l) = (e^(l h) - 1 - l h) / l^2  = h^2 phi2(l h),
 *     uc + i us: g(A) b,    g(l)  = (e^(i w h) - e^(l h)) / (i w - l)
 * (the responses to u0, u1 tau and e^(i w tau) over the step). For f(A) b
 * the divided differences come out as
 *     x row: (f(lambda_s) - f(lambda_f)) / S,
 *     v row: (lambda_s f(lambda_s) - lambda_f f(lambda_f)) / S,
 * each entry a difference of two terms that differ by a factor e^(2/3) or
 * more when the eigenvalues are 3 apart and the fast mode decays by e^-1 in
 * the step (the condition below), so each is accurate to a few u. */

/* Where the closed form is used: B > 0, real eigenvalues at least a factor 3
 * apart (S >= B / 2, i.e. 16 K M <= 3 B^2), and the fast mode decaying by at
 * least e^-1 within the step (|lambda_f| h >= 1), so that expm would square.
 * Elsewhere expm is accurate: complex or near-critical eigenvalues have
 * moduli within a factor 3 (u ||A h|| is small against each), and without
 * squarings the approximant's error is within the unit roundoff. */
static int overdamped_stiff(const popc_plant_config *cfg, double h)
{
	double m = cfg->mass_kg, b = cfg->damping_Nspm, k = cfg->stiffness_Npm;
	if (!(b > 0.0) || !(k >= 0.0))
		return 0;
	double disc = b * b - 4.0 * k * m;
	if (!(disc >= 0.25 * b * b))
		return 0;
	double s = sqrt(disc);
	return (b + s) * h >= 2.0 * m;
}

/* (e^z - 1) / z, and its limit 1 at z = 0 (expm1 keeps the small z exact). */
static double phi1(double z)
{
	return z == 0.0 ? 1.0 : expm1(z) / z;
}

/* (e^z - 1 - z) / z^2 for z <= 0: the Taylor series sum z^j / (j + 2)! for
 * |z| < 1/2 (the direct form loses 2 u / |z| there; 16 terms reach 0.5^16 /
 * 18! < 1e-20), else (phi1(z) - 1) / z, which neither cancels (phi1 < 0.79)
 * nor overflows. */
static double phi2(double z)
{
	if (fabs(z) < 0.5) {
		double sum = 0.0, coef = 1.0;
		double inv_fact[16];
		for (int j = 0; j < 16; j++) {
			coef /= (double)(j + 2); /* 1 / (j + 2)! */
			inv_fact[j] = coef;
		}
		for (int j = 15; j >= 0; j--)
			sum = sum * z + inv_fact[j];
		return sum;
	}
	return (phi1(z) - 1.0) / z;
}

/* g(l) / h = (e^(i th) - e^z) / (i th - z) with z = l h <= 0, th = w h >= 0,
 * as (re, im). The numerator as (cos th - 1) - (e^z - 1) + i sin th, so that
 * near z = th = 0 no two numbers near 1 are subtracted; the division by
 * Smith's rule (no overflow of z^2 for the fast mode's huge |z|). */
static void g_over_h(double z, double th, double *re, double *im)
{
	double s_half = sin(0.5 * th);
	double nr = -2.0 * s_half * s_half - expm1(z), ni = sin(th);
	double dr = -z, di = th; /* dr >= 0, di >= 0, not both 0 (th > 0) */
	if (dr >= di) {
		double r = di / dr, den = dr + di * r;
		*re = (nr + ni * r) / den;
		*im = (ni - nr * r) / den;
	} else {
		double r = dr / di, den = di + dr * r;
		*re = (nr * r + ni) / den;
		*im = (ni * r - nr) / den;
	}
}

static void overdamped_coeffs(const popc_plant_config *cfg, double h, popc_plant_step_coeffs *c)
{
	double m = cfg->mass_kg, b = cfg->damping_Nspm, k = cfg->stiffness_Npm;
	double s = sqrt(b * b - 4.0 * k * m);
	double lf = -(b + s) / (2.0 * m), ls = -2.0 * k / (b + s);
	double zf = lf * h, zs = ls * h; /* zf <= -1, zf <= 3 zs <= 0 */
	double ef = exp(zf), es = exp(zs);
	/* Phi: alpha = (lf e^zs - ls e^zf) / (lf - ls), beta = (e^zf - e^zs) / (lf - ls);
	 * lf / (lf - ls) = (b + s) / (2 s), ls / (lf - ls) = 2 k m / ((b + s) s) */
	double cf = (b + s) / (2.0 * s), cs = 2.0 * k * m / ((b + s) * s);
	c->phi[0][0] = cf * es - cs * ef;
	c->phi[0][1] = m * (es - ef) / s;
	c->phi[1][0] = -k * (es - ef) / s; /* -(K/M) beta */
	c->phi[1][1] = cf * ef - cs * es;
	/* u0: f0 = h phi1(z); lambda f0(lambda) = e^z - 1 */
	c->gam[0][0] = h * (phi1(zs) - phi1(zf)) / s;
	c->gam[1][0] = (es - ef) / s;
	/* u1: f1 = h^2 phi2(z); lambda f1(lambda) = f0(lambda) - h */
	c->gam[0][1] = h * h * (phi2(zs) - phi2(zf)) / s;
	c->gam[1][1] = c->gam[0][0];
	if (cfg->omega_radps != 0.0) {
		double th = cfg->omega_radps * h, gsr, gsi, gfr, gfi;
		g_over_h(zs, th, &gsr, &gsi);
		g_over_h(zf, th, &gfr, &gfi);
		/* x row: h (g_s - g_f) / s; v row: (zs g_s - zf g_f) / s (lambda h = z) */
		c->gam[0][2] = h * (gsr - gfr) / s;
		c->gam[0][3] = h * (gsi - gfi) / s;
		c->gam[1][2] = (zs * gsr - zf * gfr) / s;
		c->gam[1][3] = (zs * gsi - zf * gfi) / s;
	}
}

/* The rotation an underdamped plant makes in a step h that it does not damp
 * away: w_d h e^(-B h / (2 M)), w_d = sqrt(4 K M - B^2) / (2 M) (0 when the
 * eigenvalues are real). The balanced scaling and squaring of expm turns a
 * rotation of angle w_d h with an error of about 16 eps w_d h (measured at
 * most 2.6 eps w_d h, tests/unit/test_plant.c), and the angle itself is
 * rounded by eps w_d h, so beyond POPC_PLANT_TURN_MAX_RAD the step holds
 * less than half the digits of double precision; the factor e^(-B h / (2 M))
 * is how much of that error survives the step (a plant damped within the step
 * forgets it). */
static double underdamped_turn(const popc_plant_config *cfg, double h)
{
	double m = cfg->mass_kg, b = cfg->damping_Nspm, k = cfg->stiffness_Npm;
	double d = 4.0 * k * m - b * b;
	if (!(d > 0.0))
		return 0.0;
	return sqrt(d) / (2.0 * m) * h * exp(-b / (2.0 * m) * h);
}

int popc_plant_augmented(const popc_plant_config *cfg, double a[36])
{
	int n = cfg->omega_radps != 0.0 ? 6 : 4;
	double m = cfg->mass_kg;
	memset(a, 0, 36 * sizeof a[0]);
	a[0 * n + 1] = 1.0;
	a[1 * n + 0] = -cfg->stiffness_Npm / m;
	a[1 * n + 1] = -cfg->damping_Nspm / m;
	a[1 * n + 2] = 1.0 / m;
	a[2 * n + 3] = 1.0;
	if (n == 6) {
		a[1 * n + 4] = 1.0 / m;
		a[4 * n + 5] = cfg->omega_radps;
		a[5 * n + 4] = -cfg->omega_radps;
	}
	return n;
}

/* Exact step: the augmented system [x v y1 y2 p q] with y1' = y2 (affine input
 * u0 + u1 tau) and the rotation p' = w q, q' = -w p (p(0) = uc, q(0) = us gives
 * p = uc cos(w tau) + us sin(w tau)); u = y1 + p drives v. expm(A_aug h) holds
 * Phi in its top-left block and the input columns beside it. The sine states
 * exist only when the scene has a sine (model only what the scene needs). */
static int exact_coeffs(const popc_plant_config *cfg, double h, popc_plant_step_coeffs *c)
{
	if (overdamped_stiff(cfg, h)) { /* never for the paper's (underdamped) scenes */
		overdamped_coeffs(cfg, h, c);
		return 0;
	}
	double a[36], e[36];
	int n = popc_plant_augmented(cfg, a);
	for (int i = 0; i < n * n; i++)
		a[i] *= h;
	int st = popc_expm(n, a, e);
	if (st)
		return st;
	for (int i = 0; i < 2; i++) {
		c->phi[i][0] = e[i * n + 0];
		c->phi[i][1] = e[i * n + 1];
		c->gam[i][0] = e[i * n + 2];
		c->gam[i][1] = e[i * n + 3];
		c->gam[i][2] = n == 6 ? e[i * n + 4] : 0.0;
		c->gam[i][3] = n == 6 ? e[i * n + 5] : 0.0;
	}
	return 0;
}

/* Trapezoidal rule for the linear system z' = A z + b u, one substep of length
 * hs: (I - hs A/2) z+ = (I + hs A/2) z + hs/2 b (u(t) + u(t + hs)). */
static void trapezoid_coeffs(const popc_plant_config *cfg, double hs, popc_plant_step_coeffs *c)
{
	double m = cfg->mass_kg, k = cfg->stiffness_Npm / m, b = cfg->damping_Nspm / m;
	/* L = I - hs/2 A = [1, -hs/2; hs/2 k, 1 + hs/2 b], R = I + hs/2 A */
	double l00 = 1.0, l01 = -hs / 2, l10 = hs / 2 * k, l11 = 1.0 + hs / 2 * b;
	double det = l00 * l11 - l01 * l10;
	double i00 = l11 / det, i01 = -l01 / det, i10 = -l10 / det, i11 = l00 / det;
	double r00 = 1.0, r01 = hs / 2, r10 = -hs / 2 * k, r11 = 1.0 - hs / 2 * b;
	c->trap[0][0] = i00 * r00 + i01 * r10;
	c->trap[0][1] = i00 * r01 + i01 * r11;
	c->trap[1][0] = i10 * r00 + i11 * r10;
	c->trap[1][1] = i10 * r01 + i11 * r11;
	c->trap_in[0] = i01 * (hs / 2 / m);
	c->trap_in[1] = i11 * (hs / 2 / m);
}

int popc_plant_coeffs(const popc_plant_config *cfg, double h_s, popc_plant_step_coeffs *c)
{
	memset(c, 0, sizeof *c);
	c->h_s = h_s;
	int st = 0;
	if (cfg->method == POPC_INTEGRATOR_EXACT)
		st = exact_coeffs(cfg, h_s, c);
	else if (cfg->method == POPC_INTEGRATOR_TRAPEZOID)
		trapezoid_coeffs(cfg, h_s / cfg->substeps, c);
	if (st)
		return st;
	/* scaling and squaring can overflow for a plant far too stiff for the
	 * step: a non-finite coefficient would turn every later state into
	 * garbage (and an uninitialised-looking encoder count) */
	const double *v = &c->phi[0][0];
	for (size_t i = 0; i < 4; i++)
		if (!isfinite(v[i]))
			return POPC_ERR_NUMERIC;
	v = &c->gam[0][0];
	for (size_t i = 0; i < 8; i++)
		if (!isfinite(v[i]))
			return POPC_ERR_NUMERIC;
	v = &c->trap[0][0];
	for (size_t i = 0; i < 4; i++)
		if (!isfinite(v[i]))
			return POPC_ERR_NUMERIC;
	if (!isfinite(c->trap_in[0]) || !isfinite(c->trap_in[1]))
		return POPC_ERR_NUMERIC;
	return 0;
}

int popc_plant_init(popc_plant *p, const popc_plant_config *cfg, popc_error *err)
{
	if (!(cfg->mass_kg > 0) || !isfinite(cfg->mass_kg))
		return popc_error_set(err, POPC_ERR_INVALID, "plant: mass %g kg must be > 0",
				      cfg->mass_kg);
	if (!(cfg->damping_Nspm >= 0) || !(cfg->stiffness_Npm >= 0) || !isfinite(cfg->damping_Nspm) ||
	    !isfinite(cfg->stiffness_Npm))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: damping and stiffness must be finite and >= 0");
	if (cfg->substeps < 1 || !(cfg->period_s > 0) || !isfinite(cfg->period_s))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: substeps must be >= 1 and the period > 0");
	/* Every method divides by M and the exact one scales A h; a ratio that
	 * overflows is no plant double precision can step (e.g. K = 1e9 N/m on
	 * M = 2.3e-308 kg: K/M = inf). The messages name this module's own
	 * parameters (popc_plant_config's fields); the scene layer, which sums
	 * keys into them, names the keys (popc_plant_name_keys, from_scene.h). */
	double m = cfg->mass_kg, h = cfg->period_s;
	double k_m = cfg->stiffness_Npm / m, b_m = cfg->damping_Nspm / m;
	if (!isfinite(1.0 / m))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: 1/M is not finite for M = mass_kg = %g kg; raise mass_kg",
				      m);
	if (!isfinite(k_m) || !isfinite(k_m * h * h))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: K/M = stiffness_Npm / mass_kg = %g N/m / %g kg%s is not "
				      "finite; raise mass_kg or lower stiffness_Npm",
				      cfg->stiffness_Npm, m,
				      isfinite(k_m) ? " times T^2 (T = period_s)" : "");
	if (!isfinite(b_m))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: B/M = damping_Nspm / mass_kg = %g N s/m / %g kg is not "
				      "finite; raise mass_kg or lower damping_Nspm",
				      cfg->damping_Nspm, m);
	if (cfg->method == POPC_INTEGRATOR_EXACT && !overdamped_stiff(cfg, h)) {
		double turn = underdamped_turn(cfg, h);
		if (turn > POPC_PLANT_TURN_MAX_RAD)
			return popc_error_set(
				err, POPC_ERR_INVALID,
				"plant: the plant turns %.3g rad per period, above %.3g rad (w_d T e^(-B T "
				"/ 2M), w_d = sqrt(4KM - B^2) / 2M; K = stiffness_Npm = %g N/m, M = "
				"mass_kg = %g kg, B = damping_Nspm = %g N s/m, T = period_s = %g s): "
				"the exact step would keep under half of double precision; raise M or B, "
				"lower K, or shorten T",
				turn, POPC_PLANT_TURN_MAX_RAD, cfg->stiffness_Npm, m, cfg->damping_Nspm, h);
	}
	if (!(cfg->coulomb_N >= 0) || !isfinite(cfg->coulomb_N) || !(cfg->stiction_N >= 0) ||
	    !isfinite(cfg->stiction_N))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: coulomb_N = %g N and stiction_N = %g N must be "
				      "finite and >= 0",
				      cfg->coulomb_N, cfg->stiction_N);
	if (cfg->stiction_N > 0 && cfg->stiction_N < cfg->coulomb_N)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "plant: stiction_N = %g N is below coulomb_N = %g N; "
				      "allowed stiction_N >= coulomb_N (or 0: equal to it)",
				      cfg->stiction_N, cfg->coulomb_N);
	memset(p, 0, sizeof *p);
	p->cfg = *cfg;
	p->friction = cfg->coulomb_N > 0 || cfg->stiction_N > 0;
	p->friction_subs = 1;
	if (p->friction && cfg->method == POPC_INTEGRATOR_EXACT) {
		/* v = 0 is searched on sub-intervals that turn at most 1/2 rad
		 * (plant_friction.c, FRICTION_TURN_RAD) */
		double rate = fmax(sqrt(k_m), cfg->omega_radps);
		double n = ceil(rate * h / 0.5);
		p->friction_subs = n <= 1.0 ? 1 : n >= 256.0 ? 256 : (int)n;
		if (popc_plant_coeffs(cfg, h / p->friction_subs, &p->sub) != 0)
			return popc_error_set(err, POPC_ERR_NUMERIC,
					      "plant: the exact step matrices for T / %d = %g s are not "
					      "finite (K/M = %g 1/s^2, B/M = %g 1/s)",
					      p->friction_subs, h / p->friction_subs, k_m, b_m);
	}
	if (popc_plant_coeffs(cfg, cfg->period_s, &p->full) != 0)
		return popc_error_set(err, POPC_ERR_NUMERIC,
				      "plant: the %s step matrices for T = %g s are not finite (K/M = %g "
				      "1/s^2, B/M = %g 1/s): the plant (mass_kg, damping_Nspm, "
				      "stiffness_Npm) is too stiff for double precision at T = period_s",
				      popc_integrator_name(cfg->method), h, k_m, b_m);
	return 0;
}
