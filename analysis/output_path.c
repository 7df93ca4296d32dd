/* Output paths checked before any work (analyze.h: ana_output_file_usable,
 * ana_output_dir_usable): a path that cannot be used is bad usage, exit 2,
 * named with the option, before any log is read or any output is opened. */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "analyze.h"

/* The directory a file path would be created in: "." for a bare name. */
static void parent_of(const char *path, char *out, size_t cap)
{
	const char *slash = strrchr(path, '/');
	if (!slash)
		snprintf(out, cap, ".");
	else if (slash == path)
		snprintf(out, cap, "/");
	else
		snprintf(out, cap, "%.*s", (int)(slash - path), path);
}

static int refuse(const char *verb, const char *opt, const char *path, const char *why,
		  const char *detail)
{
	fprintf(stderr, "popc-analyze %s: %s %s: %s%s%s\n", verb, opt, path, why, detail ? ": " : "",
		detail ? detail : "");
	return POPC_EXIT_USAGE;
}

/* dir exists, is a directory, and files can be made in it */
static int dir_writable(const char *verb, const char *opt, const char *shown, const char *dir)
{
	struct stat st;
	if (stat(dir, &st) != 0) {
		char why[1200];
		snprintf(why, sizeof why, "its directory %s cannot be used", dir);
		return refuse(verb, opt, shown, why, strerror(errno));
	}
	if (!S_ISDIR(st.st_mode)) {
		char why[1200];
		snprintf(why, sizeof why, "%s is not a directory", dir);
		return refuse(verb, opt, shown, why, NULL);
	}
	if (access(dir, W_OK | X_OK) != 0) {
		char why[1200];
		snprintf(why, sizeof why, "no file can be made in %s", dir);
		return refuse(verb, opt, shown, why, strerror(errno));
	}
	return 0;
}

int ana_output_file_usable(const char *verb, const char *opt, const char *path)
{
	if (strcmp(path, "-") == 0)
		return 0;
	if (!path[0])
		return refuse(verb, opt, "''", "an empty path", NULL);
	struct stat st;
	if (stat(path, &st) == 0) {
		if (S_ISDIR(st.st_mode))
			return refuse(verb, opt, path, "is a directory; a file path is needed", NULL);
		if (access(path, W_OK) != 0)
			return refuse(verb, opt, path, "cannot be written", strerror(errno));
		return 0;
	}
	if (errno != ENOENT) /* a path through a file (ENOTDIR), a loop, no permission */
		return refuse(verb, opt, path, "cannot be used", strerror(errno));
	char dir[1100];
	parent_of(path, dir, sizeof dir);
	return dir_writable(verb, opt, path, dir);
}

int ana_output_dir_usable(const char *verb, const char *opt, const char *dir, int create)
{
	struct stat st;
	if (stat(dir, &st) == 0) {
		if (!S_ISDIR(st.st_mode))
			return refuse(verb, opt, dir, "exists and is not a directory", NULL);
		return dir_writable(verb, opt, dir, dir);
	}
	if (errno != ENOENT || !create)
		return refuse(verb, opt, dir, "cannot be used as a directory", strerror(errno));
	char parent[1100];
	parent_of(dir, parent, sizeof parent);
	return dir_writable(verb, opt, dir, parent);
}
