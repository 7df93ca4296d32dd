/* Line reader for libinih's ini_parse_stream that knows the real line number
 * and refuses a line that does not fit libinih's buffer (private to libpopc).
 *
 * libinih reads a file in pieces of its buffer size (INI_MAX_LINE, 200 bytes
 * in Debian's build): a longer line comes back split, each piece counted and
 * parsed as a line of its own, so the tail of a comment can set a key and
 * every later message names the wrong line. Blanks at the start of a line
 * are dropped, so that an indented key is a key: libinih would otherwise
 * take it for a continuation of the previous key's value. */
#ifndef POPC_INI_LINES_H
#define POPC_INI_LINES_H

#include <stdio.h>

/* Reads one line of f into str (num bytes, as libinih asks) and counts it in
 * *line. Returns str, or NULL at the end of the file, on a read error (see
 * ferror(f)), or when the line is longer than num - 1 characters, its newline
 * excluded (a CR LF ending counts as the newline): then *too_long = 1 and
 * *line is that line's number; likewise *too_long = 2 for a line holding a
 * NUL byte (libinih would read it up to the NUL: no text file). Leading
 * blanks are removed from str. */
char *popc_ini_read_line(char *str, int num, FILE *f, int *line, int *too_long);

/* Whether a line popc_ini_read_line returned holds a carriage return that
 * does not end it (one before the LF, or at the very end of the file, does):
 * a file with CR-only line ends (classic Mac OS) is one line to libinih, which
 * reads its first "[section]" and drops the rest, so such a scene read as the
 * defaults. The readers refuse it with POPC_INI_BARE_CR_WHY. */
int popc_ini_line_has_bare_cr(const char *line);
#define POPC_INI_BARE_CR_WHY                                                                     \
	"a carriage return (CR) inside the line: lines end with LF or CR LF; a file with CR-only " \
	"line ends (classic Mac OS) reads as one line (convert it: tr '\\r' '\\n')"

#endif
