/* Standard descriptors 0-2 made safe at program start.
 *
 * A program started with 0, 1 or 2 closed (`2>&-`, a daemon manager, a
 * careless parent) gives that number to the next file or socket it opens;
 * then whatever it writes to stderr or stdout goes into that file or socket:
 * a log, or the Modbus connection to a drive. Every popc program calls
 * popc_stdfds_make_safe() first thing in main, before anything opens a file
 * or a socket: a closed 0-2 is reopened on /dev/null (its text is lost, not
 * misdirected), and the program remembers which were closed, so that a
 * request to write output to standard output that is not there (`--log -`
 * with `>&-`) can be refused instead of vanishing. */
#ifndef POPC_PROGRAMS_STDFDS_H
#define POPC_PROGRAMS_STDFDS_H

/* Reopens each closed descriptor 0, 1, 2 on /dev/null (0 for reading, 1 and
 * 2 for writing). Returns 0, or -1 when one could not be reopened (no
 * /dev/null): the caller must then exit, because a descriptor it opens next
 * could take that number. Idempotent: a second call changes nothing and
 * keeps what the first found. */
int popc_stdfds_make_safe(void);

/* Whether descriptor fd (0, 1 or 2) was closed when popc_stdfds_make_safe
 * ran (and now points to /dev/null). */
int popc_stdfds_was_closed(int fd);

#endif
