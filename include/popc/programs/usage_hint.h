/* What a program says after a usage error: the error itself (getopt's, or the
 * caller's) and then ONE hint line, not the whole help, so that the error does
 * not scroll away. The hint names the nearest option or verb when one is close
 * (by edit distance over the program's own table) and where the help is:
 *
 *   popc run: unrecognized option '--varient'
 *   popc run: did you mean --variant? ('popc run --help' lists the options)
 *
 * Generic (tables of names, getopt's struct option); it prints and reads
 * getopt's globals, so it is the programs' (src/programs/), not the library's. */
#ifndef POPC_PROGRAMS_USAGE_HINT_H
#define POPC_PROGRAMS_USAGE_HINT_H

#include <getopt.h>
#include <stddef.h>

/* Optimal string alignment distance: insertions, deletions, substitutions and
 * transpositions of neighbours, one each. */
size_t popc_edit_distance(const char *a, const char *b);

/* The name nearest word, if it is close: at most 1 edit for words of up to 4
 * characters, 2 up to 8, 3 beyond (a third of the word, rounded up, at
 * most 3); the first of equals wins. NULL when none is close. */
const char *popc_nearest_name(const char *word, const char *const *names, size_t n);

/* After getopt_long returned '?' or ':' (it has printed the error): the hint
 * line on stderr. prog is argv[0] ("popc run"); opts the table given to
 * getopt_long; argv[optind - 1] is the element getopt just rejected. */
void popc_option_hint(const char *prog, const struct option *opts, int argc, char *const *argv);

/* The hint line alone, for a usage error the caller reported (a missing
 * operand): "<prog>: '<prog> --help' lists the <what>". */
void popc_help_hint(const char *prog, const char *what);

#endif
