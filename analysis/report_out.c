/* The report's output files (report.h): opened only when they are not an
 * input log, closed with one message naming a failed write; which figures a
 * log has. */
#include <errno.h>
#include <string.h>

#include "report.h"

/* 0 when DIR/file is not one of the input logs; else says so. */
int report_check_not_input(const report_out *ro, const char *path)
{
	int i = ana_output_is_input(path, ro->inputs, ro->n_inputs);
	if (i < 0)
		return 0;
	fprintf(stderr,
		"popc-analyze report: %s is the input log %s: refusing to overwrite it (choose "
		"another -o DIR)\n",
		path, ro->inputs[i]);
	return -1;
}

FILE *report_open(const report_out *ro, const char *file, char *path, size_t cap)
{
	snprintf(path, cap, "%s/%s", ro->dir, file);
	if (report_check_not_input(ro, path) != 0)
		return NULL;
	FILE *f = fopen(path, "w");
	if (!f)
		fprintf(stderr, "popc-analyze report: %s: cannot open for writing: %s\n", path,
			strerror(errno));
	return f;
}

int report_close(FILE *f, const char *path, int failed)
{
	failed |= ferror(f) != 0;
	/* errno tells only for fclose: an earlier failed write's errno may be
	 * overwritten by now */
	int close_failed = fclose(f) != 0;
	int saved = errno;
	if (!failed && !close_failed)
		return 0;
	fprintf(stderr, "popc-analyze report: %s: write failed%s%s\n", path,
		close_failed ? ": " : "", close_failed ? strerror(saved) : "");
	return -1;
}

int report_log_has(const report_log *lg, report_fig fig, unsigned figs)
{
	if (!(figs & (1u << fig)))
		return 0;
	switch (fig) {
	case RF_FIG5: return lg->has_window[RW_FIG5];
	case RF_FIG8: return lg->has_window[RW_FIG8];
	case RF_ZOOM: return lg->has_window[RW_ZOOM];
	case RF_FIG6: return lg->has_window[RW_PRESS];
	case RF_FIG11: return lg->has_window[RW_END];
	default: return 1;
	}
}

