/* The verb dispatcher of popc's programs ("popc run ...", "popc-analyze
 * energy ..."): one table of verbs, one usage text made from it, one
 * "unknown verb" error. Generic (it knows no verb); it prints, so it is the
 * programs' (src/programs/), never the library's;
 * only the programs' main() call it. */
#ifndef POPC_PROGRAMS_VERB_H
#define POPC_PROGRAMS_VERB_H

#include <stddef.h>
#include <stdio.h>

#include "popc/programs/options.h"

typedef struct popc_verb {
	const char *name;               /* "run" */
	int (*run)(int argc, char **argv); /* argv[0] is "<program> <verb>"; returns the exit code */
	const char *args;               /* its operands in the usage: "SCENE", "" */
	const char *summary;            /* one line: "run one experiment" */
	/* its option tables (options.h), NULL-terminated; NULL: none listed */
	const popc_option *const *options;
	/* its sub-verbs ("sweep merge"), which the verb's own run dispatches;
	 * listed by --complete only (their run is NULL) */
	const struct popc_verb *subs;
	size_t n_subs;
} popc_verb;

typedef struct popc_program {
	const char *name;     /* "popc": messages, --version */
	const char *version;
	const char *synopsis; /* after "usage: <name> ": "VERB [options]" */
	const char *about;    /* paragraph(s) between the usage line and the verbs */
	const char *footer;   /* after the verbs: where to read more, exit codes */
	const popc_verb *verbs;
	size_t n_verbs;
} popc_program;

/* Runs the verb argv[1] with argv[1..] (argv[1] replaced by "<name> <verb>",
 * so that getopt's messages name the program and the verb). "--help", "-h"
 * and "help" print the usage to stdout (exit 0), "--version" the version;
 * no verb prints the usage to stderr; an unknown one prints "<name>: unknown
 * verb 'X'" and one hint line (the nearest verb if one is close,
 * usage_hint.h); both return 2 (POPC_EXIT_USAGE). */
int popc_verb_dispatch(const popc_program *p, int argc, char **argv);

/* `PROGRAM --complete` (hidden: the bash completion and
 * tests/cli/test_options_agree.sh read it): "verb<TAB>PATH<TAB>ARGS" for each
 * verb and sub-verb ("sweep merge"), then its options (popc_options_complete). */
void popc_verb_complete(FILE *f, const popc_verb *verbs, size_t n, const char *parent);

#endif
