/* Windows of raw rows for the zoom and position-against-force figures
 * (report.h): a ring of the last REPORT_ZOOM_TICKS rows, so a window starts
 * that many ticks before its event in one pass over the log, and a bound on
 * each window's rows, so memory stays bounded whatever the log's length. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "report.h"

int report_capture_init(report_capture *c, const double t_event_s[RW_COUNT])
{
	memset(c, 0, sizeof *c);
	for (int i = 0; i < RW_COUNT; i++) {
		report_window *w = &c->w[i];
		w->event_index = -1;
		w->t_event_s = t_event_s[i];
		w->wanted = i == RW_PRESS || i == RW_END || !isnan(t_event_s[i]);
		if (!w->wanted)
			continue;
		w->cap = i == RW_PRESS ? REPORT_ZOOM_TICKS + REPORT_PRESS_TICKS + REPORT_ZOOM_TICKS
				       : 2 * REPORT_ZOOM_TICKS + 1;
		w->rows = calloc((size_t)w->cap, sizeof *w->rows);
		if (!w->rows) {
			report_capture_free(c);
			return -1;
		}
	}
	return 0;
}

static void keep(report_window *w, const report_sample *s)
{
	if (w->n < w->cap)
		w->rows[w->n++] = *s;
	else
		w->closed = 1;
}

/* The window opens at its event: the ring's rows first (the ticks before). */
static void open_window(report_capture *c, report_window *w, const report_sample *s)
{
	for (int k = 0; k < c->ring_n; k++)
		keep(w, &c->ring[(c->ring_pos - c->ring_n + k + REPORT_ZOOM_TICKS) % REPORT_ZOOM_TICKS]);
	w->event_index = w->n;
	keep(w, s);
	w->after = REPORT_ZOOM_TICKS;
}

void report_capture_add(report_capture *c, const report_sample *s, int in_contact)
{
	for (int i = 0; i < RW_COUNT; i++) {
		report_window *w = &c->w[i];
		if (!w->wanted || w->closed)
			continue;
		if (i == RW_END) { /* a ring: the last cap rows */
			w->rows[w->pos] = *s;
			w->pos = (w->pos + 1) % w->cap;
			if (w->n < w->cap)
				w->n++;
			continue;
		}
		if (w->event_index < 0) {
			/* the event tick: the first row at or after the event time (an
			 * event found in the log is one of its rows' times, exactly);
			 * the press: the first tick in contact */
			int here = i == RW_PRESS ? in_contact : s->t_s >= w->t_event_s;
			if (here) {
				open_window(c, w, s);
				if (i == RW_PRESS)
					w->t_event_s = s->t_s;
			}
			continue;
		}
		keep(w, s);
		if (i == RW_PRESS && in_contact)
			w->after = REPORT_ZOOM_TICKS; /* counts down once the wall is left */
		else if (--w->after <= 0)
			w->closed = 1;
	}
	c->ring[c->ring_pos] = *s;
	c->ring_pos = (c->ring_pos + 1) % REPORT_ZOOM_TICKS;
	if (c->ring_n < REPORT_ZOOM_TICKS)
		c->ring_n++;
}

void report_capture_finish(report_capture *c)
{
	report_window *w = &c->w[RW_END];
	if (w->n == 0)
		return;
	if (w->n == w->cap && w->pos > 0) {
		/* rotate left by pos, in place: three reversals */
		report_sample tmp;
#define REVERSE(lo, hi)                                                                            \
	for (int a = (lo), b = (hi) - 1; a < b; a++, b--) {                                          \
		tmp = w->rows[a];                                                                  \
		w->rows[a] = w->rows[b];                                                           \
		w->rows[b] = tmp;                                                                  \
	}
		REVERSE(0, w->pos)
		REVERSE(w->pos, w->cap)
		REVERSE(0, w->cap)
#undef REVERSE
		w->pos = 0;
	}
	w->event_index = w->n / 2;
	w->t_event_s = w->rows[w->event_index].t_s;
}

void report_capture_free(report_capture *c)
{
	for (int i = 0; i < RW_COUNT; i++) {
		free(c->w[i].rows);
		c->w[i].rows = NULL;
	}
}

int report_window_write(const report_window *w, FILE *f)
{
	for (int k = 0; k < w->n; k++) {
		ana_put_double(f, w->rows[k].t_s);
		for (int j = 0; j < D_COLS; j++) {
			fputc(' ', f);
			if (isnan(w->rows[k].v[j]))
				fputs("NaN", f);
			else
				ana_put_double(f, w->rows[k].v[j]);
		}
		fputc('\n', f);
	}
	return ferror(f) ? -1 : 0;
}
