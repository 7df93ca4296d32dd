/* What the teleoperation unit tests share (test_teleop.c, test_teleop_pp.c,
 * docs/TELEOPERATION.md): a scene of data/scenes, a run into a log, the
 * delay study over start offsets, a seeded random channel, and a log read
 * back cell by cell. Counts, never times. */
#ifndef POPC_TESTS_TELEOP_HARNESS_H
#define POPC_TESTS_TELEOP_HARNESS_H

#include <stddef.h>
#include <stdint.h>

#include "popc/run/run.h"
#include "popc/scene/scene.h"

/* Loads and validates data/scenes/NAME of the source tree. */
void teleop_load(popc_scene *s, const char *name);

/* Runs s (log to path unless NULL); returns the run's status. */
int teleop_run(const popc_scene *s, const char *path, popc_run_summary *sum);

/* The file's bytes, NUL-terminated (at most 16 MiB); the caller frees. */
char *teleop_slurp(const char *path, size_t *n);

/* Runs s with a zero-delay channel, then with teleop.link = direct, the PCs
 * off, each into a log in dir: the two logs are the same bytes but for the
 * resolved scene's link line (asserted), and longer than min_bytes. Returns
 * the channel run's log text (the caller frees). */
char *teleop_direct_equals_zero_delay(const popc_scene *s, const char *dir, size_t min_bytes);

/* qsort's order of doubles, ascending */
int teleop_cmp_double(const void *a, const void *b);

/* The delay study: round trip 2 d ticks at 1 kHz for d of
 * teleop_study_delays, start offsets operator.t0 = 0.1 s + i x 0.37 ms (the
 * contact at another phase of the tick and of the delay). A run that stopped
 * diverged, or whose slave still moves by more than TELEOP_OSC_PP_M peak to
 * peak over the last second, oscillates. */
#define TELEOP_STUDY_OFFSETS 20
#define TELEOP_OSC_PP_M 1e-3
extern const int teleop_study_delays[4];

typedef struct teleop_study_cell {
	int completed, oscillating, violations, clamped;
	double pp_m[TELEOP_STUDY_OFFSETS], fmax_N[TELEOP_STUDY_OFFSETS]; /* sorted */
} teleop_study_cell;

/* Runs base at delay d each way with the PCs pc_on over the offsets into c,
 * and prints its row of the study's table, headed by label. */
void teleop_study(const popc_scene *base, int d, int pc_on, const char *label, teleop_study_cell *c);

/* Draws each direction's channel (delay 0-299 ticks, jitter 0-59, loss up to
 * 0.6, in order or not, a seed) and the start time from rng. */
void teleop_random_channel(popc_scene *s, uint64_t *rng);

/* Reads the log at path back: every cell finite; returns its rows. */
long long teleop_rows_finite(const char *path);

#endif
