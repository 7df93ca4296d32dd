/* popc sweep SCENE --vary KEY=LIST... -o DIR [-j N] [--shard I/N] [--list]
 * popc sweep merge DIR... [-o DIR]
 *
 * The options and the order of things: plan and check every run, prepare the
 * directory, find what a resumed sweep still has to run, run it, gather
 * summary.csv, list the failures, choose the exit status. The planner, ids,
 * shards, rows and results are in the library (popc/sweep/sweep.h); the worker
 * pool that makes the runs in sweep_pool.c, the progress display in
 * sweep_progress.c, the --list command lines in sweep_list.c. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <getopt.h>
#include <inttypes.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "popc/programs/env.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_lock.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/sweep/sweep_results.h"
#include "popc/util/atomic_file.h"
#include "popc/util/text.h"
#include "sweep_dry_run.h"
#include "sweep_list.h"
#include "sweep_pool.h"
#include "sweep_progress.h"
#include "popc/programs/usage_hint.h"

static void usage(FILE *f)
{
	fputs("usage: popc sweep SCENE --vary section.key=LIST [--vary ...] -o DIR [options]\n"
	      "       popc sweep merge DIR... [-o DIR] [--allow-other-build]\n"
	      "       popc sweep stats DIR --by KEY[,KEY...] [--metrics ...] [--format ...]\n"
	      "\n"
	      "Runs the cartesian product of the --vary lists on the scene, in parallel, and\n"
	      "writes DIR/summary.csv: one row per run with its id, the varied values, its exit\n"
	      "status, the compare metrics and its wall time (last column). Each run has a\n"
	      "directory DIR/runs/<id> with its resolved scene, log and summary. Running the\n"
	      "same sweep into the same DIR again skips finished runs and retries failed ones.\n"
	      "SCENE may be an installed scene's name, as for popc run ('popc run --help').\n"
	      "\n"
	      "  --vary section.key=LIST  a scene key and its values (repeatable; the last\n"
	      "                           --vary varies fastest). LIST is a,b,c or a range\n"
	      "                           lo:hi:n (n evenly spaced points, ends included) or\n"
	      "                           lo:hi:n:log (evenly spaced in log); e.g.\n"
	      "                           --vary controller.variant=none,ref-energy,improved\n"
	      "                           --vary encoder.resolution=1e-6:1e-4:5:log\n"
	      "  --set section.key=value  a fixed override of the base scene (repeatable)\n"
	      "                           (a relative operator.table here or in --vary is\n"
	      "                           from the working directory; in the scene file,\n"
	      "                           from the file's directory; each run's scene.ini\n"
	      "                           names it absolute)\n"
	      "  -o, --output DIR         the sweep directory (created if needed)\n"
	      "  -j, --jobs N             parallel runs (default: SLURM_CPUS_PER_TASK, else\n"
	      "                           every online core). -j N makes runs in this\n"
	      "                           process beside N - 1 worker processes; if one\n"
	      "                           crashes it, the rows so far are kept, the workers\n"
	      "                           stopped, and popc goes on as with --isolate\n"
	      "  --isolate                make the runs in N worker processes only\n"
	      "  --no-log                 keep run summaries only (no log.csv, no scene.ini)\n"
	      "  --shard I/N              run only shard I of N, I from 1 to N (runs with\n"
	      "                           id mod N = I - 1): --shard 1/2 and --shard 2/2 make\n"
	      "                           the whole sweep. Default from SLURM_ARRAY_TASK_ID,\n"
	      "                           _MIN, _STEP and _COUNT when set (the array's first\n"
	      "                           task is shard 1, whatever its index). A shard\n"
	      "                           writes DIR/summary-shard-I-of-N.csv\n"
	      "  --list                   print one 'popc run' command line per run of the\n"
	      "                           shard (for GNU parallel) instead of running; each\n"
	      "                           runs the run's resolved scene, written now to\n"
	      "                           DIR/runs/<id>/scene.ini (later edits of SCENE do\n"
	      "                           not reach it); then 'popc sweep merge DIR'\n"
	      "                           gathers their results\n"
	      "  --dry-run                print the plan and its runs (one 'ID<TAB>values' line\n"
	      "                           each, of the shard) and what DIR holds (a resume?),\n"
	      "                           and write nothing: no DIR, plan, lock or run\n"
	      "                           directory (--list writes each run's scene.ini)\n"
	      "  --program PATH           the popc that --list lines call (default: this one)\n"
	      "  --allow-other-build      resume (or merge) a sweep that another popc version\n"
	      "                           or build made; refused otherwise (exit 2), since\n"
	      "                           the summary would mix two builds' results. The\n"
	      "                           plan records every build that added results\n"
	      "  -q, --quiet              no progress\n"
	      "  -h, --help               this help\n"
	      "\n",
	      f);
	/* its own string: C99 promises 4095 characters */
	fputs("stats: median, quartiles and range of the metrics per group of runs\n"
	      "('popc sweep stats --help').\n"
	      "\n"
	      "merge: gathers the runs of shard outputs (or of --list runs) into one\n"
	      "summary.csv in DIR (default: the first DIR), equal to a one-machine sweep's but\n"
	      "for the wall_time_s column.\n"
	      "\n"
	      "Exit status: 0 every run succeeded, 1 some run failed (listed) or has no result,\n"
	      "2 bad scene, --vary or usage (nothing ran), 5 interrupted (finished runs kept).\n"
	      "docs/SWEEPS.md: Slurm job arrays, GNU parallel, resuming, merging.\n",
	      f);
}

enum { OPT_VARY = 256, OPT_SET, OPT_NO_LOG, OPT_SHARD, OPT_LIST, OPT_PROGRAM, OPT_ALLOW_OTHER_BUILD,
       OPT_ISOLATE, OPT_DRY_RUN };

static const popc_option sweep_options[] = {
	{"vary", 0, OPT_VARY, "KEY=LIST"},
	{"set", 0, OPT_SET, "KEY=VALUE"},
	{"output", 'o', 'o', "DIR"},
	{"jobs", 'j', 'j', "N"},
	{"isolate", 0, OPT_ISOLATE, NULL},
	{"no-log", 0, OPT_NO_LOG, NULL},
	{"shard", 0, OPT_SHARD, "I/N"},
	{"list", 0, OPT_LIST, NULL},
	{"dry-run", 0, OPT_DRY_RUN, NULL},
	{"program", 0, OPT_PROGRAM, "FILE"},
	{"allow-other-build", 0, OPT_ALLOW_OTHER_BUILD, NULL},
	{"quiet", 'q', 'q', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
static const popc_option merge_options[] = {
	{"output", 'o', 'o', "DIR"},
	{"allow-other-build", 0, OPT_ALLOW_OTHER_BUILD, NULL},
	{"quiet", 'q', 'q', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const popc_cli_sweep_opts[] = {sweep_options, NULL};
const popc_option *const popc_cli_sweep_merge_opts[] = {merge_options, NULL};

/* ---- failures listed at the end ------------------------------------------------- */

typedef struct failure_list {
	const popc_sweep_plan *plan;
	int list_missing;             /* name runs without a result too */
	long long shown, failed, missing;
} failure_list;

enum { FAILURES_SHOWN = 30 };

static void list_failure(void *user, long long i, int exit_status, const char *reason)
{
	failure_list *fl = user;
	if (exit_status < 0)
		fl->missing++;
	else
		fl->failed++;
	if ((exit_status < 0 && !fl->list_missing) || fl->shown >= FAILURES_SHOWN)
		return;
	if (fl->shown == 0)
		fprintf(stderr, "popc sweep: failed runs:\n");
	fl->shown++;
	char id[POPC_SWEEP_ID_MAX], what[512];
	popc_sweep_run_id(fl->plan, i, id);
	popc_sweep_run_describe(fl->plan, i, what, sizeof what);
	if (exit_status < 0)
		fprintf(stderr, "  %s (%s): no result\n", id, what);
	else
		fprintf(stderr, "  %s (%s): exit %d: %s\n", id, what, exit_status,
			reason[0] ? reason : "(no reason recorded)");
}

/* Notes from reading rows files (a header cut by a kill): not errors. */
static void show_notes(const char *verb, const popc_sweep_results *r, int quiet)
{
	if (quiet || r->n_notes == 0)
		return;
	fprintf(stderr, "popc %s: note: %s\n", verb, r->note);
	if (r->n_notes > 1)
		fprintf(stderr, "popc %s: note: and %d more rows files with a note\n", verb,
			r->n_notes - 1);
}

/* ---- the verbs ---------------------------------------------------------------------- */

static void abs_path(const char *path, char *out, size_t cap)
{
	char *r = realpath(path, NULL);
	snprintf(out, cap, "%s", r ? r : path);
	free(r);
}

static int cmd_merge(int argc, char **argv)
{
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_sweep_merge_opts, opts, shorts);
	const char *out = NULL;
	int quiet = 0, allow_other_build = 0, c;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case 'o': out = optarg; break;
		case OPT_ALLOW_OTHER_BUILD: allow_other_build = 1; break;
		case 'q': quiet = 1; break;
		case 'h': usage(stdout); return 0;
		default: popc_option_hint(argv[0], opts, argc, argv); return POPC_EXIT_USAGE;
		}
	}
	if (optind >= argc) {
		fprintf(stderr, "popc sweep merge: no sweep directory given\n");
		return POPC_EXIT_USAGE;
	}
	const char *const *dirs = (const char *const *)argv + optind;
	int n_dirs = argc - optind;
	popc_error err;
	if (out && popc_sweep_output_dir_check("-o", out, &err) != 0)
		return popc_cli_fail("sweep merge", POPC_ERR_INVALID, &err);
	if (!out)
		out = dirs[0];
	popc_sweep_plan plan;
	if (popc_sweep_plan_from_dir(&plan, dirs[0], &err) != 0)
		return popc_cli_fail("sweep merge", POPC_ERR_INVALID, &err);
	/* the other builds among the directories, noted in the output's plan */
	popc_sweep_plan *builds = calloc((size_t)n_dirs, sizeof *builds);
	int n_builds = 0;
	if (!builds) {
		popc_sweep_plan_free(&plan);
		fprintf(stderr, "popc sweep merge: out of memory\n");
		return POPC_EXIT_RUN_FAILED;
	}
	for (int d = 1; d < n_dirs; d++) {
		popc_sweep_plan other;
		if (popc_sweep_plan_from_dir(&other, dirs[d], &err) != 0) {
			popc_sweep_plan_free(&plan);
			free(builds);
			return popc_cli_fail("sweep merge", POPC_ERR_INVALID, &err);
		}
		uint64_t id = other.plan_id;
		int same_build = popc_sweep_plan_same_build(&plan, &other);
		char first[POPC_SWEEP_BUILD_MAX + 96], this[POPC_SWEEP_BUILD_MAX + 96];
		popc_sweep_plan_describe_build(&plan, first, sizeof first);
		popc_sweep_plan_describe_build(&other, this, sizeof this);
		if (!same_build) {
			int known = 0;
			for (int b = 0; b < n_builds; b++)
				known |= popc_sweep_plan_same_build(&builds[b], &other);
			if (!known)
				popc_sweep_plan_set_build(&builds[n_builds++], other.popc_version,
							  other.popc_build);
		}
		popc_sweep_plan_free(&other);
		if (id == plan.plan_id && !same_build && !allow_other_build) {
			fprintf(stderr,
				"popc sweep merge: %s was made by %s, %s by %s: the summary would mix "
				"two builds' results; merge shards of one build, or give "
				"--allow-other-build (the merged plan then records both)\n",
				dirs[0], first, dirs[d], this);
			popc_sweep_plan_free(&plan);
			free(builds);
			return POPC_EXIT_USAGE;
		}
		if (id != plan.plan_id) {
			fprintf(stderr,
				"popc sweep merge: %s and %s hold different sweeps (plans %016" PRIx64
				" and %016" PRIx64 ")\n",
				dirs[0], dirs[d], plan.plan_id, id);
			popc_sweep_plan_free(&plan);
			free(builds);
			return POPC_EXIT_USAGE;
		}
	}
	/* the output directory gets the plan too, so that it is a sweep
	 * directory itself (merge and resume read it) */
	int is_input = 0;
	for (int d = 0; d < n_dirs; d++)
		is_input |= strcmp(out, dirs[d]) == 0;
	if (!is_input) {
		char src[POPC_PATH_MAX + 32], dst[POPC_PATH_MAX + 32];
		snprintf(dst, sizeof dst, "%s/sweep.plan", out);
		snprintf(src, sizeof src, "%s/sweep.plan", dirs[0]);
		FILE *f = fopen(src, "rb");
		char buf[1 << 16];
		size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
		if (f)
			fclose(f);
		struct stat sb;
		int st = popc_mkdir_p(out, &err);
		if (!st && stat(dst, &sb) != 0)
			st = popc_write_file_atomic(dst, buf, n, &err);
		if (!st) {
			popc_sweep_plan o;
			st = popc_sweep_plan_from_dir(&o, out, &err);
			if (!st && o.plan_id != plan.plan_id)
				st = popc_error_set(&err, POPC_ERR_INVALID, "%s holds another sweep", out);
			if (!st)
				popc_sweep_plan_free(&o);
		}
		if (st) {
			popc_sweep_plan_free(&plan);
			free(builds);
			return popc_cli_fail("sweep merge", st, &err);
		}
	}
	/* every build whose results the merged summary holds, in its plan
	 * (--allow-other-build; each call is a no-op for the plan's maker) */
	int note_st = popc_sweep_dir_note_build(&plan, out, &err);
	for (int b = 0; b < n_builds && !note_st; b++)
		note_st = popc_sweep_dir_note_build(&builds[b], out, &err);
	free(builds);
	if (note_st) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep merge", note_st, &err);
	}
	char path[POPC_PATH_MAX + 32];
	snprintf(path, sizeof path, "%s/summary.csv", out);
	popc_sweep_tally t;
	failure_list fl = {.plan = &plan};
	popc_sweep_results res;
	int st = popc_sweep_results_load(&res, &plan, dirs, n_dirs, 1, &err);
	if (!st) {
		show_notes("sweep merge", &res, quiet);
		st = popc_sweep_results_write(&res, &plan, NULL, path, &t, list_failure, &fl, &err);
		popc_sweep_results_free(&res);
	}
	popc_sweep_plan_free(&plan);
	if (st)
		return popc_cli_fail("sweep merge", st, &err);
	if (!quiet || t.failed || t.missing)
		fprintf(stderr, "popc sweep merge: %s: %lld of %lld runs, %lld failed, %lld without a result\n",
			path, t.ok + t.failed, t.planned, t.failed, t.missing);
	return t.failed || t.missing ? POPC_EXIT_RUN_FAILED : POPC_EXIT_OK;
}

/* The command line of a sweep (not merge), checked. */
typedef struct sweep_args {
	char **vary, **sets;          /* pointers into argv */
	int n_vary, n_sets;
	int quiet, keep_log, list, allow_other_build, isolate, dry_run;
	long long jobs;               /* 0: sweep_pool_default_jobs() */
	const char *scene_path, *dir, *shard_text, *program;
} sweep_args;

/* Plans, checks and runs (or lists) the sweep of a checked command line. */
static int sweep_main(const sweep_args *a)
{
	/* plan everything, and check every run's scene, before anything runs.
	 * The base scene is not validated alone: it need not be a scene of its
	 * own (--set operator.intent=table --vary operator.table=a.csv,b.csv),
	 * and every run's scene is validated, naming the run. */
	popc_scene base;
	popc_error err;
	/* an -o that cannot be a directory of files is bad usage, said before
	 * anything is read or made */
	int st = popc_sweep_output_dir_check("-o", a->dir, &err);
	if (st)
		return popc_cli_fail("sweep", st, &err);
	st = popc_env_scene_defaults(&base, &err);
	if (!st)
		st = popc_scene_load(&base, a->scene_path, &err);
	for (int m = 0; m < a->n_sets && !st; m++)
		st = popc_scene_set_assignment(&base, a->sets[m], &err);
	if (st)
		return popc_cli_fail("sweep", st, &err);
	int n_vary = a->n_vary;
	popc_sweep_axis *axes = calloc((size_t)n_vary, sizeof *axes);
	if (!axes) {
		fprintf(stderr, "popc sweep: out of memory\n");
		return POPC_EXIT_RUN_FAILED;
	}
	for (int k = 0; k < n_vary && !st; k++)
		st = popc_sweep_axis_parse(a->vary[k], &axes[k], &err);
	for (int k = 0; k < n_vary && !st; k++)
		for (int m = 0; m < a->n_sets && !st; m++)
			if (popc_cli_set_names_key(a->sets[m], axes[k].section, axes[k].key))
				st = popc_error_set(&err, POPC_ERR_INVALID,
						    "--set %s and --vary %s.%s=%s: the key is both fixed "
						    "and varied; give it once",
						    a->sets[m], axes[k].section, axes[k].key, axes[k].spec);
	popc_sweep_plan plan;
	if (st) {
		for (int k = 0; k < n_vary; k++)
			popc_sweep_axis_free(&axes[k]);
		free(axes);
		return popc_cli_fail("sweep", st, &err);
	}
	st = popc_sweep_plan_init(&plan, &base, axes, n_vary, 1, &err);
	/* popc run's summary row has no tele_* cells: a teleoperation sweep's
	 * rows are made from the summary in the sweep's own process */
	if (!st && plan.teleop && a->list)
		st = popc_error_set(&err, POPC_ERR_INVALID,
				    "--list: a teleoperation sweep makes its tele_* columns from each "
				    "run's summary in its own process; run it without --list (with "
				    "--shard I/N on each machine)");
	if (st) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	popc_sweep_plan_set_build(&plan, popc_cli_version(), popc_cli_build_id());

	popc_sweep_shard shard;
	st = sweep_pool_shard(a->shard_text, &shard, &err);
	if (st < 0) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	if (a->dry_run) {
		/* before the directory is opened: nothing is made, locked or written */
		int r = sweep_dry_run_print(&plan, &shard, a->dir);
		popc_sweep_plan_free(&plan);
		return r;
	}
	char scene_abs[PATH_MAX], dir_abs[PATH_MAX];
	abs_path(base.source, scene_abs, sizeof scene_abs); /* an installed scene's, when found by name */
	st = popc_sweep_dir_open(&plan, a->dir, scene_abs, a->allow_other_build, &shard, &err);
	if (st < 0) {
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	if (st == 1 && !a->quiet) {
		char this[POPC_SWEEP_BUILD_MAX + 96];
		popc_sweep_plan_describe_build(&plan, this, sizeof this);
		fprintf(stderr, "popc sweep: note: %s was made by another popc build; resuming with "
				"%s (--allow-other-build), recorded in its sweep.plan\n",
			a->dir, this);
	}
	abs_path(a->dir, dir_abs, sizeof dir_abs);
	if (a->list) {
		char self[PATH_MAX];
		const char *program = a->program;
		if (!program) {
			ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
			self[n > 0 ? n : 0] = '\0';
			program = n > 0 ? self : "popc";
		}
		int r = sweep_list_print(&plan, &shard, program, dir_abs);
		popc_sweep_plan_free(&plan);
		return r;
	}

	/* resume: finished runs are skipped, failed ones run again */
	long long n_shard = 0, n_todo = 0;
	for (long long i = 0; i < plan.n_runs; i++)
		n_shard += popc_sweep_in_shard(&shard, i);
	long long *todo = malloc((size_t)(n_shard ? n_shard : 1) * sizeof *todo);
	if (!todo) {
		popc_sweep_plan_free(&plan);
		fprintf(stderr, "popc sweep: out of memory\n");
		return POPC_EXIT_RUN_FAILED;
	}
	const char *dirs[1] = {a->dir};
	popc_sweep_results res;
	st = popc_sweep_results_load(&res, &plan, dirs, 1, 1, &err);
	if (st) {
		free(todo);
		popc_sweep_plan_free(&plan);
		return popc_cli_fail("sweep", st, &err);
	}
	for (long long i = 0; i < plan.n_runs; i++)
		if (popc_sweep_in_shard(&shard, i) && !(res.run[i].row && res.run[i].exit_status == 0))
			todo[n_todo++] = i;
	popc_sweep_results_free(&res);

	sweep_pool_config pool = {.plan = &plan, .dir = a->dir, .keep_log = a->keep_log,
				  .jobs = a->jobs > 0 ? (int)a->jobs : sweep_pool_default_jobs(), .rows_pid = 0,
				  .die_after_claim = -1, .crash_at = -1, .interrupt_after = -1, .isolate = a->isolate};
	sweep_pool_test_hooks(&pool);
	sweep_progress prog;
	sweep_progress_start(&prog, a->quiet, n_shard, n_shard - n_todo);
	if (!a->quiet && n_shard - n_todo > 0)
		fprintf(stderr, "popc sweep: %lld of %lld runs already done in %s\n", n_shard - n_todo,
			n_shard, a->dir);
	popc_cli_install_signals(0); /* the simulated axis only */
	int trouble = n_todo > 0 ? sweep_pool_run(&pool, todo, n_todo, &prog) : 0;
	free(todo);
	double elapsed = sweep_progress_elapsed_s(&prog);

	/* summary.csv from the run files, in id order, renamed into place: an
	 * interrupted sweep leaves the last whole one */
	char path[POPC_PATH_MAX + 64];
	if (shard.count > 1)
		snprintf(path, sizeof path, "%s/summary-shard-%lld-of-%lld.csv", a->dir,
			 shard.index + 1, shard.count);
	else
		snprintf(path, sizeof path, "%s/summary.csv", a->dir);
	popc_sweep_tally t;
	/* not interrupted, every run of the shard should have a result: name
	 * any that has none (a row that could not be written, a worker that
	 * could not be started) */
	failure_list fl = {.plan = &plan, .list_missing = !popc_cli_stop};
	st = popc_sweep_results_load(&res, &plan, dirs, 1, 1, &err);
	if (!st) {
		show_notes("sweep", &res, a->quiet);
		st = popc_sweep_results_write(&res, &plan, &shard, path, &t, list_failure, &fl, &err);
		popc_sweep_results_free(&res);
	}
	popc_sweep_plan_free(&plan);
	if (st)
		return popc_cli_fail("sweep", st, &err);
	long long listed = fl.failed + (fl.list_missing ? fl.missing : 0);
	if (fl.shown < listed)
		fprintf(stderr, "  ... and %lld more (exit_status in %s)\n", listed - fl.shown, path);
	if (!a->quiet || t.failed || t.missing)
		fprintf(stderr,
			"popc sweep: %s: %lld runs, %lld succeeded, %lld failed, %lld not run; "
			"%lld run now in %.3g s\n",
			path, t.planned, t.ok, t.failed, t.missing, prog.done_now, elapsed);
	if (popc_cli_stop) {
		fprintf(stderr, "popc sweep: interrupted; run the same command again to resume\n");
		return POPC_EXIT_INTERRUPTED;
	}
	return trouble || t.failed || t.missing ? POPC_EXIT_RUN_FAILED : 0;
}

int popc_cmd_sweep(int argc, char **argv)
{
	if (argc >= 2 && strcmp(argv[1], "stats") == 0) {
		static char prog[] = "popc sweep stats";
		argv[1] = prog;
		return popc_cmd_sweep_stats(argc - 1, argv + 1);
	}
	if (argc >= 2 && strcmp(argv[1], "merge") == 0) {
		static char prog[] = "popc sweep merge"; /* getopt's messages name argv[0] */
		argv[1] = prog;
		return cmd_merge(argc - 1, argv + 1);
	}
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_sweep_opts, opts, shorts);
	sweep_args a = {.keep_log = 1};
	int c, rc = -1, oom = 0;
	optind = 1;
	while (rc < 0 && (c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case OPT_VARY: oom |= popc_arg_push(&a.vary, &a.n_vary, optarg); break;
		case OPT_SET: oom |= popc_arg_push(&a.sets, &a.n_sets, optarg); break;
		case 'o': a.dir = optarg; break;
		case 'j':
			if (popc_parse_ll_text(optarg, 1, 4096, &a.jobs) != 0) {
				fprintf(stderr, "popc sweep: -j '%s': a whole number in [1, 4096]\n", optarg);
				rc = POPC_EXIT_USAGE;
			}
			break;
		case OPT_NO_LOG: a.keep_log = 0; break;
		case OPT_SHARD: a.shard_text = optarg; break;
		case OPT_LIST: a.list = 1; break;
		case OPT_DRY_RUN: a.dry_run = 1; break;
		case OPT_PROGRAM: a.program = optarg; break;
		case OPT_ALLOW_OTHER_BUILD: a.allow_other_build = 1; break;
		case OPT_ISOLATE: a.isolate = 1; break;
		case 'q': a.quiet = 1; break;
		case 'h': usage(stdout); rc = 0; break;
		default: popc_option_hint(argv[0], opts, argc, argv); rc = POPC_EXIT_USAGE; break;
		}
	}
	if (rc < 0 && !oom && (popc_cli_assignment_split("sweep", "--set", a.sets, a.n_sets) ||
				popc_cli_assignment_split("sweep", "--vary", a.vary, a.n_vary)))
		rc = POPC_EXIT_USAGE;
	if (rc < 0) {
		/* options that would be silently ignored are refused */
		const char *why = optind >= argc       ? "missing SCENE file"
				  : optind + 1 != argc ? "more than one SCENE file"
				  : !a.dir             ? "missing -o DIR"
				  : !a.dir[0]          ? "-o '': give a directory name"
				  : a.n_vary == 0      ? "nothing to vary: give --vary section.key=LIST"
				  : a.list && !a.keep_log
					  ? "--no-log does not apply to --list: every listed popc run "
					    "keeps its log (merge computes the chatter columns from it)"
				  : a.list && a.jobs
					  ? "-j does not apply to --list: give GNU parallel its own --jobs"
				  : a.list && a.isolate
					  ? "--isolate does not apply to --list: each listed popc run is "
					    "a process of its own"
				  : a.program && !a.list
					  ? "--program applies to --list only (the popc the listed lines "
					    "call); a sweep runs in this process"
				  : a.dry_run && a.list
					  ? "--dry-run and --list: --list writes each run's scene.ini; "
					    "give one of them"
					  : NULL;
		if (oom) {
			fprintf(stderr, "popc sweep: out of memory\n");
			rc = POPC_EXIT_RUN_FAILED;
		} else if (why) {
			fprintf(stderr, "popc sweep: %s\n", why);
			popc_help_hint(argv[0], "options");
			rc = POPC_EXIT_USAGE;
		} else {
			a.scene_path = argv[optind];
			rc = sweep_main(&a);
		}
	}
	free(a.vary);
	free(a.sets);
	return rc;
}
