/* The names that tell logs apart in one table (analyze.h, ana_log_names). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"

/* The last k '/'-separated components of path, ".csv" dropped from the last
 * ("a/b/improved.csv", 2: "b/improved"); the whole path when it has fewer.
 * Returns how many components path has. */
static int suffix_name(const char *path, int k, char *out, size_t cap)
{
	if (strcmp(path, "-") == 0) {
		snprintf(out, cap, "stdin");
		return 1;
	}
	int parts = 1;
	for (const char *p = path; *p; p++)
		parts += *p == '/' && p[1] != '\0';
	const char *start = path + strlen(path);
	for (int seen = 0; start > path; start--)
		if (start[-1] == '/' && start[0] != '\0' && ++seen == k)
			break;
	size_t n = strlen(start);
	if (n > 4 && strcmp(start + n - 4, ".csv") == 0)
		n -= 4;
	snprintf(out, cap, "%.*s", (int)n, start);
	return parts;
}

int ana_log_names(char *const *paths, int n, char (*names)[ANA_LOG_NAME_MAX])
{
	/* per log: components used, components there are, one more wanted */
	int *k = malloc(3 * (size_t)(n > 0 ? n : 1) * sizeof *k);
	if (!k)
		return -1;
	int *parts = k + n, *more = k + 2 * n;
	for (int i = 0; i < n; i++) {
		k[i] = 1;
		parts[i] = suffix_name(paths[i], 1, names[i], ANA_LOG_NAME_MAX);
	}
	/* one more component for each log whose name another log has, until
	 * none does (or the colliding paths have no more: the same path twice) */
	for (int grew = 1; grew;) {
		grew = 0;
		for (int i = 0; i < n; i++) {
			more[i] = 0;
			for (int j = 0; j < n && !more[i]; j++)
				more[i] = j != i && strcmp(names[i], names[j]) == 0 &&
					  strcmp(paths[i], paths[j]) != 0 && k[i] < parts[i];
		}
		for (int i = 0; i < n; i++)
			if (more[i]) {
				suffix_name(paths[i], ++k[i], names[i], ANA_LOG_NAME_MAX);
				grew = 1;
			}
	}
	free(k);
	return 0;
}
