#!/usr/bin/env bash
# --format json wherever --format is (issue 27: `events --format json`
# printed text with exit 0, `sweep stats --format json` was refused): events,
# chatter, energy, compare, sweep stats and bench. Each JSON line is valid
# JSON (python3's json, strict) and, but for bench (its timings differ run to
# run), equals the same command's --format csv row cell for cell with the
# very digits of the CSV (json_matches_csv.py --digits). A bad --format names
# json among the formats. sweep stats --format csv quotes a cell with a comma
# (RFC 4180), which it did not.
set -u
POPC=${POPC:?POPC must name the popc program}
ANALYZE=${1:?usage: test_format_json.sh POPC_ANALYZE}
SRC=${POPC_SOURCE_ROOT:?}
T=$(mktemp -d /tmp/popc-format-json-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
CHECK=$SRC/tests/cli/json_matches_csv.py
export POPC_DATA_PATH="$SRC/data"
cd "$T" || exit 1

# two short logs: one that chatters (ref-energy from 3.05 s), one that does not
"$POPC" run paper --set run.duration=4 --variant ref-energy --log ref-energy.csv -q
"$POPC" run paper --set run.duration=4 --variant improved --log improved.csv -q

# both FORMAT-less commands: csv into $T/NAME.csv, json into $T/NAME.jsonl
pair() {
  local name=$1; shift
  "$@" --format csv >"$name.csv" 2>"$name.csv.err"
  local rc_csv=$?
  "$@" --format json >"$name.jsonl" 2>"$name.json.err"
  local rc_json=$?
  check "$name: --format json exits as --format csv ($rc_json, $rc_csv)" test "$rc_json" -eq "$rc_csv"
  check "$name: JSON lines, one per CSV row, the same digits" python3 "$CHECK" "$name.csv" "$name.jsonl" --digits
}
pair events "$ANALYZE" events ref-energy.csv improved.csv
check "  events: an empty cell is null (improved has no Fig. 5 event)" grep -q '"fig5_s":null' events.jsonl
pair chatter "$ANALYZE" chatter ref-energy.csv improved.csv
pair energy "$ANALYZE" energy ref-energy.csv improved.csv
pair compare "$ANALYZE" compare ref-energy.csv improved.csv

"$POPC" sweep paper --set run.duration=1 --vary controller.variant=none,improved \
  --vary encoder.resolution=1e-5,2e-5 -o sw --no-log -q -j 1 2>sweep.err
check "a small sweep" test -s sw/summary.csv
pair stats "$POPC" sweep stats sw --by controller.variant
check "  stats: the group's value a string, a metric's n a number" \
  grep -q '"controller.variant":"improved","metric":"pc_rms_late","n":2,' stats.jsonl

# a group's value with a comma (a summary cell quoted as RFC 4180 has it):
# quoted again in the CSV, one string in the JSON
mkdir -p quoted
awk -F, -v OFS=, 'NR > 1 && $2 == "improved" { $2 = "\"improved,x\"" } { print }' sw/summary.csv >quoted/summary.csv
"$POPC" sweep stats quoted --by controller.variant --format csv >quoted.csv 2>quoted.err
check "stats --format csv: a value with a comma is quoted" grep -q '^"improved,x",pc_rms_late,2,' quoted.csv
check "  and reads back as one cell" python3 -c '
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
assert all(len(r) == len(rows[0]) for r in rows), rows
assert any(r[0] == "improved,x" for r in rows)' quoted.csv
"$POPC" sweep stats quoted --by controller.variant --format json >quoted.jsonl 2>>quoted.err
check "  json: the same cells" python3 "$CHECK" quoted.csv quoted.jsonl --digits

"$POPC" bench loop --min-time 0 --repeat 1 --format json >bench.jsonl 2>bench.err
check "bench loop --format json: exit 0" test $? -eq 0
check "  valid JSON lines with the CSV's names" python3 -c '
import json, sys
lines = open(sys.argv[1]).read().splitlines()
assert lines, "no lines"
for l in lines:
    o = json.loads(l, parse_constant=lambda c: 1 / 0)
    assert list(o)[0] == "what" and "exact" in o and "ratio" in o, o
' bench.jsonl

for cmd in "$ANALYZE events" "$ANALYZE chatter" "$ANALYZE energy" "$POPC sweep stats sw --by controller.variant"; do
  expect_exit 2 "${cmd##*/} --format xml refused" $cmd improved.csv --format xml
  check "  the message names json" err_has json
done
expect_exit 2 "bench --format xml refused" "$POPC" bench loop --format xml
check "  the message names json" err_has json
check_summary
