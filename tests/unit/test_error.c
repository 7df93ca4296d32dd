/* popc_error_name_params (util/error.h): a lower layer's parameter names in a
 * message replaced by what the user wrote, whole identifiers only, in one
 * pass, never past the message's size. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "popc/util/error.h"

static const popc_error_name names[] = {
	{"mass_kg", "(operator.mass + device.mass)"},
	{"period_s", "1 / run.rate"},
	{"window_s", "--threshold window=S"},
	{"loop", "loop loop"}, /* a name that holds its param: not read again */
};

static void names_whole_identifiers(void **state)
{
	(void)state;
	static const char *const cases[][2] = {
		{"M = mass_kg = 1 kg; raise mass_kg", "M = (operator.mass + device.mass) = 1 kg; raise "
						      "(operator.mass + device.mass)"},
		{"T = period_s", "T = 1 / run.rate"},
		{"(window_s, lc_window_s)", "(--threshold window=S, lc_window_s)"},
		{"mass_kgx xmass_kg mass_kg_2 mass_kg.", "mass_kgx xmass_kg mass_kg_2 "
							 "(operator.mass + device.mass)."},
		{"loop", "loop loop"},
		{"", ""},
		{"no parameter here", "no parameter here"},
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		popc_error err;
		popc_error_set(&err, POPC_ERR_INVALID, "%s", cases[i][0]);
		popc_error_name_params(&err, names, sizeof names / sizeof names[0]);
		assert_string_equal(err.msg, cases[i][1]);
	}
	popc_error_name_params(NULL, names, 1); /* no message: nothing to do */
}

static void names_cut_at_the_message_size(void **state)
{
	(void)state;
	popc_error err;
	memset(err.msg, 'a', sizeof err.msg - 10);
	memcpy(err.msg + sizeof err.msg - 10, " mass_kg", 9); /* with its '\0' */
	popc_error_name_params(&err, names, sizeof names / sizeof names[0]);
	assert_int_equal(strlen(err.msg), sizeof err.msg - 1);
	assert_memory_equal(err.msg + sizeof err.msg - 10, " (operato", 9);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(names_whole_identifiers),
		cmocka_unit_test(names_cut_at_the_message_size),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
