/* A program's table output as CSV or JSON Lines (table_out.h). */
#include "popc/programs/table_out.h"

#include <stdlib.h>
#include <string.h>

int popc_table_out_begin(popc_table_out *t, FILE *f, int json, const char *header,
			 const char *const *text_names)
{
	memset(t, 0, sizeof *t);
	t->f = f;
	t->json = json;
	if (!json) {
		fprintf(f, "%s\n", header);
		return 0;
	}
	t->names_line = strdup(header);
	if (!t->names_line)
		return -1; /* nothing written, nothing to free */
	t->n = popc_json_csv_names(t->names_line, t->names, POPC_TABLE_COLUMNS_MAX);
	for (int i = 0; i < t->n; i++) {
		t->kinds[i] = POPC_JSON_NUMBER;
		for (int k = 0; text_names && text_names[k]; k++)
			if (strcmp(t->names[i], text_names[k]) == 0)
				t->kinds[i] = POPC_JSON_TEXT;
	}
	return 0;
}

/* JSON: a fresh stream for the rows; when out of memory, /dev/null and the
 * error kept for flush (the caller's writes need a stream either way) */
static void open_rows(popc_table_out *t)
{
	t->rows = open_memstream(&t->buf, &t->len);
	if (!t->rows) {
		t->rows = fopen("/dev/null", "w");
		t->failed = 1;
	}
}

FILE *popc_table_out_row(popc_table_out *t)
{
	if (!t->json)
		return t->f;
	if (!t->rows)
		open_rows(t);
	return t->rows ? t->rows : stderr; /* not even /dev/null: a last resort */
}

int popc_table_out_flush(popc_table_out *t)
{
	if (!t->json || !t->rows)
		return t->failed ? -1 : 0;
	if (fclose(t->rows) != 0)
		t->failed = 1;
	t->rows = NULL;
	/* one object a row: a line ends at a '\n' outside quotes (a quoted cell
	 * may hold one) */
	size_t at = 0;
	int quoted = 0;
	for (size_t k = 0; t->buf && k < t->len; k++) {
		if (t->buf[k] == '"')
			quoted = !quoted;
		else if (t->buf[k] == '\n' && !quoted) {
			popc_json_csv_object(t->f, t->n, t->names, t->kinds, t->buf + at, k - at);
			at = k + 1;
		}
	}
	if (t->buf && at < t->len)
		popc_json_csv_object(t->f, t->n, t->names, t->kinds, t->buf + at, t->len - at);
	free(t->buf);
	t->buf = NULL;
	t->len = 0;
	return t->failed ? -1 : 0;
}
int popc_table_out_end(popc_table_out *t)
{
	int st = popc_table_out_flush(t);
	free(t->names_line);
	t->names_line = NULL;
	return st;
}
