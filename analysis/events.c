/* The paper's timeline events in a log (docs/ANALYSIS.md, "Events"), found in
 * one pass with constant memory: the settling of the backward-difference
 * velocity to one count per period (seed Fig. 4), the first one-count velocity reversal under an
 * active PC after which W - E_ref falls (Fig. 5) and the first PC activation
 * followed by a tick without displacement (Fig. 8). */
#include <math.h>
#include <string.h>

#include "analyze.h"

void ana_find_events_init(ana_events_finder *f, double hold_s)
{
	memset(f, 0, sizeof *f);
	f->hold_s = hold_s;
	ana_events *ev = &f->ev;
	ev->settle_s = ev->settle_end_s = ev->settle_final_s = (double)NAN;
	ev->settle_tick = -1;
	ev->fig5_s = ev->fig5_dw_J = ev->fig8_s = (double)NAN;
	ev->fig5_first_s = ev->fig8_first_s = (double)NAN;
	f->run_fig5_s = f->run_fig5_dw_J = f->run_fig8_s = (double)NAN;
	ev->x_min_settled_m = ev->x_max_settled_m = (double)NAN;
}

static void settle_found(ana_events_finder *f)
{
	f->settled = f->settle_open = 1;
	f->ev.settle_s = f->run_start_s;
	f->ev.settle_tick = f->run_start_tick;
	f->ev.x_min_settled_m = f->run_x_min_m;
	f->ev.x_max_settled_m = f->run_x_max_m;
	f->ev.fig5_s = f->run_fig5_s;
	f->ev.fig5_dw_J = f->run_fig5_dw_J;
	f->ev.fig8_s = f->run_fig8_s;
}

/* The settle stretch: calm ticks (|dcount| <= 1) one after another; the
 * first stretch after a tick that is not calm that lasts hold_s is the one
 * (or, in finish, the stretch that reaches the end). */
static void track_settle(ana_events_finder *f, const popc_tick *t, int calm)
{
	ana_events *ev = &f->ev;
	if (!calm) {
		ev->n_fast++;
		if (f->settle_open) {
			ev->settle_end_s = t->t_s;
			f->settle_open = 0;
		}
		f->in_run = 0;
		return;
	}
	if (!f->in_run) {
		f->in_run = 1;
		f->run_start_s = t->t_s;
		f->run_start_tick = f->n;
		f->run_x_min_m = f->run_x_max_m = t->x_m;
		f->run_fig5_s = f->run_fig5_dw_J = f->run_fig8_s = (double)NAN;
	}
	if (t->x_m < f->run_x_min_m)
		f->run_x_min_m = t->x_m;
	if (t->x_m > f->run_x_max_m)
		f->run_x_max_m = t->x_m;
	if (f->settle_open) {
		ev->x_min_settled_m = f->run_x_min_m;
		ev->x_max_settled_m = f->run_x_max_m;
	}
	/* settling follows motion: a calm start (the hand at rest before the
	 * approach) is no settle until a faster tick came before it */
	if (!f->settled && ev->n_fast > 0 && t->t_s - f->run_start_s >= f->hold_s)
		settle_found(f);
}

/* An event of Fig. 5 or 8 at tick k = the previous row. The paper shows them
 * in the low-velocity phase: fig*_s is the first at or after settle_s. While
 * the settle stretch is not yet known, the first event of the current calm
 * stretch is kept (run_fig*), and settle_found takes it if that stretch is
 * the one. */
static void fig_event(ana_events_finder *f, int fig, double dw_J)
{
	ana_events *ev = &f->ev;
	const double t_s = f->t_prev_s;
	double *first = fig == 5 ? &ev->fig5_first_s : &ev->fig8_first_s;
	double *settled = fig == 5 ? &ev->fig5_s : &ev->fig8_s;
	double *run = fig == 5 ? &f->run_fig5_s : &f->run_fig8_s;
	if (fig == 5)
		ev->n_fig5++;
	else
		ev->n_fig8++;
	if (isnan(*first))
		*first = t_s;
	if (f->settled) {
		if (isnan(*settled) && t_s >= ev->settle_s) {
			*settled = t_s;
			if (fig == 5)
				ev->fig5_dw_J = dw_J;
		}
	} else if (f->in_run && t_s >= f->run_start_s && isnan(*run)) {
		*run = t_s;
		if (fig == 5)
			f->run_fig5_dw_J = dw_J;
	}
}

void ana_find_events_row(ana_events_finder *f, const ana_row *row)
{
	ana_events *ev = &f->ev;
	const popc_tick *t = &row->tick;
	const double we_J = t->W_J - t->E_ref_J;
	const int pc_active = t->f_pc_N != 0.0;
	ev->pc_known = row->pc_force_known;
	ev->w_known = row->w_known;
	long long dcount = 0;
	if (f->n > 0)
		dcount = t->count - f->count_prev;
	track_settle(f, t, dcount >= -1 && dcount <= 1);
	if (f->n > 0) {
		/* Fig. 5: a one-count step at k (the previous row) with the PC on,
		 * the reverse step at k+1 (this row), and W - E_ref lower at k+1 */
		if (f->n >= 2 && row->pc_force_known && row->w_known && f->pc_active_prev &&
		    (f->dcount_prev == 1 || f->dcount_prev == -1) && dcount == -f->dcount_prev &&
		    we_J < f->we_prev_J)
			fig_event(f, 5, we_J - f->we_prev_J);
		/* Fig. 8: the PC turned on at k (off at k-1, or k the first row),
		 * and no count moved from k to k+1 */
		if (row->pc_force_known && f->pc_active_prev && !f->pc_active_prev2 && dcount == 0)
			fig_event(f, 8, 0.0);
	}
	f->dcount_prev = dcount;
	f->pc_active_prev2 = f->pc_active_prev;
	f->pc_active_prev = pc_active;
	f->count_prev = t->count;
	f->t_prev_s = t->t_s;
	f->we_prev_J = we_J;
	f->n++;
	ev->ticks = f->n;
}

void ana_find_events_finish(const ana_events_finder *f, ana_events *ev)
{
	*ev = f->ev;
	if (!f->in_run)
		return; /* the last tick is not calm: no stretch reaches the end */
	if (!f->settled) {
		/* the calm stretch that reaches the end, shorter than hold_s (or
		 * the whole log, calm throughout) */
		ana_events_finder g = *f;
		settle_found(&g);
		*ev = g.ev;
	}
	ev->settle_final_s = f->run_start_s;
}

static void on_row(void *ctx, const ana_row *row)
{
	ana_find_events_row(ctx, row);
}

int ana_find_events(const char *path, const ana_input_options *o, double hold_s, ana_events *ev,
		    popc_error *err)
{
	ana_log l;
	int st = ana_log_open(&l, path, o, err);
	if (st)
		return st;
	ana_events_finder f;
	ana_find_events_init(&f, hold_s);
	ana_row row;
	while ((st = ana_log_next(&l, &row, err)) == 1)
		on_row(&f, &row);
	ana_log_close(&l);
	if (st < 0)
		return st;
	ana_find_events_finish(&f, ev);
	return 0;
}
