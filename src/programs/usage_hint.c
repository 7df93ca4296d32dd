/* One hint line after a usage error (usage_hint.h). */
#include "popc/programs/usage_hint.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

size_t popc_edit_distance(const char *a, const char *b)
{
	/* three rows of the dynamic programme: names are short, and a word
	 * longer than 64 characters is compared by its first 64 */
	enum { MAX = 64 };
	size_t n = strlen(a), m = strlen(b);
	if (n > MAX)
		n = MAX;
	if (m > MAX)
		m = MAX;
	size_t prev2[MAX + 1], prev[MAX + 1], cur[MAX + 1];
	for (size_t j = 0; j <= m; j++)
		prev[j] = j;
	memset(prev2, 0, sizeof prev2);
	for (size_t i = 1; i <= n; i++) {
		cur[0] = i;
		for (size_t j = 1; j <= m; j++) {
			size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
			size_t best = prev[j] + 1;               /* deletion */
			if (cur[j - 1] + 1 < best)
				best = cur[j - 1] + 1;           /* insertion */
			if (prev[j - 1] + cost < best)
				best = prev[j - 1] + cost;       /* substitution */
			if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
			    prev2[j - 2] + 1 < best)
				best = prev2[j - 2] + 1;         /* transposition */
			cur[j] = best;
		}
		memcpy(prev2, prev, sizeof prev);
		memcpy(prev, cur, sizeof cur);
	}
	return prev[m];
}

const char *popc_nearest_name(const char *word, const char *const *names, size_t n)
{
	size_t len = strlen(word);
	size_t limit = len <= 4 ? 1 : len <= 8 ? 2 : 3;
	const char *best = NULL;
	size_t best_d = limit + 1;
	for (size_t i = 0; i < n; i++) {
		size_t d = popc_edit_distance(word, names[i]);
		if (d < best_d) {
			best_d = d;
			best = names[i];
		}
	}
	return best;
}

void popc_help_hint(const char *prog, const char *what)
{
	fprintf(stderr, "%s: '%s --help' lists the %s\n", prog, prog, what);
}

void popc_option_hint(const char *prog, const struct option *opts, int argc, char *const *argv)
{
	const char *bad = optind > 0 && optind <= argc ? argv[optind - 1] : NULL;
	/* an unknown long option: getopt leaves optopt 0 (a short one, or a
	 * missing argument, sets it; no spelling to correct then) */
	if (optopt == 0 && bad && strncmp(bad, "--", 2) == 0 && bad[2]) {
		char word[65];
		size_t len = strcspn(bad + 2, "=");
		if (len >= sizeof word)
			len = sizeof word - 1;
		memcpy(word, bad + 2, len);
		word[len] = '\0';
		const char *names[128];
		size_t n = 0;
		for (const struct option *o = opts; o->name && n < 128; o++)
			names[n++] = o->name;
		const char *near = popc_nearest_name(word, names, n);
		if (near) {
			fprintf(stderr, "%s: did you mean --%s? ('%s --help' lists the options)\n", prog,
				near, prog);
			return;
		}
	}
	popc_help_hint(prog, "options");
}
