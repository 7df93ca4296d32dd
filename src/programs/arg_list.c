/* Command-line argument lists (arg_list.h). */
#include "popc/programs/arg_list.h"

#include <stdlib.h>

int popc_arg_push(char ***list, int *n, char *value)
{
	char **grown = realloc(*list, (size_t)(*n + 1) * sizeof **list);
	if (!grown)
		return -1;
	grown[(*n)++] = value;
	*list = grown;
	return 0;
}
