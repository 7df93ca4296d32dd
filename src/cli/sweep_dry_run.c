/* popc sweep --dry-run, popc map --dry-run (sweep_dry_run.h). Reads only:
 * stat, the plan file and the rows files, never a lock or a write. */
#include "sweep_dry_run.h"

#include <stdio.h>
#include <sys/stat.h>

#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_results.h"

int sweep_dry_run_dir(FILE *f, const popc_sweep_plan *p, const char *dir)
{
	struct stat sb;
	char path[POPC_PATH_MAX + 32];
	snprintf(path, sizeof path, "%s/sweep.plan", dir);
	if (stat(dir, &sb) != 0) {
		fprintf(f, "%s does not exist (it would be made)", dir);
		return 0;
	}
	if (stat(path, &sb) != 0) {
		fprintf(f, "%s exists, no sweep in it", dir);
		return 0;
	}
	popc_sweep_plan old;
	popc_error err;
	if (popc_sweep_plan_from_dir(&old, dir, &err) != 0) {
		fprintf(f, "%s holds a plan that cannot be read (%s)", dir, err.msg);
		return 1;
	}
	int same = old.plan_id == p->plan_id;
	popc_sweep_plan_free(&old);
	if (!same) {
		fprintf(f, "%s holds another sweep (it would be refused)", dir);
		return 1;
	}
	const char *dirs[1] = {dir};
	popc_sweep_results res;
	if (popc_sweep_results_load(&res, p, dirs, 1, 0, &err) != 0) {
		fprintf(f, "%s holds this sweep, its results cannot be read (%s)", dir, err.msg);
		return 1;
	}
	long long done = 0;
	for (long long i = 0; i < p->n_runs; i++)
		done += res.run[i].row && res.run[i].exit_status == 0;
	popc_sweep_results_free(&res);
	fprintf(f, "%s holds this sweep: %lld of %lld runs succeeded (it would resume)", dir, done,
		p->n_runs);
	return 0;
}

int sweep_dry_run_print(const popc_sweep_plan *p, const popc_sweep_shard *sh, const char *dir)
{
	long long n_shard = 0;
	for (long long i = 0; i < p->n_runs; i++)
		n_shard += popc_sweep_in_shard(sh, i);
	printf("# popc sweep --dry-run: %lld runs", p->n_runs);
	if (sh->count > 1)
		printf(", shard %lld of %lld: %lld of them", sh->index + 1, sh->count, n_shard);
	printf("; ");
	int refused = sweep_dry_run_dir(stdout, p, dir);
	printf("; nothing written\n");
	char id[POPC_SWEEP_ID_MAX], values[4096];
	for (long long i = 0; i < p->n_runs; i++) {
		if (!popc_sweep_in_shard(sh, i))
			continue;
		popc_sweep_run_id(p, i, id);
		popc_sweep_run_describe(p, i, values, sizeof values);
		printf("%s\t%s\n", id, values);
	}
	if (fflush(stdout) != 0 || ferror(stdout))
		return POPC_EXIT_RUN_FAILED;
	return refused ? POPC_EXIT_USAGE : POPC_EXIT_OK;
}
