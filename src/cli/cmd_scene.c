/* popc scene show FILE [--set k=v]...  |  popc scene keys */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "popc/core/intent.h"
#include "popc/scene/from_scene.h"

static void usage(FILE *f)
{
	fputs("usage: popc scene show [FILE] [--set section.key=value]...\n"
	      "       popc scene keys\n"
	      "\n"
	      "show  prints the resolved scene as INI, every default explicit: the scene\n"
	      "      file (or only the defaults, the paper's scene, without FILE) with the\n"
	      "      --set overrides applied and validated (an intent table is read too).\n"
	      "      Exit 2 names what is wrong: file:line, key and allowed range.\n"
	      "      Relative paths (operator.table, axis.map) are printed absolute: from\n"
	      "      the scene file's directory, or for --set from the working directory.\n"
	      "keys  lists every scene key with its default and allowed range.\n",
	      f);
}

int popc_cmd_scene(int argc, char **argv)
{
	if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
		usage(argc < 2 ? stderr : stdout);
		return argc < 2 ? 2 : 0;
	}
	int keys = strcmp(argv[1], "keys") == 0;
	if (!keys && strcmp(argv[1], "show") != 0) {
		fprintf(stderr, "popc scene: unknown action '%s'\n", argv[1]);
		usage(stderr);
		return 2;
	}
	static const struct option show_opts[] = {
		{"set", required_argument, NULL, 's'},
		{"help", no_argument, NULL, 'h'},
		{NULL, 0, NULL, 0},
	};
	const struct option *opts = show_opts + (keys ? 1 : 0); /* keys: --help only */
	char **sets = NULL;
	int n_sets = 0, c;
	optind = 1;
	argc--;
	argv++;
	static char prog_show[] = "popc scene show", prog_keys[] = "popc scene keys";
	argv[0] = keys ? prog_keys : prog_show; /* getopt's messages name argv[0] */
	while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
		switch (c) {
		case 's':
			if (popc_cli_push(&sets, &n_sets, optarg) != 0) {
				fprintf(stderr, "popc scene show: out of memory\n");
				free(sets);
				return 1;
			}
			break;
		case 'h': usage(stdout); free(sets); return 0;
		default: usage(stderr); free(sets); return 2;
		}
	}
	if (keys) {
		if (optind < argc) {
			fprintf(stderr, "popc scene keys: unexpected argument '%s'\n", argv[optind]);
			usage(stderr);
			return 2;
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
		return 2;
	}
	popc_scene s;
	popc_error err;
	int st = popc_cli_load_scene(&s, path, sets, n_sets, &err);
	free(sets);
	if (!st && s.intent == POPC_INTENT_TABLE) {
		/* the table is part of the scene: check it as popc run reads it */
		popc_intent in;
		st = popc_intent_from_scene(&in, &s, &err);
		popc_intent_free(&in);
	}
	if (st)
		return popc_cli_fail("scene show", st, &err);
	printf("; resolved scene%s%s\n", path ? " from " : " (defaults)", path ? path : "");
	popc_scene_write(&s, stdout, "");
	return 0;
}
