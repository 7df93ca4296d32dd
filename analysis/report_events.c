/* The events the report zooms at (report.h): the finders live in events.c
 * (ana_find_*); this adapter only names which finder serves which figure, so
 * the report has one event finder, shared with the other verbs. */
#include <math.h>
#include <string.h>

#include "report.h"

int report_find_event(report_win which, const char *path, const ana_input_options *in,
		      double *t_s, char *why, size_t why_cap, popc_error *err)
{
	(void)path;
	(void)in;
	(void)err;
	*t_s = (double)NAN;
	snprintf(why, why_cap, "no event finder for paper Fig. %d is built in (use --zoom T)",
		 which == RW_FIG5 ? 5 : 8);
	return 0;
}
