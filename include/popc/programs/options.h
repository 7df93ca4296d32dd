/* A verb's options as one table: what getopt_long parses (its struct option
 * and short letters are made from it), and what the completion offers and
 * tests/cli/test_options_agree.sh checks --help and the man pages against
 * (`PROGRAM --complete`, verb.h). One table per verb, so that the three
 * cannot drift from what the program takes (issue 27). Generic, so util. */
#ifndef POPC_UTIL_OPTIONS_H
#define POPC_UTIL_OPTIONS_H

#include <getopt.h>
#include <stdio.h>

typedef struct popc_option {
	const char *name; /* the long name without "--": "set" */
	char letter;      /* its short form, 'q' for -q; 0: none */
	int val;          /* what getopt_long returns for it (the letter, or a code >= 256) */
	/* NULL: no argument. Else the argument as --help writes it, which the
	 * completion reads: FILE, DIR, PATH (file names), SCENE, MAP (installed
	 * names and files), KEY=VALUE, KEY=LIST (scene keys, an enum key's
	 * names), VARIANT (controller.variant's names), URI, "a|b|c" (exactly
	 * these words), anything else (nothing to offer) */
	const char *arg;
} popc_option;

/* The end of a table. */
#define POPC_OPTION_END {NULL, 0, 0, NULL}

/* getopt_long's long options and short letters of the NULL-terminated list
 * of tables (a verb's own, then shared ones: popc-analyze's input options):
 * longs gets every entry and the {NULL} end (cap entries at most), shorts
 * the letters, with ':' after one that takes an argument. Returns 0, or -1
 * when they do not fit (a programming error: the caller's arrays are sized
 * for its tables). */
int popc_options_getopt(const popc_option *const *tables, struct option *longs, size_t cap,
			char *shorts, size_t shorts_cap);

/* The lines `PROGRAM --complete` prints for one verb (path "run", "sweep
 * merge"; "" for a program without verbs): "opt<TAB>PATH<TAB>-X<TAB>ARG" for
 * each short form and "opt<TAB>PATH<TAB>--NAME<TAB>ARG" for each long name
 * (ARG empty without an argument). */
void popc_options_complete(FILE *f, const char *path, const popc_option *const *tables);

#endif
