/* Fuzz harnesses of popc's input parsers (tests/README.md, "Fuzzing").
 *
 * Each harness takes one input (data, size), feeds it to the library the way
 * the programs do, and checks the properties that hold for every input; a
 * broken property is reported by popc_fuzz_fail, which aborts, so that
 * libFuzzer (run-fuzz.sh) and the corpus replay (replay_main.c, a meson test)
 * both see it. The harnesses never write outside their memory files. */
#ifndef POPC_FUZZ_H
#define POPC_FUZZ_H

#include <stddef.h>
#include <stdint.h>

typedef int (*popc_fuzz_fn)(const uint8_t *data, size_t size);

int popc_fuzz_numfmt_parse(const uint8_t *data, size_t size);
int popc_fuzz_numfmt_format(const uint8_t *data, size_t size);
int popc_fuzz_log_reader(const uint8_t *data, size_t size);
int popc_fuzz_analyze_input(const uint8_t *data, size_t size);
int popc_fuzz_scene(const uint8_t *data, size_t size);
int popc_fuzz_ini_lines(const uint8_t *data, size_t size);
int popc_fuzz_intent(const uint8_t *data, size_t size);
int popc_fuzz_sweep_dir(const uint8_t *data, size_t size);
int popc_fuzz_map(const uint8_t *data, size_t size);
int popc_fuzz_register_map(const uint8_t *data, size_t size);
int popc_fuzz_modbus_uri(const uint8_t *data, size_t size);

/* Prints the broken property (printf-style) and the input, then aborts. */
void popc_fuzz_fail(const uint8_t *data, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
	__attribute__((format(printf, 3, 4), noreturn))
#endif
	;

/* A file holding data[0 .. size-1]: an anonymous memory file (memfd, no
 * disk), named by a path that fopen can open (/proc/self/fd/N). Returns the
 * descriptor (close it with popc_fuzz_file_close) or -1 with path unset. */
int popc_fuzz_file(const uint8_t *data, size_t size, char *path, size_t cap);
void popc_fuzz_file_close(int fd);

/* Whether msg starts with "PATH:N:" with N in [1, max_line]; *line gets N. */
int popc_fuzz_names_line(const char *msg, const char *path, long long max_line, long long *line);

/* Lines of data as a line reader counts them: the newlines, plus one for a
 * last line without one. */
long long popc_fuzz_count_lines(const uint8_t *data, size_t size);

#endif
