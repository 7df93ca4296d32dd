/* The events the report zooms at (report.h), from the analyser's one event
 * finder (events.c, ana_find_events: the same definitions as the 'events'
 * verb), in a read of the log before the report's own, so that the zoom
 * windows are known when the report's pass keeps their rows. */
#include <math.h>
#include <string.h>

#include "report.h"

int report_find_events(report_log *lg, const ana_input_options *in, popc_error *err)
{
	ana_input_options quiet = *in;
	quiet.quiet = 1; /* the report's own read of the log notes what it must */
	ana_events ev;
	int st = ana_find_events(lg->path, &quiet, ANA_SETTLE_HOLD_S, &ev, err);
	if (st)
		return st;
	/* the paper's events are in the low-velocity phase (from settle_s on);
	 * a log that never settles still shows its first one */
	lg->t_event_s[RW_FIG5] = !isnan(ev.fig5_s) ? ev.fig5_s : ev.fig5_first_s;
	lg->t_event_s[RW_FIG8] = !isnan(ev.fig8_s) ? ev.fig8_s : ev.fig8_first_s;
	lg->t_settle_s = ev.settle_s;
	lg->t_settle_final_s = ev.settle_final_s;
	lg->x_settled_min_m = ev.x_min_settled_m;
	lg->x_settled_max_m = ev.x_max_settled_m;
	return 0;
}
