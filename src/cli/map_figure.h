/* popc map's figure (map_figure.c): a gnuplot script over DIR/boundary.csv,
 * kept as DIR/map.gp, and its PNG and PDF. */
#ifndef POPC_CLI_MAP_FIGURE_H
#define POPC_CLI_MAP_FIGURE_H

#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

/* Writes DIR/map.gp for the map's plan (the boundary.csv columns of
 * cmd_map.c: the axes, then criterion, outcome, k_ok, k_bad, ...), one
 * curve per variant and criterion (criteria: their names in boundary.csv). */
int popc_map_figure_write(const popc_sweep_plan *p, const char *dir, const char *const *criteria,
			  int n_criteria, popc_error *err);

/* Runs gnuplot on DIR/map.gp (in DIR): DIR/map.png and DIR/map.pdf. */
int popc_map_figure_plot(const char *dir, popc_error *err);

#endif
