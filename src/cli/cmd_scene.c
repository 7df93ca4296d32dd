/* popc scene show FILE [--set k=v]...  |  popc scene keys  |  popc scene list [--maps] */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "popc/core/intent.h"
#include "popc/log/log_reader.h"
#include "popc/programs/env.h"
#include "popc/scene/data_path.h"
#include "popc/scene/from_scene.h"
#include "popc/programs/usage_hint.h"

static const popc_option list_options[] = {
	{"maps", 0, 'm', NULL},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
static const popc_option show_options[] = {
	{"set", 0, 's', "KEY=VALUE"},
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
static const popc_option help_options[] = {
	{"help", 'h', 'h', NULL},
	POPC_OPTION_END,
};
const popc_option *const popc_cli_scene_list_opts[] = {list_options, NULL};
const popc_option *const popc_cli_scene_show_opts[] = {show_options, NULL};
const popc_option *const popc_cli_scene_keys_opts[] = {help_options, NULL};
const popc_option *const popc_cli_scene_opts[] = {help_options, NULL};

static void usage(FILE *f)
{
	fputs("usage: popc scene show [FILE] [--set section.key=value]...\n"
	      "       popc scene keys\n"
	      "       popc scene list [--maps]\n"
	      "\n"
	      "show  prints the resolved scene as INI, every default explicit: the scene\n"
	      "      file (or only the defaults, the paper's scene, without FILE) with the\n"
	      "      --set overrides applied and validated (an intent table is read too).\n"
	      "      FILE may be a popc log: its header's scene, which popc run makes the\n"
	      "      log's rows again from, bit for bit.\n"
	      "      Exit 2 names what is wrong: file:line, key and allowed range.\n"
	      "      Relative paths (operator.table, axis.map) are printed absolute: from\n"
	      "      the scene file's directory, or for --set from the working directory.\n"
	      "keys  lists every scene key with its default and allowed range.\n"
	      "list  lists the installed scenes (--maps: the drive maps) that popc finds\n"
	      "      by name, one 'NAME<tab>PATH' a line: the data directories' scenes/\n"
	      "      (drives/), from POPC_DATA_PATH or the built-in directory.\n"
	      "\n"
	      "  --set section.key=value  show: override a scene key (repeatable)\n"
	      "  --maps                   list: the drive maps, not the scenes\n"
	      "  -h, --help               this help\n"
	      "\n"
	      "FILE (and popc run's SCENE, --map, axis.map) may be a name: one without a\n"
	      "'/' that is no file in the working directory (for axis.map in a scene file:\n"
	      "in the scene's directory) is looked up in each data directory as NAME, then\n"
	      "NAME.ini: 'popc run paper', '--map generic'. The path found is recorded\n"
	      "absolute. POPC_DATA_PATH=DIR[:DIR...] sets the data directories (an empty\n"
	      "entry stands for the built-in one); now: ",
	      f);
	char dirs[1024];
	popc_data_dirs(popc_env_data_path(), dirs, sizeof dirs);
	fprintf(f, "%s\n", dirs);
}

/* Whether path is a popc log: a file whose first line is "# popc log" (a
 * scene file never starts so: "#" lines are comments there). */
static int is_popc_log(const char *path)
{
	FILE *f = fopen(path, "r");
	if (!f)
		return 0;
	char line[16] = "";
	int yes = fgets(line, sizeof line, f) && strcmp(line, "# popc log\n") == 0;
	fclose(f);
	return yes;
}

/* The scene a popc log was run with, from its header (the whole resolved
 * scene: popc run writes every key), then the --set assignments, validated:
 * popc run of the result makes the log's rows again, bit for bit. */
static int load_log_scene(popc_scene *s, const char *path, char **sets, int n_sets, popc_error *err)
{
	popc_log_reader r;
	int st = popc_log_reader_open(&r, path, NULL, err);
	if (st)
		return st;
	st = popc_env_scene_defaults(s, err);
	if (!st)
		st = popc_log_reader_scene(&r, s, err);
	popc_log_reader_close(&r);
	snprintf(s->source, sizeof s->source, "%s", path);
	for (int i = 0; !st && i < n_sets; i++)
		st = popc_scene_set_assignment(s, sets[i], err);
	return st ? st : popc_scene_validate(s, err);
}

/* popc scene list [--maps]: what the names find (completion reads it) */
static int scene_list(int argc, char **argv)
{
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(popc_cli_scene_list_opts, opts, shorts);
	static char prog[] = "popc scene list";
	argv[0] = prog; /* getopt's messages name argv[0] */
	int maps = 0, c;
	optind = 1;
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case 'm': maps = 1; break;
		case 'h': usage(stdout); return 0;
		default: popc_option_hint(argv[0], opts, argc, argv); return POPC_EXIT_USAGE;
		}
	}
	if (optind < argc) {
		fprintf(stderr, "popc scene list: unexpected argument '%s'\n", argv[optind]);
		return POPC_EXIT_USAGE;
	}
	popc_data_list(maps ? POPC_DATA_DRIVES : POPC_DATA_SCENES, popc_env_data_path(), stdout, stderr,
		       "popc scene list");
	return fflush(stdout) == 0 && !ferror(stdout) ? POPC_EXIT_OK : POPC_EXIT_RUN_FAILED;
}

int popc_cmd_scene(int argc, char **argv)
{
	if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
		usage(argc < 2 ? stderr : stdout);
		return argc < 2 ? POPC_EXIT_USAGE : POPC_EXIT_OK;
	}
	int keys = strcmp(argv[1], "keys") == 0, list = strcmp(argv[1], "list") == 0;
	if (list)
		return scene_list(argc - 1, argv + 1);
	if (!keys && strcmp(argv[1], "show") != 0) {
		fprintf(stderr, "popc scene: unknown action '%s'\n", argv[1]);
		static const char *const actions[] = {"show", "keys", "list"};
		const char *near = popc_nearest_name(argv[1], actions, 3);
		if (near)
			fprintf(stderr, "popc scene: did you mean '%s'? ('popc scene --help' lists "
					"the actions)\n", near);
		else
			popc_help_hint("popc scene", "actions");
		return POPC_EXIT_USAGE;
	}
	struct option opts[POPC_CLI_MAX_OPTIONS];
	char shorts[2 * POPC_CLI_MAX_OPTIONS];
	popc_cli_getopt_tables(keys ? popc_cli_scene_keys_opts : popc_cli_scene_show_opts, opts, shorts);
	char **sets = NULL;
	int n_sets = 0, c;
	optind = 1;
	argc--;
	argv++;
	static char prog_show[] = "popc scene show", prog_keys[] = "popc scene keys";
	argv[0] = keys ? prog_keys : prog_show; /* getopt's messages name argv[0] */
	while ((c = getopt_long(argc, argv, shorts, opts, NULL)) != -1) {
		switch (c) {
		case 's':
			if (popc_arg_push(&sets, &n_sets, optarg) != 0) {
				fprintf(stderr, "popc scene show: out of memory\n");
				free(sets);
				return POPC_EXIT_RUN_FAILED;
			}
			break;
		case 'h': usage(stdout); free(sets); return 0;
		default: popc_option_hint(argv[0], opts, argc, argv); free(sets); return POPC_EXIT_USAGE;
		}
	}
	if (keys) {
		if (optind < argc) {
			fprintf(stderr, "popc scene keys: unexpected argument '%s'\n", argv[optind]);
			popc_help_hint(argv[0], "options");
			return POPC_EXIT_USAGE;
		}
		popc_scene_print_keys(stdout);
		return 0;
	}
	const char *path = NULL;
	if (optind < argc)
		path = argv[optind++];
	if (optind < argc) {
		fprintf(stderr, "popc scene show: unexpected argument '%s'\n", argv[optind]);
		free(sets);
		return POPC_EXIT_USAGE;
	}
	popc_scene s;
	popc_error err;
	int from_log = path && is_popc_log(path);
	int st = from_log ? load_log_scene(&s, path, sets, n_sets, &err)
			  : popc_cli_load_scene(&s, path, sets, n_sets, &err);
	free(sets);
	if (!st && s.intent == POPC_INTENT_TABLE) {
		/* the table is part of the scene: check it as popc run reads it */
		popc_intent in;
		st = popc_intent_from_scene(&in, &s, &err);
		popc_intent_free(&in);
	}
	if (st)
		return popc_cli_fail("scene show", st, &err);
	/* s.source: the file read (an installed scene's absolute path when
	 * found by name) */
	printf("; resolved scene%s%s\n", !path ? " (defaults)" : from_log ? " of the log " : " from ",
	       path ? s.source : "");
	popc_scene_write(&s, stdout, "");
	return 0;
}
