/* libpopc: log writing and reading (popc/popc.h), over the log layer's
 * writer and streaming reader. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "lib_private.h"
#include "popc/log/log.h"
#include "popc/log/log_reader.h"

struct popc_lib_log_writer {
	popc_log_writer w;
};

struct popc_lib_log_reader {
	popc_log_reader r;
};

POPC_API int popc_lib_log_writer_open(popc_lib_log_writer **out, const char *log_path,
				      const popc_lib_scene *s, const char *source, unsigned columns,
				      popc_lib_error *err)
{
	*out = NULL;
	if (columns & ~(unsigned)(POPC_LIB_LOG_X_TRUE | POPC_LIB_LOG_TIMING))
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_log_writer_open: columns: allowed "
					  "POPC_LIB_LOG_X_TRUE | POPC_LIB_LOG_TIMING");
	popc_lib_log_writer *w = malloc(sizeof *w);
	if (!w)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM,
					  "popc_lib_log_writer_open: out of memory");
	_Static_assert((int)POPC_LIB_LOG_X_TRUE == (int)POPC_LOG_COL_X_TRUE &&
			       (int)POPC_LIB_LOG_TIMING == (int)POPC_LOG_COL_TIMING,
		       "the public column bits are the log's");
	popc_error e;
	int st = popc_log_open(&w->w, log_path, columns, &e);
	if (st) {
		free(w);
		return popc_lib_fail(err, st, &e);
	}
	st = popc_log_write_header(&w->w, source ? source : "sim", &s->scene, NULL, &e);
	if (st) {
		popc_error ce;
		popc_log_close(&w->w, &ce);
		free(w);
		return popc_lib_fail(err, st, &e);
	}
	*out = w;
	return 0;
}

POPC_API int popc_lib_log_write_row(popc_lib_log_writer *w, const popc_lib_row *row,
				    popc_lib_error *err)
{
	popc_log_row r;
	r.tick.t_s = row->tick.t_s;
	r.tick.x_m = row->tick.x_m;
	r.tick.count = row->tick.count;
	r.tick.v_mps = row->tick.v_mps;
	r.tick.f_e_N = row->tick.f_e_N;
	r.tick.f_pc_N = row->tick.f_pc_N;
	r.tick.f_c_N = row->tick.f_c_N;
	r.tick.W_J = row->tick.W_J;
	r.tick.E_ref_J = row->tick.E_ref_J;
	r.tick.flags = row->tick.flags;
	r.x_true_m = row->x_true_m;
	r.E_port_J = row->E_port_J;
	r.dt_s = row->dt_s;
	r.rtt_s = row->rtt_s;
	popc_error e;
	/* no NaN or inf reaches a log cell: every cell this log writes is checked
	 * (the columns of its set, log_columns.h's table) */
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
		if (!popc_log_column_written(popc_log_columns[id].fill, w->w.columns))
			continue;
		if (!isfinite(popc_log_row_get(&r, (popc_log_column_id)id)))
			return popc_lib_fail(err,
					     popc_error_set(&e, POPC_ERR_INVALID,
							    "%s: row at t = %.17g: column %s is not finite "
							    "(NaN or inf); the row is not written",
							    w->w.path, row->tick.t_s, popc_log_columns[id].name),
					     &e);
	}
	return popc_lib_fail(err, popc_log_write_row(&w->w, &r, &e), &e);
}

POPC_API int popc_lib_log_writer_close(popc_lib_log_writer *w, const char *stop_reason,
				       popc_lib_error *err)
{
	if (!w)
		return 0;
	popc_error e, ce;
	int st = stop_reason ? popc_log_write_comment(&w->w, "stop", stop_reason, &e) : 0;
	if (!st)
		st = popc_log_flush(&w->w, &e);
	int cst = popc_log_close(&w->w, &ce);
	free(w);
	if (st)
		return popc_lib_fail(err, st, &e);
	return popc_lib_fail(err, cst, &ce);
}

POPC_API int popc_lib_log_reader_open(popc_lib_log_reader **out, const char *log_path,
				      popc_lib_error *err)
{
	*out = NULL;
	popc_lib_log_reader *r = malloc(sizeof *r);
	if (!r)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM,
					  "popc_lib_log_reader_open: out of memory");
	popc_error e;
	popc_log_reader_options opt = {0};
	int st = popc_log_reader_open(&r->r, log_path, &opt, &e);
	if (st) {
		free(r);
		return popc_lib_fail(err, st, &e);
	}
	*out = r;
	return 0;
}

POPC_API int popc_lib_log_reader_column_count(const popc_lib_log_reader *r)
{
	return r->r.n_cols;
}

POPC_API const char *popc_lib_log_reader_column_name(const popc_lib_log_reader *r, int i)
{
	return i >= 0 && i < r->r.n_cols ? r->r.col_name[i] : NULL;
}

POPC_API int popc_lib_log_reader_header_count(const popc_lib_log_reader *r)
{
	return r->r.n_keys;
}

POPC_API const char *popc_lib_log_reader_header_key(const popc_lib_log_reader *r, int i)
{
	return i >= 0 && i < r->r.n_keys ? r->r.key[i] : NULL;
}

POPC_API const char *popc_lib_log_reader_header_value(const popc_lib_log_reader *r, int i)
{
	return i >= 0 && i < r->r.n_keys ? r->r.value[i] : NULL;
}

POPC_API int popc_lib_log_reader_next(popc_lib_log_reader *r, double *values, popc_lib_error *err)
{
	popc_error e;
	int st = popc_log_reader_next(&r->r, values, &e);
	return st < 0 ? popc_lib_fail(err, st, &e) : st;
}

POPC_API const char *popc_lib_log_reader_stop_reason(const popc_lib_log_reader *r)
{
	return r->r.stop_reason;
}

POPC_API int popc_lib_scene_from_log(popc_lib_scene *s, const popc_lib_log_reader *r,
				     popc_lib_error *err)
{
	/* a popc log says its format and source (popc_log_write_header); a
	 * recorded log has no scene to give, and its defaults would pass for one */
	if (!popc_log_reader_header(&r->r, "format") || !popc_log_reader_header(&r->r, "source")) {
		if (err)
			snprintf(err->msg, sizeof err->msg,
				 "%.400s: not a popc log (no '# format' and '# source' header lines): "
				 "it holds no scene",
				 r->r.path);
		return POPC_LIB_ERR_INVALID;
	}
	/* on a copy, so that a key refused half way leaves s as it was */
	popc_scene sc = s->scene;
	popc_error e;
	int st = popc_log_reader_scene(&r->r, &sc, &e);
	if (!st)
		s->scene = sc;
	return popc_lib_fail(err, st, &e);
}

POPC_API void popc_lib_log_reader_close(popc_lib_log_reader *r)
{
	if (!r)
		return;
	popc_log_reader_close(&r->r);
	free(r);
}
