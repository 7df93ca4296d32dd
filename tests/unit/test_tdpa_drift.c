/* Position-drift compensation within the observer's energy
 * (core/tdpa_drift.h) and the passivity excess (core/tdpa.h): each law's
 * velocity bounds and energy limit, table-driven; nothing before the first
 * packet or from a non-finite input; and, over random ticks, the two-port
 * condition after every compensated tick, the excess adding exactly E_0 to
 * what may leave and nothing (bit for bit) when 0. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "popc/core/random.h"
#include "popc/core/tdpa_drift.h"
#include "popc/core/teleop.h"

static const double T = 1e-3;

static int same_bits(double a, double b)
{
	return memcmp(&a, &b, sizeof a) == 0;
}

/* One tick from a side that received remote_J and delivered out_J before. */
static void side_with(popc_tdpa_side *s, double remote_J, double out_J)
{
	popc_tdpa_side_init(s, 10.0);
	popc_tdpa_receive(s, remote_J);
	popc_energy_flow_add(&s->flow, out_J);
}

static void test_laws(void **state)
{
	(void)state;
	static const struct {
		const char *what;
		popc_drift_law law;
		double remote_J, out_J, u, c, x_rx, x_cmd;
		double want; /* v_dc */
	} cases[] = {
		/* free space (c = 0): the whole drift in one period, within v_max 0.5 */
		{"off", POPC_DRIFT_OFF, 1, 0, 0.1, 0, 0.01, 0, 0},
		{"artigas, free, drift 1 mm", POPC_DRIFT_ARTIGAS2010, 0, 0, 0.0, 0, 0.001, 0, 1.0 * 0.5},
		{"artigas, free, drift 0.2 mm", POPC_DRIFT_ARTIGAS2010, 0, 0, 0.0, 0, 0.0002, 0, 0.2},
		{"artigas, free, after u T", POPC_DRIFT_ARTIGAS2010, 0, 0, 0.1, 0, 0.0003, 0, 0.2},
		{"artigas, free, drift behind", POPC_DRIFT_ARTIGAS2010, 0, 0, 0.0, 0, -0.0001, 0, -0.1},
		/* coelho: at most ratio 0.5 x |u| */
		{"coelho, free, u = 0.1", POPC_DRIFT_COELHO2018, 0, 0, 0.1, 0, 0.0003, 0, 0.05},
		{"coelho, free, u = -0.1", POPC_DRIFT_COELHO2018, 0, 0, -0.1, 0, 0.0003, 0, 0.05},
		{"coelho, at rest", POPC_DRIFT_COELHO2018, 0, 0, 0.0, 0, 0.0003, 0, 0},
		/* in contact (c = -f_s = 2 N): v_dc c T at most W_0 = 1e-4 J */
		{"artigas, energy 1e-4 J", POPC_DRIFT_ARTIGAS2010, 1e-4, 0, 0.0, 2, 0.001, 0, 0.05},
		{"artigas, energy plenty", POPC_DRIFT_ARTIGAS2010, 1, 0, 0.0, 2, 0.0001, 0, 0.1},
		{"artigas, no energy", POPC_DRIFT_ARTIGAS2010, 1e-4, 1e-4, 0.0, 2, 0.001, 0, 0},
		{"artigas, W_0 < 0", POPC_DRIFT_ARTIGAS2010, 0, 1e-4, 0.0, 2, 0.001, 0, 0},
		/* proposed output's energy counted first: u c T = 0.1 x 2 x 1e-3 = 2e-4 */
		{"artigas, after u's energy", POPC_DRIFT_ARTIGAS2010, 3e-4, 0, 0.1, 2, 0.001, 0, 0.05},
		/* the drift backward takes energy in: no energy needed */
		{"artigas, dissipating", POPC_DRIFT_ARTIGAS2010, 0, 1e-4, 0.0, 2, -0.0001, 0, -0.1},
		{"coelho, energy-limited", POPC_DRIFT_COELHO2018, 3e-4, 0, 0.1, 2, 0.001, 0, 0.05},
		{"coelho, ratio-limited", POPC_DRIFT_COELHO2018, 1, 0, 0.1, 2, 0.001, 0, 0.05},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_tdpa_side s;
		side_with(&s, cases[i].remote_J, cases[i].out_J);
		const popc_drift_config cfg = {cases[i].law, 0.5, 0.5};
		const double v = popc_drift_velocity(&s, &cfg, cases[i].u, cases[i].c, T, cases[i].x_rx,
						     cases[i].x_cmd);
		if (!(fabs(v - cases[i].want) <= 1e-12 * fabs(cases[i].want) + 1e-15))
			fail_msg("%s: v_dc = %.17g, want %.17g", cases[i].what, v, cases[i].want);
	}
	/* nothing received yet (NaN), or a non-finite input: 0 */
	popc_tdpa_side s;
	side_with(&s, 1, 0);
	const popc_drift_config cfg = {POPC_DRIFT_ARTIGAS2010, 0.5, 0.5};
	const double bad[] = {(double)NAN, (double)INFINITY};
	for (int i = 0; i < 2; i++) {
		assert_true(same_bits(popc_drift_velocity(&s, &cfg, 0.0, 0.0, T, bad[i], 0.0), 0.0));
		assert_true(same_bits(popc_drift_velocity(&s, &cfg, 0.0, 0.0, T, 0.001, bad[i]), 0.0));
		assert_true(same_bits(popc_drift_velocity(&s, &cfg, bad[i], 0.0, T, 0.001, 0.0), 0.0));
		assert_true(same_bits(popc_drift_velocity(&s, &cfg, 0.0, bad[i], T, 0.001, 0.0), 0.0));
	}
}

/* Random ticks of a side with the drift law on, the PC on or off: with the
 * PC, what left never exceeds what was received plus the excess (the
 * condition, within rounding); v_dc within its bounds; with the PC off the
 * compensation alone never makes the observer negative where it was not. */
static void test_condition_random(void **state)
{
	(void)state;
	uint64_t rng = 2010;
	for (int law = POPC_DRIFT_ARTIGAS2010; law <= POPC_DRIFT_COELHO2018; law++)
		for (int ex = 0; ex < 2; ex++) {
			const double E0 = ex ? 1e-3 : 0.0;
			popc_tdpa_side s;
			popc_tdpa_side_init_excess(&s, 0.0, E0);
			const popc_drift_config cfg = {(popc_drift_law)law, 0.3, 0.4};
			double remote = 0.0, x_cmd = 0.0;
			long long compensated = 0;
			for (int k = 0; k < 200000; k++) {
				remote += 2e-5 * popc_uniform(&rng);
				const double u = 0.2 * (popc_uniform(&rng) - 0.5);
				const double c = popc_uniform(&rng) < 0.3 ? 0.0 : 10.0 * (popc_uniform(&rng) - 0.5);
				const double x_rx = x_cmd + 0.002 * (popc_uniform(&rng) - 0.5);
				double v_dc;
				popc_tdpa_step st = popc_drift_port(&s, &cfg, remote, u, c, T, 1, x_rx, x_cmd, &v_dc);
				compensated += v_dc != 0.0;
				assert_true(fabs(v_dc) <= cfg.v_max_mps);
				if (law == POPC_DRIFT_COELHO2018)
					assert_true(fabs(v_dc) <= cfg.ratio * fabs(u));
				assert_true(same_bits(st.u, u + v_dc + st.d));
				if (!popc_teleop_condition_holds(s.remote_in_J + s.excess_J,
								 popc_energy_flow_out(&s.flow)))
					fail_msg("law %d, E_0 %g, tick %d: out %.17g > remote %.17g + %g", law, E0,
						 k, popc_energy_flow_out(&s.flow), s.remote_in_J, E0);
				x_cmd += st.u * T;
			}
			print_message("%s, excess %g J: compensated on %lld of 200000 ticks\n",
				      popc_drift_law_names[law], E0, compensated);
			assert_true(compensated > 10000);
		}
}

/* The excess: 0 gives the bits of popc_tdpa_side_init; E_0 lets exactly E_0
 * more leave before the PC acts. */
static void test_excess(void **state)
{
	(void)state;
	popc_tdpa_side a, b;
	popc_tdpa_side_init(&a, 5.0);
	popc_tdpa_side_init_excess(&b, 5.0, 0.0);
	uint64_t rng = 7;
	for (int k = 0; k < 50000; k++) {
		const double r = 1e-3 * k * popc_uniform(&rng), u = popc_uniform(&rng) - 0.5,
			     c = popc_uniform(&rng) - 0.5;
		popc_tdpa_step sa = popc_teleop_port(&a, r, u, c, T, 1);
		popc_tdpa_step sb = popc_teleop_port(&b, r, u, c, T, 1);
		assert_true(same_bits(sa.u, sb.u) && same_bits(sa.d, sb.d) && same_bits(sa.W_J, sb.W_J));
		assert_true(same_bits(popc_teleop_margin_J(&a), popc_teleop_margin_J(&b)));
	}
	/* nothing received: with E_0 = 2e-3 J, 1 N x 1 m/s x 1 ms delivers 1e-3 J
	 * twice without a correction, the third tick is corrected to 0 */
	popc_tdpa_side s;
	popc_tdpa_side_init_excess(&s, 0.0, 2e-3);
	for (int k = 0; k < 3; k++) {
		popc_tdpa_step st = popc_teleop_port(&s, 0.0, 1.0, 1.0, T, 1);
		assert_int_equal(st.flags & POPC_TDPA_ACTIVE, k == 2 ? POPC_TDPA_ACTIVE : 0);
	}
	assert_true(fabs(popc_energy_flow_out(&s.flow) - 2e-3) < 1e-18);
	assert_true(popc_teleop_condition_holds(s.remote_in_J + s.excess_J, popc_energy_flow_out(&s.flow)));
	assert_false(popc_teleop_condition_holds(s.remote_in_J, popc_energy_flow_out(&s.flow)));
}

static void test_names(void **state)
{
	(void)state;
	assert_string_equal(popc_teleop_variant_name(1, POPC_DRIFT_OFF), "tdpa");
	assert_string_equal(popc_teleop_variant_name(0, POPC_DRIFT_OFF), "none");
	assert_string_equal(popc_teleop_variant_name(1, POPC_DRIFT_COELHO2018), "tdpa-coelho2018");
	assert_string_equal(popc_teleop_variant_name(0, POPC_DRIFT_ARTIGAS2010), "none-artigas2010");
	assert_string_equal(popc_drift_law_names[POPC_DRIFT_LAW_COUNT - 1], "coelho2018");
	assert_null(popc_drift_law_names[POPC_DRIFT_LAW_COUNT]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_laws),
		cmocka_unit_test(test_condition_random),
		cmocka_unit_test(test_excess),
		cmocka_unit_test(test_names),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
