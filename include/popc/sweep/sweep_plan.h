/* The sweep planner (docs/SWEEPS.md): value lists and ranges, the cartesian
 * product, run ids, plan ids and shards (src/sweep/sweep_plan.c).
 *
 * A sweep is a base scene and a list of axes, each a scene key with a list of
 * values ("--vary operator.speed=0.01:0.1:10"). Its runs are the cartesian
 * product of the axes, the last axis varying fastest (nested loops in the
 * order the axes were given). Run i has the id "i" written with a fixed number
 * of digits (the width of n_runs - 1, at least 4), so ids sort as text in the
 * order of the product, are the same on every machine, and name the run's
 * directory DIR/runs/<id>/.
 *
 * Shard I of N (I from 1 to N, as the test runners Playwright, Jest and node
 * --test count shards) owns the runs with i mod N == I - 1: shards never overlap, cover
 * the sweep together, and each gets a slice of every region of the product,
 * which balances the load when one corner of the product runs slower. */
#ifndef POPC_SWEEP_PLAN_H
#define POPC_SWEEP_PLAN_H

#include <stddef.h>
#include <stdint.h>

#include "popc/scene/scene.h"
#include "popc/util/error.h"

/* Limits: a range has at most this many points, a sweep this many runs, and a
 * value this many characters. They bound memory and keep ids to 9 digits. */
#define POPC_SWEEP_RANGE_MAX 10000000L
#define POPC_SWEEP_RUNS_MAX 1000000000LL
#define POPC_SWEEP_VALUE_MAX 256
#define POPC_SWEEP_ID_MAX 16
#define POPC_SWEEP_BUILD_MAX 128

/* One --vary axis. */
typedef struct popc_sweep_axis {
	char section[64], key[64];
	char spec[POPC_SWEEP_VALUE_MAX * 2]; /* the text after '=' as given */
	int n_values;
	char **values;                       /* text applied with popc_scene_set */
} popc_sweep_axis;

/* The most --vary axes a plan takes. */
#define POPC_SWEEP_AXES_MAX 64

typedef struct popc_sweep_plan {
	popc_scene base;                 /* the resolved base scene */
	int n_axes;
	popc_sweep_axis *axes;
	int axis_key[POPC_SWEEP_AXES_MAX]; /* axes[a]'s scene key (popc_scene_key_index) */
	long long n_runs;
	int id_width;
	uint64_t plan_id;                /* FNV-1a of base scene text, axes and columns */
	char *columns;                   /* summary.csv header line, with '\n' (sweep_columns.h) */
	int teleop;                      /* 1: every run a teleoperation scene, whose
					  * table has the tele_* columns; 0: every
					  * run one-port (a mix is refused) */
	/* which popc made the plan: its version and build id (set by the program
	 * with popc_sweep_plan_set_build; read back by popc_sweep_plan_from_dir;
	 * "" when not recorded: a plan file of a popc before build ids). Not
	 * part of plan_id: another build runs the same sweep, and may resume it
	 * when asked (popc_sweep_dir_prepare). */
	char popc_version[64];
	char popc_build[POPC_SWEEP_BUILD_MAX];
} popc_sweep_plan;

/* Expands a range or list into values (no scene involved):
 *   "a,b,c"      a list (items may not be empty or hold '"' or newlines)
 *   "lo:hi:n"    n points from lo to hi, evenly spaced (hi exact)
 *   "lo:hi:n:log" n points from lo to hi, evenly spaced in log (lo, hi > 0)
 * Range points are written with 12 significant digits ("%.12g"), so that
 * 0:1:11 gives 0.3, not 0.30000000000000004, and a log range gives the same
 * text on machines whose libm exp/log differ in the last bit. Duplicate
 * values are an error. The caller frees with popc_sweep_values_free. */
int popc_sweep_expand(const char *spec, char ***values, int *n_values, popc_error *err);
void popc_sweep_values_free(char **values, int n_values);

/* Parses "section.key=LIST" into an axis (values expanded, key not checked). */
int popc_sweep_axis_parse(const char *vary, popc_sweep_axis *axis, popc_error *err);
void popc_sweep_axis_free(popc_sweep_axis *axis);

/* Builds a plan on the resolved base scene. Takes ownership of axes (an array
 * of n_axes parsed axes, freed by popc_sweep_plan_free even on error). Checks,
 * before anything runs: keys known and given once, every value accepted by
 * popc_scene_set for its key (the message names the key, the value and the
 * allowed range), the product within POPC_SWEEP_RUNS_MAX, and, when
 * check_every_run is set, every run's scene through popc_scene_validate, its
 * axis (the simulated one only) and every operator table the runs read (each
 * table once). */
int popc_sweep_plan_init(popc_sweep_plan *p, const popc_scene *base, popc_sweep_axis *axes,
			 int n_axes, int check_every_run, popc_error *err);
void popc_sweep_plan_free(popc_sweep_plan *p);

/* Records which popc makes the plan (cut to fit; a line break ends it). */
void popc_sweep_plan_set_build(popc_sweep_plan *p, const char *version, const char *build);

/* 1 when both plans were made by the same version and build. */
int popc_sweep_plan_same_build(const popc_sweep_plan *a, const popc_sweep_plan *b);

/* "popc 0.1.0 (build 2be9692abcde)", or words saying the plan records none. */
void popc_sweep_plan_describe_build(const popc_sweep_plan *p, char *buf, size_t cap);

/* The value index on every axis of run i (value_index has n_axes entries). */
void popc_sweep_run_values(const popc_sweep_plan *p, long long i, int *value_index);

/* The resolved scene of run i: base, then each axis' value, then validation. */
int popc_sweep_run_scene(const popc_sweep_plan *p, long long i, popc_scene *s, popc_error *err);

/* The id of run i (buf holds at least POPC_SWEEP_ID_MAX bytes). */
void popc_sweep_run_id(const popc_sweep_plan *p, long long i, char *buf);
/* Parses an id back; -1 when text is not an id of this plan. */
long long popc_sweep_id_parse(const popc_sweep_plan *p, const char *text);

/* Run i's values for messages: "section.key=value section.key=value ...",
 * cut to fit cap. */
void popc_sweep_run_describe(const popc_sweep_plan *p, long long i, char *buf, size_t cap);

/* FNV-1a 64-bit, the hash of plan ids. */
uint64_t popc_sweep_fnv1a(uint64_t h, const void *data, size_t n);
#define POPC_SWEEP_FNV_OFFSET 0xcbf29ce484222325ULL

/* ---- sharding ------------------------------------------------------------ */

typedef struct popc_sweep_shard {
	long long index, count;      /* index in [0, count): shard I/N has index I - 1 */
} popc_sweep_shard;

/* "I/N" with 1 <= I <= N (shard I/N gets index I - 1); "0/N" is refused with
 * a message that shards count from 1. */
int popc_sweep_shard_parse(const char *text, popc_sweep_shard *sh, popc_error *err);

/* The shard of a Slurm array task: index (SLURM_ARRAY_TASK_ID - MIN) / STEP
 * of SLURM_ARRAY_TASK_COUNT, i.e. shard (TASK_ID - MIN) / STEP + 1 of N, whatever
 * index the array starts at. Pass the four variables' values (NULL when
 * unset; min and step may be NULL). Returns 1 when id and count are set and
 * give a shard, 0 when they are not set, or a negative popc_status. */
int popc_sweep_shard_from_slurm(const char *task_id, const char *task_count, const char *task_min,
				const char *task_step, popc_sweep_shard *sh, popc_error *err);

static inline int popc_sweep_in_shard(const popc_sweep_shard *sh, long long i)
{
	return i % sh->count == sh->index;
}

#endif
