/* popc_same_file (same_file.h). */
#include "popc/util/same_file.h"

#include <string.h>
#include <sys/stat.h>

static int names_a_file(const char *path)
{
	return path && path[0] && strcmp(path, "-") != 0;
}

int popc_same_file(const char *a, const char *b)
{
	struct stat sa, sb;
	if (!names_a_file(a) || !names_a_file(b) || stat(a, &sa) != 0 || stat(b, &sb) != 0)
		return 0;
	return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}
