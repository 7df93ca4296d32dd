/* The call-cycle detector's own check (meson.build: call-cycles-detects):
 * call_cycles_fixture_a.c and call_cycles_fixture_b.c call each other, a
 * cycle the detector must report. */
#ifndef CALL_CYCLES_FIXTURE_H
#define CALL_CYCLES_FIXTURE_H

int call_cycles_fixture_a(int n);
int call_cycles_fixture_b(int n);

#endif
