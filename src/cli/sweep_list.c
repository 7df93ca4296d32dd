/* popc sweep --list (sweep_list.h). */
#include "sweep_list.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "popc/sweep/sweep_dir.h"
#include "popc/util/atomic_file.h"

/* Writes text as one shell word (single quotes unless it is plain). */
static void put_word(FILE *f, const char *text)
{
	if (text[0] && strspn(text, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
				    "_-+=.,/:@%") == strlen(text)) {
		fputs(text, f);
		return;
	}
	fputc('\'', f);
	for (const char *c = text; *c; c++) {
		if (*c == '\'')
			fputs("'\\''", f);
		else
			fputc(*c, f);
	}
	fputc('\'', f);
}

/* One `popc run` line per run of the shard. Each runs the run's resolved
 * scene, written now to DIR/runs/<id>/scene.ini (every key, paths absolute:
 * scene.h), not the sweep's scene file with --set words: the lines run later,
 * maybe on other machines, and an edit of the scene file in between would
 * give results other than the plan's, which merge would take as the plan's. */
int sweep_list_print(const popc_sweep_plan *p, const popc_sweep_shard *sh, const char *program,
		     const char *dir_abs)
{
	char rdir[POPC_PATH_MAX], path[POPC_PATH_MAX + 32];
	for (long long i = 0; i < p->n_runs; i++) {
		if (!popc_sweep_in_shard(sh, i))
			continue;
		/* popc run writes into the run's directory but does not make it */
		if (popc_sweep_run_dir(p, dir_abs, i, rdir, sizeof rdir) != 0 ||
		    (mkdir(rdir, 0777) != 0 && errno != EEXIST)) {
			fprintf(stderr, "popc sweep: %s: %s\n", rdir, strerror(errno));
			return POPC_EXIT_RUN_FAILED;
		}
		popc_scene s;
		popc_error err;
		char *text = NULL;
		size_t len;
		snprintf(path, sizeof path, "%s/scene.ini", rdir);
		int st = popc_sweep_run_scene(p, i, &s, &err);
		if (!st)
			st = popc_scene_to_text(&s, &text, &len, &err);
		if (!st)
			st = popc_write_file_atomic(path, text, len, &err);
		free(text);
		if (st) {
			fprintf(stderr, "popc sweep: %s\n", err.msg);
			return popc_status_exit_code(st);
		}
		put_word(stdout, program);
		fputs(" run ", stdout);
		put_word(stdout, path);
		/* the log always: popc run's summary lacks the chatter detector's
		 * columns, which merge computes from it */
		snprintf(path, sizeof path, "%s/log.csv", rdir);
		fputs(" --log ", stdout);
		put_word(stdout, path);
		snprintf(path, sizeof path, "%s/run.csv", rdir);
		fputs(" --summary ", stdout);
		put_word(stdout, path);
		fputs(" -q\n", stdout);
	}
	return fflush(stdout) != 0 || ferror(stdout) ? POPC_EXIT_RUN_FAILED : POPC_EXIT_OK;
}
