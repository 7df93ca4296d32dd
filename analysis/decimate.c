/* Min/max-per-bucket decimation for plots (analyze.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"

int ana_decim_init(ana_decimator *d, int n_cols, int max_buckets)
{
	memset(d, 0, sizeof *d);
	if (n_cols < 1 || n_cols > ANA_DECIM_MAX_COLS || max_buckets < 4)
		return -1;
	d->n_cols = n_cols;
	d->cap = max_buckets & ~1; /* even: buckets merge in pairs */
	d->width = 1;
	d->b = calloc((size_t)d->cap, sizeof *d->b);
	return d->b ? 0 : -1;
}

static void merge_into(ana_decim_bucket *a, const ana_decim_bucket *b, int n_cols)
{
	for (int c = 0; c < n_cols; c++) {
		/* NaN never wins a comparison, so a column that is always NaN stays NaN */
		if (b->mn[c] < a->mn[c] || isnan(a->mn[c])) {
			a->mn[c] = b->mn[c];
			a->imn[c] = b->imn[c];
		}
		if (b->mx[c] > a->mx[c] || isnan(a->mx[c])) {
			a->mx[c] = b->mx[c];
			a->imx[c] = b->imx[c];
		}
	}
	a->n += b->n;
	a->t1_s = b->t1_s;
}

void ana_decim_add(ana_decimator *d, double t_s, const double *v)
{
	if (d->n == 0 || d->b[d->n - 1].n >= d->width) {
		if (d->n == d->cap) {
			/* full: merge pairs, double the width */
			for (int i = 0; i < d->cap / 2; i++) {
				d->b[i] = d->b[2 * i];
				merge_into(&d->b[i], &d->b[2 * i + 1], d->n_cols);
			}
			d->n = d->cap / 2;
			d->width *= 2;
		}
		if (d->n == 0 || d->b[d->n - 1].n >= d->width) {
			ana_decim_bucket *b = &d->b[d->n++];
			b->n = 0;
			b->t0_s = t_s;
			for (int c = 0; c < d->n_cols; c++) {
				b->mn[c] = b->mx[c] = v[c];
				b->imn[c] = b->imx[c] = d->k;
			}
		}
	}
	ana_decim_bucket *b = &d->b[d->n - 1];
	for (int c = 0; c < d->n_cols; c++) {
		if (v[c] < b->mn[c] || isnan(b->mn[c])) {
			b->mn[c] = v[c];
			b->imn[c] = d->k;
		}
		if (v[c] > b->mx[c] || isnan(b->mx[c])) {
			b->mx[c] = v[c];
			b->imx[c] = d->k;
		}
	}
	b->n++;
	b->t1_s = t_s;
	d->k++;
}

static void put(FILE *f, double v)
{
	if (isnan(v))
		fputs(" NaN", f);
	else {
		fputc(' ', f);
		ana_put_double(f, v);
	}
}

int ana_decim_write(const ana_decimator *d, FILE *f)
{
	for (int i = 0; i < d->n; i++) {
		const ana_decim_bucket *b = &d->b[i];
		/* the envelope: the bucket's minima then its maxima, at its first
		 * and its last time, so that a filled band between them covers the
		 * bucket's span (one row for a bucket of one tick) */
		for (int r = 0; r < (b->n > 1 ? 2 : 1); r++) {
			ana_put_double(f, r == 0 ? b->t0_s : b->t1_s);
			for (int c = 0; c < d->n_cols; c++)
				put(f, b->mn[c]);
			for (int c = 0; c < d->n_cols; c++)
				put(f, b->mx[c]);
			fputc('\n', f);
		}
	}
	return ferror(f) ? -1 : 0;
}

void ana_decim_free(ana_decimator *d)
{
	free(d->b);
	d->b = NULL;
}
