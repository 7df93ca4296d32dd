#!/usr/bin/env bash
# Machine-readable summaries in JSON (docs/READING.md): popc run
# --summary-format json, popc-analyze compare --format json and a sweep's
# summary.jsonl, each read with python3's json module and compared with the
# CSV of the same table cell for cell (json_matches_csv.py), numbers bit
# for bit; empty cells are null; a bad --summary-format or --format is
# refused with exit 2.
#   test_json.sh POPC_ANALYZE
set -u
A=$1
POPC=${POPC:?}
SRC=${POPC_SOURCE_ROOT:?}
CHECK=$SRC/tests/cli/json_matches_csv.py
W=$(mktemp -d "${TMPDIR:-/tmp}/popc-json.XXXXXX")
trap 'rm -rf "$W"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
SCENE=$SRC/data/scenes/paper.ini
WALL=wall_time_s,realtime_factor,ns_per_tick

# popc run: the same two runs as CSV rows and as JSON lines (appended)
for v in ref-energy improved; do
	"$POPC" run "$SCENE" -q --variant $v --log "$W/$v.csv" --summary "$W/run.csv" || fail "run $v"
	"$POPC" run "$SCENE" -q --variant $v --summary "$W/run.jsonl" --summary-format json ||
		fail "run $v --summary-format json"
done
# a 0.05 s run: shorter than a chatter window
"$POPC" run "$SCENE" -q --set run.duration=0.05 --log "$W/short.csv" || fail "short run"
python3 "$CHECK" "$W/run.csv" "$W/run.jsonl" --skip $WALL || fail "popc run JSON differs from CSV"
# standard output: one line, no header
out=$("$POPC" run "$SCENE" -q --set run.duration=0.5 --summary - --summary-format json) &&
	[ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] &&
	printf '%s\n' "$out" | python3 -c 'import json,sys; d=json.loads(sys.stdin.read()); assert d["ticks"] == 501 and d["variant"] == "ref-energy", d' ||
	fail "--summary - --summary-format json: $out"
"$POPC" run "$SCENE" -q --summary "$W/x" --summary-format xml 2>"$W/err"
[ $? -eq 2 ] && grep -q "summary-format 'xml': csv or json" "$W/err" && [ ! -e "$W/x" ] ||
	fail "--summary-format xml: $(cat "$W/err")"

# compare: every column, with n/a cells (the short log's chatter) as null
logs=("$W/ref-energy.csv" "$W/improved.csv" "$W/short.csv")
"$A" compare --format csv "${logs[@]}" >"$W/compare.csv" 2>/dev/null || fail "compare csv"
"$A" compare --format json "${logs[@]}" >"$W/compare.jsonl" 2>/dev/null || fail "compare json"
python3 "$CHECK" "$W/compare.csv" "$W/compare.jsonl" --want-null chatter_s,limit_cycle ||
	fail "compare JSON differs from CSV"
"$A" compare --format yaml "${logs[0]}" >/dev/null 2>"$W/err"
[ $? -eq 2 ] && grep -q "markdown or json" "$W/err" || fail "compare --format yaml: $(cat "$W/err")"
# energy takes --format json since issue 27 (test_format_json.sh); a format
# it has not is refused, naming json among its own
"$A" energy --format yaml "${logs[0]}" >/dev/null 2>"$W/err"
[ $? -eq 2 ] && grep -q "text, csv or json" "$W/err" || fail "energy --format yaml: $(cat "$W/err")"

# a sweep: summary.jsonl beside summary.csv, the same rows, typed
"$POPC" sweep "$SCENE" -q -j 2 -o "$W/sweep" --set run.duration=0.3 \
	--vary controller.variant=none,improved --vary encoder.resolution=1e-5,1e-6 || fail "sweep"
python3 "$CHECK" "$W/sweep/summary.csv" "$W/sweep/summary.jsonl" || fail "sweep summary.jsonl differs"
python3 - "$W/sweep/summary.jsonl" <<'PY' || fail "sweep summary.jsonl types"
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
assert len(rows) == 4, rows
assert all(isinstance(r["run"], str) and isinstance(r["controller.variant"], str)
           and isinstance(r["encoder.resolution"], float) and isinstance(r["ticks"], int)
           for r in rows), rows
PY

[ $fails -eq 0 ] && echo "JSON summaries: all equal their CSV" || echo "$fails failure(s)"
[ $fails -eq 0 ]
