/* jit_constants: what bench/tick_jit.py takes from popc before its first tick.
 *
 *   jit_constants SCENE [--set section.key=value]...
 *
 * The numba reference of bench/tick_jit.py computes every tick of `popc run
 * SCENE` itself, operation for operation. What it does not compute is what
 * popc computes once, before the loop: the exact step's matrices (Phi and the
 * input columns: a Pade approximant of a 4 x 4 exponential, plant.c), the
 * damping's dissipation form (Van Loan's 8 x 8 block exponential,
 * plant_dissipation.c), the plant's rest position and the divergence bound
 * (sim_axis.c), and the same matrices for the parts of each period that a
 * breakpoint of the operator's profile splits (sim_axis.c, advance()). They
 * are printed here as C99 hex floats (%a: exact, float.fromhex reads them),
 * one name and its values a line:
 *
 *   period, ticks, delta, x_rest, k_x_rest, diverged, pc_bound, force_limit
 *   env KIND K B POSITION
 *   intent IS_FORCE K_OP B_OP K_X0 N t_0 q_0 ... t_N-1 q_N-1
 *   full  PHI(4) GAM(8) HAS_DISS D(4) U01 U02 U03 U12 U13 U23
 *   split K PARTS, then PARTS lines
 *   part  H WHOLE PHI(4) GAM(8) D(4) U01 U02 U03 U12 U13 U23
 *
 * It covers what the reference covers (the paper's scene and its kin): the
 * simulated axis, the exact integrator without friction, impedance
 * causality, variant ref-energy, no loop delay, a piecewise-linear intent
 * (ramp, force, table). Anything else: exit 2 and why. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "popc/axes/sim_axis.h"
#include "popc/core/controller.h"
#include "popc/core/intent.h"
#include "popc/core/plant.h"
#include "popc/core/plant_dissipation.h"
#include "popc/scene/from_scene.h"

static int usage(void)
{
	fputs("usage: jit_constants SCENE [--set section.key=value]...\n", stderr);
	return 2;
}

static void put(const char *name, double v)
{
	printf("%s %a\n", name, v);
}

/* the step's matrices and the dissipation form's coefficients, in the
 * order tick_jit.py reads them */
static void put_coeffs(const popc_plant_step_coeffs *c, const popc_plant_dissipation *d)
{
	for (int i = 0; i < 2; i++)
		for (int j = 0; j < 2; j++)
			printf(" %a", c->phi[i][j]);
	for (int i = 0; i < 2; i++)
		for (int j = 0; j < 4; j++)
			printf(" %a", c->gam[i][j]);
	for (int i = 0; i < 4; i++)
		printf(" %a", d->d[i]);
	printf(" %a %a %a %a %a %a", d->u[0][1], d->u[0][2], d->u[0][3], d->u[1][2], d->u[1][3],
	       d->u[2][3]);
}

/* Which scenes the reference covers; NULL when it covers s. */
static const char *not_covered(const popc_scene *s, const popc_plant *p)
{
	if (strcmp(s->axis, "sim") != 0)
		return "only the simulated axis (axis.kind = sim)";
	if (s->causality != POPC_CAUSALITY_IMPEDANCE)
		return "only impedance causality";
	if (s->integrator != POPC_INTEGRATOR_EXACT)
		return "only integrator.method = exact";
	if (p->friction)
		return "only a device without friction";
	if (s->variant != POPC_VARIANT_REF_ENERGY)
		return "only controller.variant = ref-energy (the paper scene's)";
	if (s->delay_ticks != 0)
		return "only run.delay_ticks = 0";
	if (s->intent == POPC_INTENT_SINE)
		return "only piecewise-linear intents (ramp, force, table)";
	return NULL;
}

int main(int argc, char **argv)
{
	if (argc < 2 || (argc % 2) != 0)
		return usage();
	popc_scene s;
	popc_error err;
	popc_scene_defaults(&s);
	if (popc_scene_load(&s, argv[1], &err) != 0) {
		fprintf(stderr, "jit_constants: %s\n", err.msg);
		return 2;
	}
	for (int k = 2; k + 1 < argc; k += 2) {
		if (strcmp(argv[k], "--set") != 0)
			return usage();
		if (popc_scene_set_assignment(&s, argv[k + 1], &err) != 0) {
			fprintf(stderr, "jit_constants: %s\n", err.msg);
			return 2;
		}
	}
	if (popc_scene_validate(&s, &err) != 0) {
		fprintf(stderr, "jit_constants: %s\n", err.msg);
		return 2;
	}
	popc_plant_config cfg;
	popc_plant_config_from_scene(&cfg, &s);
	popc_plant plant;
	popc_intent in;
	memset(&in, 0, sizeof in);
	if (popc_plant_init(&plant, &cfg, &err) != 0 || popc_intent_from_scene(&in, &s, &err) != 0) {
		fprintf(stderr, "jit_constants: %s\n", err.msg);
		popc_intent_free(&in);
		return 2;
	}
	const char *why = not_covered(&s, &plant);
	if (why) {
		fprintf(stderr, "jit_constants: %s: the reference covers %s\n", argv[1], why);
		popc_intent_free(&in);
		return 2;
	}
	/* the rest position and the divergence bound: those of the sim axis,
	 * read from its first sample (x_true) as bench_floor.c does */
	popc_axis *ax;
	if (popc_sim_axis_create(&ax, &s, &err) != 0) {
		fprintf(stderr, "jit_constants: %s\n", err.msg);
		popc_intent_free(&in);
		return 2;
	}
	popc_axis_sample smp;
	int st = ax->ops->sample(ax, &smp, &err);
	popc_axis_destroy(&ax);
	if (st) {
		fprintf(stderr, "jit_constants: %s\n", err.msg);
		popc_intent_free(&in);
		return 2;
	}
	const double T = popc_scene_period_s(&s), x_rest = smp.x_true_m;
	const double tol = POPC_INTENT_TICK_TOL_PERIODS * T;
	const long long n_ticks = popc_scene_ticks(&s) + 1;
	put("period", T);
	put("duration", s.duration_s);
	printf("ticks %lld\n", n_ticks);
	put("delta", s.enc_resolution_m);
	put("x_rest", x_rest);
	put("k_x_rest", cfg.stiffness_Npm * x_rest);
	put("diverged", fmin(popc_scene_reach_m(&s, &in, NULL, 0), 1e6)); /* sim_axis.c */
	put("pc_bound", s.pc_bound_N);
	put("force_limit", 0.0); /* the sim axis has none (axis.h) */
	popc_environment env;
	popc_environment_from_scene(&env, &s);
	printf("env %d %a %a %a\n", (int)env.kind, env.stiffness_Npm, env.damping_Nspm,
	       env.position_m);
	printf("intent %d %a %a %a %zu", in.q_is_force, in.k_op, in.b_op, in.k_op * in.x0, in.n);
	for (size_t i = 0; i < in.n; i++)
		printf(" %a %a", in.t[i], in.q[i]);
	printf("\n");
	popc_plant_dissipation diss;
	int has_diss = popc_plant_dissipation_init(&diss, &cfg, T) == 0;
	printf("full");
	put_coeffs(&plant.full, &diss);
	printf(" %d\n", has_diss);
	/* the periods that a breakpoint splits: popc_intent_period_input's
	 * test, then advance()'s parts */
	popc_intent_segment g = {0};
	for (long long k = 0; k + 1 < n_ticks; k++) {
		double t = (double)k * T, t_end = (double)(k + 1) * T;
		popc_plant_input u;
		if (popc_intent_period_input(&in, &g, t, t_end, tol, &u))
			continue;
		popc_plant_step_coeffs c[16];
		popc_plant_dissipation d[16];
		double h[16];
		int whole[16], n = 0;
		for (int w = 1; n < 16;) {
			double next;
			popc_intent_input(&in, t, &u, &next);
			int inside = next < t_end - tol && next > t;
			h[n] = inside ? next - t : t_end - t;
			whole[n] = w && !inside;
			if (whole[n]) {
				c[n] = plant.full;
				d[n] = diss;
			} else if ((h[n] == plant.full.h_s ? (c[n] = plant.full, 0)
							   : popc_plant_coeffs(&cfg, h[n], &c[n])) != 0 ||
				   popc_plant_dissipation_init(&d[n], &cfg, h[n]) != 0) {
				fprintf(stderr, "jit_constants: the step of %g s at tick %lld has no "
						"finite matrices\n", h[n], k);
				popc_intent_free(&in);
				return 1;
			}
			n++;
			if (!inside)
				break;
			t = next;
			w = 0;
		}
		printf("split %lld %d\n", k, n);
		for (int i = 0; i < n; i++) {
			printf("part %a %d", h[i], whole[i]);
			put_coeffs(&c[i], &d[i]);
			printf("\n");
		}
	}
	popc_intent_free(&in);
	return 0;
}
