/* Parameter sweeps (docs/SWEEPS.md): everything `popc sweep` and `popc sweep
 * merge` use, one header per file of src/sweep/, in the order they call each
 * other (each calls only those above it; tests/layers/call_cycles.py checks
 * there is no cycle):
 *
 *   sweep_files.h    atomic writes, mkdir -p, whole-file reads
 *   sweep_columns.h  summary.csv's columns, one table; the header
 *   sweep_plan.h     values and ranges, the product, run ids, plan ids, shards
 *   sweep_row.h      a run's summary row, built by the table and read back
 *   sweep_chatter.h  the chatter columns' detector, online or from a log
 *   sweep_dir.h      the sweep directory: plan file, run directories, rows files
 *   sweep_results.h  the best row of every run; summary.csv in id order
 *   sweep_run.h      one run in this process
 *
 * (the plan hashes the header, so the table sits below the plan; a row names
 * its run's id and values, so it sits above). */
#ifndef POPC_SWEEP_H
#define POPC_SWEEP_H

#include "popc/sweep/sweep_files.h"
#include "popc/sweep/sweep_columns.h"
#include "popc/sweep/sweep_plan.h"
#include "popc/sweep/sweep_row.h"
#include "popc/sweep/sweep_chatter.h"
#include "popc/sweep/sweep_dir.h"
#include "popc/sweep/sweep_results.h"
#include "popc/sweep/sweep_run.h"
#include "popc/sweep/sweep_map.h"

#endif
