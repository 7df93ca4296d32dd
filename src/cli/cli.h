/* Shared helpers of the popc command-line verbs. */
#ifndef POPC_CLI_H
#define POPC_CLI_H

#include <signal.h>

#include "popc/util/error.h"
#include "popc/programs/arg_list.h" /* --set and --vary lists */
#include "popc/programs/options.h"
#include "popc/util/parse.h" /* every number an option takes */
#include "popc/scene/scene.h"

/* Set by every signal whose default would end popc (SIGINT, SIGTERM, SIGHUP,
 * SIGQUIT, ...: the list and the reasons are in cli_common.c); the run loop
 * polls it every tick (SIGPIPE and SIGXFSZ are ignored: write errors). */
extern volatile sig_atomic_t popc_cli_stop;
/* drive: a real axis is enabled during the run; SIGTSTP then ends the run
 * safely instead of suspending popc with the drive at its last force. */
void popc_cli_install_signals(int drive);

/* The command line popc was started with (main keeps it before any verb's
 * getopt permutes it): -j 1's sweep starts popc again with it after a crash
 * (sweep_crash.h). NULL before popc_cli_keep_argv. */
extern char **popc_cli_argv;
void popc_cli_keep_argv(int argc, char **argv);

/* Prints "popc: <msg>" to stderr and returns the exit code for status. */
int popc_cli_fail(const char *verb, int status, const popc_error *err);

/* Loads a scene file (or only defaults when path is NULL), applies the
 * --set assignments in order and validates. */
int popc_cli_load_scene(popc_scene *s, const char *path, char **sets, int n_sets, popc_error *err);

/* A scene key given by an option of its own (popc run --variant NAME is
 * controller.variant): its errors name the option. value NULL: not given. */
typedef struct popc_cli_key_option {
	const char *option, *section, *key, *value;
} popc_cli_key_option;

/* popc_cli_load_scene, then the key options (after --set: they win), then
 * validation. */
int popc_cli_load_scene_options(popc_scene *s, const char *path, char **sets, int n_sets,
				const popc_cli_key_option *opts, int n_opts, popc_error *err);

/* An assignment option's argument without '=' ("--set environment.stiffness
 * 2000": the shell gave two words, and the second would be taken for a second
 * SCENE file): says on stderr to give "OPTION KEY=VALUE" as one word, with the
 * word that followed it on the command line (popc_cli_argv) when there is
 * one, and returns 1 (the caller exits 2); 0 when every value has a '='. */
int popc_cli_assignment_split(const char *verb, const char *option, char *const *values, int n);

/* Whether the --set assignment "section.key=value" names this key (names
 * compared without the blanks around them, as popc_scene_set reads them). */
int popc_cli_set_names_key(const char *set, const char *section, const char *key);

/* Closes the open_memstream f (its text in *buf, *n) and writes the text to
 * DIR/NAME atomically; frees *buf either way. */
int popc_cli_commit_memstream(FILE *f, char **buf, size_t *n, const char *dir, const char *name,
			      popc_error *err);

/* Whether path is "-" (standard output) while popc started with descriptor 1
 * closed (stdfds.h): then says so on stderr, naming the option, and returns 1
 * (the caller exits 2 before anything runs). */
int popc_cli_stdout_closed(const char *verb, const char *option, const char *path);


/* This popc's version (meson's project version) and build id: git describe of
 * the source tree at build time, with a hash of the uncommitted diff when
 * dirty, "unknown" outside git (src/cli/popc_build_id.h.in). A sweep records
 * both and refuses to resume or merge with another build. */
const char *popc_cli_version(void);
const char *popc_cli_build_id(void);

/* The log header's provenance lines (provenance.c), malloc'd, NULL when out
 * of memory: "# popc_build = " the build id, "# date = " the time now in UTC
 * (ISO 8601, 2026-12-05T12:00:00Z) and "# command = " the command line as
 * started (popc_cli_argv), each argument as a shell reads it back. They
 * differ from run to run: whoever compares logs leaves out exactly these
 * three lines (README, "The log"). */
char *popc_cli_provenance(void);

/* getopt_long's arrays made from a verb's option tables (options.h): opts
 * and shorts of these sizes hold every verb's. */
#define POPC_CLI_MAX_OPTIONS 64
void popc_cli_getopt_tables(const popc_option *const *tables,
			    struct option opts[POPC_CLI_MAX_OPTIONS], char shorts[2 * POPC_CLI_MAX_OPTIONS]);

/* Each verb's option tables (its getopt_long's options, what `popc --complete`
 * lists): popc_main.c's verb table points at them. */
extern const popc_option *const popc_cli_run_opts[];
extern const popc_option *const popc_cli_scene_show_opts[];
extern const popc_option *const popc_cli_scene_keys_opts[];
extern const popc_option *const popc_cli_scene_list_opts[];
extern const popc_option *const popc_cli_scene_opts[];
extern const popc_option *const popc_cli_bench_opts[];
extern const popc_option *const popc_cli_sweep_opts[];
extern const popc_option *const popc_cli_sweep_merge_opts[];
extern const popc_option *const popc_cli_sweep_stats_opts[];
extern const popc_option *const popc_cli_map_opts[];

int popc_cmd_run(int argc, char **argv);
int popc_cmd_scene(int argc, char **argv);
int popc_cmd_bench(int argc, char **argv);
int popc_cmd_sweep(int argc, char **argv);
int popc_cmd_sweep_stats(int argc, char **argv); /* popc sweep stats (sweep_stats.c) */
int popc_cmd_map(int argc, char **argv);

#endif
