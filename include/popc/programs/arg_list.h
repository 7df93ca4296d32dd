/* A list of command-line arguments collected while options are parsed (every
 * --set, --vary, --column of popc and popc-analyze): the strings stay argv's,
 * the array grows as needed and is freed by the caller (free(list)). */
#ifndef POPC_PROGRAMS_ARG_LIST_H
#define POPC_PROGRAMS_ARG_LIST_H

/* Appends value to *list (*n entries). Returns 0, or -1 when out of memory
 * (the list is left as it was). */
int popc_arg_push(char ***list, int *n, char *value);

#endif
