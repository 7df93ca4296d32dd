/* Installed scenes and drive maps found by name (data_path.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "popc/scene/data_path.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popc/scene/scene.h"
#include "popc_config.h"

const char *popc_data_kind_dir(popc_data_kind kind)
{
	return kind == POPC_DATA_DRIVES ? "drives" : kind == POPC_DATA_TRACES ? "traces" : "scenes";
}

/* The i-th data directory into out (0 when there is none): the data path's
 * entries, an empty one standing for POPC_DATADIR, or POPC_DATADIR alone. */
static int data_dir(const char *path, int i, char *out, size_t cap)
{
	if (!path || !path[0])
		return i == 0 ? (snprintf(out, cap, "%s", POPC_DATADIR), 1) : 0;
	for (const char *p = path;; p++) {
		const char *end = strchr(p, ':');
		size_t len = end ? (size_t)(end - p) : strlen(p);
		if (i-- == 0) {
			if (len == 0)
				snprintf(out, cap, "%s", POPC_DATADIR);
			else
				snprintf(out, cap, "%.*s", (int)len, p);
			return 1;
		}
		if (!end)
			return 0;
		p = end;
	}
}

void popc_data_dirs(const char *data_path, char *out, size_t cap)
{
	size_t len = 0;
	char dir[POPC_PATH_MAX];
	out[0] = '\0';
	for (int i = 0; data_dir(data_path, i, dir, sizeof dir) && len < cap; i++)
		len += (size_t)snprintf(out + len, cap - len, "%s%s", i ? ":" : "", dir);
}

static int is_file(const char *path)
{
	struct stat sb;
	return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

static int ends_with(const char *s, const char *tail)
{
	size_t ls = strlen(s), lt = strlen(tail);
	return ls >= lt && strcmp(s + ls - lt, tail) == 0;
}

/* dir/kind/name into out; a relative dir (POPC_DATA_PATH=../data) is made
 * absolute and without its "..", an absolute one is kept as written (its
 * symbolic links too); -1 when it does not fit. */
static int data_file(const char *dir, popc_data_kind kind, const char *name, const char *suffix,
		     char *out, size_t cap)
{
	char *real = dir[0] != '/' ? realpath(dir, NULL) : NULL;
	int n = snprintf(out, cap, "%s/%s/%s%s", real ? real : dir, popc_data_kind_dir(kind), name,
			 suffix);
	free(real);
	return n < 0 || (size_t)n >= cap ? -1 : 0;
}

int popc_data_find(popc_data_kind kind, const char *name, const char *base_dir,
		   const char *data_path, char *out, size_t cap, popc_error *err)
{
	if (!name[0] || strchr(name, '/'))
		return 0;
	char local[POPC_PATH_MAX * 2];
	snprintf(local, sizeof local, "%s%s%s", base_dir ? base_dir : "", base_dir ? "/" : "", name);
	struct stat sb;
	/* a local file wins, whatever it is (its reader says what is wrong);
	 * not a directory, which is no scene or map: a directory named paper
	 * in the working directory blocked the scene name paper (issue 27) */
	int local_dir = stat(local, &sb) == 0 && S_ISDIR(sb.st_mode);
	if (!local_dir && stat(local, &sb) == 0)
		return 0;
	/* NAME first: a file named exactly so; then NAME.ini, the shipped files' names */
	const char *suffixes[2] = {"", ends_with(name, ".ini") ? NULL : ".ini"};
	char dir[POPC_PATH_MAX];
	for (int i = 0; data_dir(data_path, i, dir, sizeof dir); i++)
		for (int k = 0; k < 2; k++)
			if (suffixes[k] && data_file(dir, kind, name, suffixes[k], out, cap) == 0 &&
			    is_file(out))
				return 1;
	char dirs[POPC_PATH_MAX], tried[POPC_PATH_MAX];
	popc_data_dirs(data_path, dirs, sizeof dirs);
	const char *kd = popc_data_kind_dir(kind);
	if (suffixes[1])
		snprintf(tried, sizeof tried, "%s/%s or %s/%s.ini", kd, name, kd, name);
	else
		snprintf(tried, sizeof tried, "%s/%s", kd, name);
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: no such file in %s%s, nor %s in the data director%s %s "
			      "(POPC_DATA_PATH sets them; popc(1), FILES)",
			      name, base_dir ? base_dir : "the working directory",
			      local_dir ? " (a directory of that name, not a file)" : "", tried,
			      strchr(dirs, ':') ? "ies" : "y", dirs);
}

static int cmp_names(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Whether text holds a control character (C0 or DEL): such a name cannot
 * be one field of a NAME<TAB>PATH line. */
static int has_control(const char *text)
{
	for (const unsigned char *p = (const unsigned char *)text; *p; p++)
		if (*p < 0x20 || *p == 0x7f)
			return 1;
	return 0;
}

/* text with its control characters escaped (\t, \n, \xHH), for a note */
static void put_escaped(FILE *f, const char *text)
{
	for (const unsigned char *p = (const unsigned char *)text; *p; p++) {
		if (*p == '\t')
			fputs("\\t", f);
		else if (*p == '\n')
			fputs("\\n", f);
		else if (*p < 0x20 || *p == 0x7f)
			fprintf(f, "\\x%02x", *p);
		else
			fputc(*p, f);
	}
}

int popc_data_list(popc_data_kind kind, const char *data_path, FILE *f, FILE *notes,
		   const char *who)
{
	char dir[POPC_PATH_MAX], sub[POPC_PATH_MAX + 16];
	char **seen = NULL;
	int n_seen = 0, cap_seen = 0;
	for (int i = 0; data_dir(data_path, i, dir, sizeof dir); i++) {
		if (data_file(dir, kind, "", "", sub, sizeof sub) != 0)
			continue;
		DIR *d = opendir(sub);
		if (!d)
			continue;
		int first_here = n_seen;
		for (struct dirent *e; (e = readdir(d));) {
			size_t len = strlen(e->d_name);
			if (e->d_name[0] == '.' || len <= 4 || !ends_with(e->d_name, ".ini"))
				continue;
			char path[POPC_PATH_MAX * 2 + 16];
			snprintf(path, sizeof path, "%s%s", sub, e->d_name);
			if (!is_file(path))
				continue;
			if (has_control(path)) {
				if (notes) {
					fprintf(notes, "%s: note: not listed: ", who);
					put_escaped(notes, path);
					fputs(": a name or path with a tab, a newline or another control "
					      "character cannot be one NAME<TAB>PATH line (rename it)\n",
					      notes);
				}
				continue;
			}
			int dup = 0;
			for (int k = 0; k < n_seen && !dup; k++)
				dup = strncmp(seen[k], e->d_name, len - 4) == 0 && seen[k][len - 4] == '\0';
			if (dup)
				continue;
			if (n_seen == cap_seen) {
				int cap = cap_seen ? 2 * cap_seen : 16;
				char **grown = realloc(seen, (size_t)cap * sizeof *seen);
				if (!grown)
					break;
				seen = grown;
				cap_seen = cap;
			}
			/* "NAME\0" then the path after it, in one allocation */
			size_t lp = strlen(path);
			char *entry = malloc(len - 4 + 1 + lp + 1);
			if (!entry)
				break;
			memcpy(entry, e->d_name, len - 4);
			entry[len - 4] = '\0';
			memcpy(entry + len - 3, path, lp + 1);
			seen[n_seen++] = entry;
		}
		closedir(d);
		qsort(seen + first_here, (size_t)(n_seen - first_here), sizeof *seen, cmp_names);
		for (int k = first_here; k < n_seen; k++)
			fprintf(f, "%s\t%s\n", seen[k], seen[k] + strlen(seen[k]) + 1);
	}
	for (int k = 0; k < n_seen; k++)
		free(seen[k]);
	free(seen);
	return n_seen;
}
