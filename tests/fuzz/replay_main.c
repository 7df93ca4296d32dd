/* Replays the checked-in fuzz corpus through every harness (a meson test,
 * no clang needed): each file of CORPUS/<harness>/ is one input, and a broken
 * property aborts with the input printed (fuzz.h).
 *
 *   fuzz_replay CORPUS            every harness, every file
 *   fuzz_replay HARNESS FILE...   one harness, these files (a reproducer) */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"

static const struct {
	const char *name;
	popc_fuzz_fn fn;
} harnesses[] = {
	{"numfmt_parse", popc_fuzz_numfmt_parse},   {"numfmt_format", popc_fuzz_numfmt_format},
	{"log_reader", popc_fuzz_log_reader},       {"scene", popc_fuzz_scene},
	{"analyze_input", popc_fuzz_analyze_input},
	{"ini_lines", popc_fuzz_ini_lines},         {"intent", popc_fuzz_intent},
	{"sweep_dir", popc_fuzz_sweep_dir},
	{"map", popc_fuzz_map},
#ifdef POPC_FUZZ_MODBUS /* a build with the Modbus family (meson option modbus) */
	{"register_map", popc_fuzz_register_map},   {"modbus_uri", popc_fuzz_modbus_uri},
#endif
};
#define N_HARNESSES (sizeof harnesses / sizeof harnesses[0])

/* Runs fn on the file's bytes; -1 if it cannot be read. */
static int replay_file(popc_fuzz_fn fn, const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f) {
		fprintf(stderr, "fuzz_replay: %s: cannot open\n", path);
		return -1;
	}
	size_t cap = 4096, n = 0;
	unsigned char *buf = malloc(cap);
	size_t got;
	while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
		n += got;
		if (n == cap) {
			unsigned char *nb = realloc(buf, cap * 2);
			if (!nb) {
				free(buf);
				buf = NULL;
				break;
			}
			buf = nb;
			cap *= 2;
		}
	}
	int bad = ferror(f) || !buf;
	fclose(f);
	if (bad) {
		free(buf);
		fprintf(stderr, "fuzz_replay: %s: cannot read\n", path);
		return -1;
	}
	/* an exact-size copy, so that ASan sees a read past the input's end */
	unsigned char *exact = malloc(n ? n : 1);
	if (!exact) {
		free(buf);
		return -1;
	}
	memcpy(exact, buf, n);
	free(buf);
	fn(exact, n);
	free(exact);
	return 0;
}

static int by_name(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Every regular file of dir, in name order; the number replayed or -1. */
static int replay_dir(popc_fuzz_fn fn, const char *dir)
{
	DIR *d = opendir(dir);
	if (!d) {
		fprintf(stderr, "fuzz_replay: %s: cannot open the directory\n", dir);
		return -1;
	}
	char **names = NULL;
	size_t n = 0, cap = 0;
	struct dirent *e;
	while ((e = readdir(d)) != NULL) {
		if (e->d_name[0] == '.')
			continue;
		if (n == cap) {
			cap = cap ? cap * 2 : 64;
			char **nn = realloc(names, cap * sizeof *names);
			if (!nn)
				break;
			names = nn;
		}
		names[n] = strdup(e->d_name);
		if (names[n])
			n++;
	}
	closedir(d);
	qsort(names, n, sizeof *names, by_name);
	int count = 0;
	for (size_t i = 0; i < n; i++) {
		char path[8192]; /* dir (up to 4096) / name (up to 256) */
		snprintf(path, sizeof path, "%s/%s", dir, names[i]);
		if (count >= 0 && replay_file(fn, path) == 0)
			count++;
		else
			count = -1;
		free(names[i]);
	}
	free(names);
	return count;
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		fprintf(stderr, "usage: fuzz_replay CORPUS | fuzz_replay HARNESS FILE...\n");
		return 2;
	}
	if (argc > 2) {
		for (size_t h = 0; h < N_HARNESSES; h++)
			if (strcmp(harnesses[h].name, argv[1]) == 0) {
				for (int i = 2; i < argc; i++)
					if (replay_file(harnesses[h].fn, argv[i]) != 0)
						return 1;
				printf("%s: %d inputs replayed, no property broken\n", argv[1], argc - 2);
				return 0;
			}
		fprintf(stderr, "fuzz_replay: no harness '%s'\n", argv[1]);
		return 2;
	}
	/* the file harnesses read memory files through /proc/self/fd: without
	 * them every such input would pass unread */
	char path[64];
	int fd = popc_fuzz_file((const uint8_t *)"x", 1, path, sizeof path);
	FILE *probe = fd >= 0 ? fopen(path, "r") : NULL;
	if (!probe) {
		printf("fuzz_replay: skipped: no memory file readable as /proc/self/fd/N here\n");
		popc_fuzz_file_close(fd);
		return 77;
	}
	fclose(probe);
	popc_fuzz_file_close(fd);
	int total = 0;
	for (size_t h = 0; h < N_HARNESSES; h++) {
		char dir[4096];
		snprintf(dir, sizeof dir, "%s/%s", argv[1], harnesses[h].name);
		int n = replay_dir(harnesses[h].fn, dir);
		/* an empty or missing corpus would make this test pass on nothing */
		if (n <= 0) {
			fprintf(stderr, "fuzz_replay: %s: no inputs replayed\n", dir);
			return 1;
		}
		printf("%s: %d inputs\n", harnesses[h].name, n);
		total += n;
	}
	printf("%d inputs replayed through %zu harnesses, no property broken\n", total, N_HARNESSES);
	return 0;
}
