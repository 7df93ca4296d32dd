/* The log's column table as data (log_columns.h). */
#include "popc/log/log_columns.h"

#include <string.h>

const popc_log_column popc_log_columns[POPC_LOG_N_COLUMNS] = {
#define COLUMN_ENTRY(ID, name, unit, fill, format, field, meaning)                                  \
	[POPC_LOG_COLUMN_##ID] = {#name, unit, meaning, POPC_LOG_COL_##fill, POPC_LOG_CELL_##format},
	POPC_LOG_COLUMN_TABLE(COLUMN_ENTRY)
#undef COLUMN_ENTRY
};

int popc_log_column_find(const char *name)
{
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++)
		if (strcmp(popc_log_columns[id].name, name) == 0)
			return id;
	return -1;
}

int popc_log_column_index(unsigned columns, popc_log_column_id id)
{
	if ((int)id < 0 || id >= POPC_LOG_N_COLUMNS ||
	    !popc_log_column_written(popc_log_columns[id].fill, columns))
		return -1;
	int index = 0;
	for (int k = 0; k < (int)id; k++)
		index += popc_log_column_written(popc_log_columns[k].fill, columns);
	return index;
}

size_t popc_log_column_names(unsigned columns, char *buf, size_t cap)
{
	size_t len = 0;
	for (int id = 0; id < POPC_LOG_N_COLUMNS; id++) {
		if (!popc_log_column_written(popc_log_columns[id].fill, columns))
			continue;
		const char *name = popc_log_columns[id].name;
		const size_t n = strlen(name);
		if (len + (len > 0) + n >= cap)
			break; /* cap below POPC_LOG_NAMES_LINE_MAX: the names that fit */
		if (len > 0)
			buf[len++] = ',';
		memcpy(buf + len, name, n);
		len += n;
	}
	if (cap > 0)
		buf[len] = '\0';
	return len;
}

double popc_log_row_get(const popc_log_row *r, popc_log_column_id id)
{
	switch (id) {
#define GET_CELL(ID, name, unit, fill, format, field, meaning)                                      \
	case POPC_LOG_COLUMN_##ID: return (double)r->field;
		POPC_LOG_COLUMN_TABLE(GET_CELL)
#undef GET_CELL
	case POPC_LOG_N_COLUMNS: break;
	}
	return 0.0;
}

/* a cell's double as its field's type (the value must be representable) */
#define FROM_DOUBLE_DOUBLE(v) (v)
#define FROM_DOUBLE_COUNT(v) ((long long)(v))
#define FROM_DOUBLE_FLAGS(v) ((unsigned)(v))

void popc_log_row_set(popc_log_row *r, popc_log_column_id id, double value)
{
	switch (id) {
#define SET_CELL(ID, name, unit, fill, format, field, meaning)                                      \
	case POPC_LOG_COLUMN_##ID: r->field = FROM_DOUBLE_##format(value); break;
		POPC_LOG_COLUMN_TABLE(SET_CELL)
#undef SET_CELL
	case POPC_LOG_N_COLUMNS: break;
	}
}
