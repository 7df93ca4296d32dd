#!/usr/bin/env bash
# Real readers type every summary's columns right (docs/READING.md,
# "Summaries: CSV and JSON"): every real column floating point (DuckDB
# DOUBLE, pandas float64), the counts integers, the run ids strings, with
# the recipes READING.md gives, in each summary popc writes: a sweep's
# summary.csv and summary.jsonl, `popc run --summary` CSV and JSON, and
# `popc-analyze compare` CSV and JSON.
#
#   summaries.sh pandas|duckdb   (POPC, POPC_ANALYZE, POPC_SOURCE_ROOT,
#                                 POPC_BUILD_ROOT from the environment)
#
# The case: rows whose real cells are all integral first. The sweep's first
# half is variant none (pc_rms, pc_max, pc_active, pc_energy, pc_rms_late,
# chatter_s 0) and its integrator is exact (integrator_error_m 0 in every
# row); the run summaries and the compare rows start with such a run too.
# Cells written "0" were typed BIGINT by DuckDB and int64 by pandas (issue
# 27). DuckDB samples 20480 rows to type a column; the test reads with
# sample_size = 1, so that a few rows stand for a big sweep's first 20480.
set -u
READER=${1:?pandas or duckdb}
POPC=${POPC:?}
ANALYZE=${POPC_ANALYZE:?}
SRC=${POPC_SOURCE_ROOT:?}
HERE=$SRC/tests/readers
W=$(mktemp -d "${TMPDIR:-/tmp}/popc-summaries.XXXXXX")
trap 'rm -rf "$W"' EXIT
die() { echo "FAIL: $*" >&2; exit 1; }
skip() { echo "SKIP: $*" >&2; exit 77; }

case $READER in
pandas)
	PY=
	for p in python3 /usr/bin/python3; do
		"$p" -c 'import pandas' 2>/dev/null && { PY=$p; break; }
	done
	[ -n "$PY" ] ||
		skip "no python3 imports pandas (Debian: apt-get install python3-pandas; tools/install-deps.sh test)" ;;
duckdb)
	NPM=${POPC_BUILD_ROOT:?}/tests/summaries-npm
	. "$HERE/duckdb_npm.sh"
	cp "$HERE/summary_types.mjs" "$NPM/" ;; # node finds node_modules beside the script
*) die "unknown reader $READER" ;;
esac

export POPC_DATA_PATH=$SRC/data
cd "$W" || die "cannot enter $W"
# a sweep: 3 runs of none, then 3 of improved (the last --vary is the fastest)
"$POPC" sweep paper --vary controller.variant=none,improved --vary environment.stiffness=1000:4000:3 \
	--set run.duration=1 -o sweep -j 2 -q || die "sweep failed"
# run summaries, none first, in CSV and in JSON; their logs for compare
for v in none improved; do
	"$POPC" run paper -q --set run.duration=1 --variant "$v" --log "$v.csv" --summary run.csv || die "run $v failed"
	"$POPC" run paper -q --set run.duration=1 --variant "$v" --summary run.jsonl --summary-format json ||
		die "run $v (json) failed"
done
"$ANALYZE" compare --format csv none.csv improved.csv >compare.csv || die "compare --format csv failed"
"$ANALYZE" compare --format json none.csv improved.csv >compare.jsonl || die "compare --format json failed"
# the case is there: the first row's pc_rms and the sweep's integrator_error_m are 0
grep -q '"pc_rms":0' sweep/summary.jsonl || die "the sweep's first rows have no zero pc_rms"

files=(sweep/summary.csv sweep/summary.jsonl run.csv run.jsonl compare.csv compare.jsonl)
if [ "$READER" = pandas ]; then
	"$PY" "$HERE/summary_types.py" "${files[@]}"
else
	(cd "$NPM" && node summary_types.mjs "${files[@]/#/$W/}")
fi
