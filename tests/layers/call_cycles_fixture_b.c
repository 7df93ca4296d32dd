/* The other half of the fixture cycle (call_cycles_fixture.h). */
#include "call_cycles_fixture.h"

int call_cycles_fixture_b(int n)
{
	return n > 0 ? call_cycles_fixture_a(n - 1) : 1;
}
