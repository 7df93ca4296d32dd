/* Option tables (options.h). */
#include "popc/programs/options.h"

#include <string.h>

int popc_options_getopt(const popc_option *const *tables, struct option *longs, size_t cap,
			char *shorts, size_t shorts_cap)
{
	size_t n = 0, s = 0;
	for (size_t t = 0; tables[t]; t++) {
		for (const popc_option *o = tables[t]; o->name; o++) {
			if (n + 1 >= cap)
				return -1;
			longs[n++] = (struct option){o->name, o->arg ? required_argument : no_argument,
						     NULL, o->val};
			if (!o->letter)
				continue;
			if (s + 3 >= shorts_cap)
				return -1;
			shorts[s++] = o->letter;
			if (o->arg)
				shorts[s++] = ':';
		}
	}
	longs[n] = (struct option){NULL, 0, NULL, 0};
	if (shorts_cap == 0)
		return -1;
	shorts[s] = '\0';
	return 0;
}

void popc_options_complete(FILE *f, const char *path, const popc_option *const *tables)
{
	for (size_t t = 0; tables[t]; t++) {
		for (const popc_option *o = tables[t]; o->name; o++) {
			const char *arg = o->arg ? o->arg : "";
			if (o->letter)
				fprintf(f, "opt\t%s\t-%c\t%s\n", path, o->letter, arg);
			fprintf(f, "opt\t%s\t--%s\t%s\n", path, o->name, arg);
		}
	}
}
