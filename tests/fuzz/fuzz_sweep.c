/* Sweep directory harness (sweep_dir.h, sweep_results.h): a sweep.plan and a
 * rows file read back, as a resume or a merge reads them.
 *
 * Input: the plan's text, then a line "%%", then the rows file's text (no
 * such line: a plan alone). Properties: an error names the file (and, where
 * it names a line, a line of that file); an accepted plan has runs, as many
 * as its vary lines make, and a summary header of its axes; every row the
 * results keep belongs to a run of the plan, ends with its line, has the
 * plan's values of its run and no cell that is not a finite number of popc's
 * grammar (no nan or inf reaches summary.csv). */
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_results.h"
#include "popc/sweep/sweep_row.h"

static void check_error(const uint8_t *data, size_t size, const char *msg, const char *path,
			const uint8_t *file, size_t file_size)
{
	size_t n = strlen(path);
	if (strncmp(msg, path, n) != 0)
		popc_fuzz_fail(data, size, "error without the file: %s", msg);
	if (msg[n] == ':' && msg[n + 1] >= '0' && msg[n + 1] <= '9' &&
	    !popc_fuzz_names_line(msg, path, popc_fuzz_count_lines(file, file_size), NULL))
		popc_fuzz_fail(data, size, "error naming a line not in the file: %s", msg);
}

int popc_fuzz_sweep_dir(const uint8_t *data, size_t size)
{
	static const char sep[] = "\n%%\n";
	const uint8_t *plan_text = data, *rows_text = NULL;
	size_t plan_size = size, rows_size = 0;
	for (size_t k = 0; k + 4 <= size; k++)
		if (memcmp(data + k, sep, 4) == 0) {
			plan_size = k + 1;
			rows_text = data + k + 4;
			rows_size = size - k - 4;
			break;
		}
	char plan_path[64], rows_path[64];
	int fd = popc_fuzz_file(plan_text, plan_size, plan_path, sizeof plan_path);
	if (fd < 0)
		return 0;
	popc_sweep_plan plan;
	popc_error err;
	err.msg[0] = '\0';
	int st = popc_sweep_plan_read(&plan, plan_path, &err);
	popc_fuzz_file_close(fd);
	if (st) {
		check_error(data, size, err.msg, plan_path, plan_text, plan_size);
		return 0;
	}
	long long runs = 1;
	for (int a = 0; a < plan.n_axes; a++) {
		if (plan.axes[a].n_values < 1)
			popc_fuzz_fail(data, size, "vary line %d has no values", a + 1);
		runs *= plan.axes[a].n_values;
	}
	if (plan.n_runs < 1 || plan.n_runs != runs)
		popc_fuzz_fail(data, size, "a plan of %lld runs, its vary lines make %lld", plan.n_runs,
			       runs);
	char *header = popc_sweep_columns_header(plan.axes, plan.n_axes);
	if (!header || strcmp(header, plan.columns) != 0)
		popc_fuzz_fail(data, size, "the plan's columns are not its axes' header");
	free(header);
	if (!rows_text || (fd = popc_fuzz_file(rows_text, rows_size, rows_path, sizeof rows_path)) < 0) {
		popc_sweep_plan_free(&plan);
		return 0;
	}
	popc_sweep_results res;
	err.msg[0] = '\0';
	st = popc_sweep_results_load_rows(&res, &plan, rows_path, &err);
	popc_fuzz_file_close(fd);
	if (st) {
		check_error(data, size, err.msg, rows_path, rows_text, rows_size);
		popc_sweep_plan_free(&plan);
		return 0;
	}
	for (long long i = 0; i < res.n; i++) {
		const popc_sweep_result_entry *e = &res.run[i];
		if (!e->row)
			continue;
		if (e->len < 1 || e->row[e->len - 1] != '\n')
			popc_fuzz_fail(data, size, "run %lld: a row that does not end its line", i);
		if (popc_sweep_row_check(&plan, i, e->row, (size_t)e->len - 1, &err) != 0)
			popc_fuzz_fail(data, size, "run %lld: a row kept that no run makes: %s", i,
				       err.msg);
		if (e->exit_status < 0 || e->exit_status > 999 ||
		    popc_sweep_row_exit_status(&plan, e->row) != e->exit_status)
			popc_fuzz_fail(data, size, "run %lld: exit status %d", i, e->exit_status);
	}
	popc_sweep_results_free(&res);
	popc_sweep_plan_free(&plan);
	return 0;
}
