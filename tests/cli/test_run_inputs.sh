#!/usr/bin/env bash
# popc run's options that could do nothing or damage silently (issue 28):
# - --summary onto a file that holds the other format (CSV under JSON Lines
#   or the reverse) is refused before any work, exit 2, naming the file and
#   the format it holds; the file stays byte for byte;
# - a run that fails before its first tick (the log cannot be opened) leaves
#   no summary file behind that it created (it left a 0-byte one);
# - --map and --connect with the simulated axis are refused, exit 2, naming
#   the option and axis.kind (they set keys only a Modbus axis reads).
# Each case failed on popc before issue 28: the mixed summaries were
# appended (exit 0), the empty summary was left, --connect was ignored.
set -u
POPC=${POPC:?POPC must name the popc program}
case $POPC in /*) ;; *) POPC=$PWD/$POPC ;; esac
SRC=${POPC_SOURCE_ROOT:?}
T=$(mktemp -d /tmp/popc-runin-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
SCENE=$SRC/data/scenes/paper.ini
RUN=(run "$SCENE" -q --set run.duration=0.01)

# --- summaries: one format per file
expect_exit 0 "a CSV summary" "$POPC" "${RUN[@]}" --summary "$T/s.csv"
cp "$T/s.csv" "$T/keep.csv"
expect_exit 2 "  then JSON into it" "$POPC" "${RUN[@]}" --summary "$T/s.csv" --summary-format json
check "  names the file and what it holds" err_has "popc run: --summary $T/s.csv holds CSV (line 1 is not a JSON object: a CSV header): refusing to append a JSON line to it (give --summary-format csv, or another file)"
check "  the file is unchanged" cmp -s "$T/s.csv" "$T/keep.csv"
expect_exit 0 "  CSV again appends" "$POPC" "${RUN[@]}" --summary "$T/s.csv" --summary-format csv
check "  one header, two rows" test "$(grep -c '' "$T/s.csv")" -eq 3

expect_exit 0 "a JSON Lines summary" "$POPC" "${RUN[@]}" --summary "$T/s.jsonl" --summary-format json
cp "$T/s.jsonl" "$T/keep.jsonl"
expect_exit 2 "  then CSV into it" "$POPC" "${RUN[@]}" --summary "$T/s.jsonl"
check "  names the file and what it holds" err_has "popc run: --summary $T/s.jsonl holds JSON Lines (line 1 is a JSON object): refusing to append a CSV row to it (give --summary-format json, or another file)"
check "  the file is unchanged" cmp -s "$T/s.jsonl" "$T/keep.jsonl"
expect_exit 0 "  JSON again appends" "$POPC" "${RUN[@]}" --summary "$T/s.jsonl" --summary-format json
check "  two lines" test "$(grep -c '' "$T/s.jsonl")" -eq 2
: >"$T/empty"
expect_exit 0 "an empty file takes either format" "$POPC" "${RUN[@]}" --summary "$T/empty" --summary-format json
check "  one JSON line" test "$(grep -c '^{' "$T/empty")" -eq 1
expect_exit 2 "refused before any work: no log written" \
	"$POPC" "${RUN[@]}" --summary "$T/s.csv" --summary-format json --log "$T/nolog.csv"
check "  no log" test ! -e "$T/nolog.csv"

# --- a run that cannot open its log leaves no summary it created
expect_exit 1 "--log in a missing directory" "$POPC" "${RUN[@]}" --summary "$T/new.csv" --log "$T/nodir/x.csv"
check "  names the log" err_has "$T/nodir/x.csv"
check "  no summary file left behind" test ! -e "$T/new.csv"
cp "$T/keep.csv" "$T/old.csv"
expect_exit 1 "  with a summary that existed" "$POPC" "${RUN[@]}" --summary "$T/old.csv" --log "$T/nodir/x.csv"
check "  it stays as it was" cmp -s "$T/old.csv" "$T/keep.csv"

# --- Modbus options on the simulated axis
expect_exit 2 "--connect with the simulated axis" "$POPC" "${RUN[@]}" --connect tcp:127.0.0.1:1502
check "  names the option and axis.kind" err_has "popc run: --connect tcp:127.0.0.1:1502: only for axis.kind = modbus, and axis.kind is sim (give --axis modbus, or leave --connect out)"
expect_exit 2 "--map with the simulated axis" "$POPC" "${RUN[@]}" --map "$SRC/data/drives/generic.ini" --log "$T/map.csv"
check "  names the option and axis.kind" err_has "popc run: --map $SRC/data/drives/generic.ini: only for axis.kind = modbus, and axis.kind is sim"
check "  nothing ran" test ! -e "$T/map.csv"
expect_exit 2 "--axis sim named as well" "$POPC" "${RUN[@]}" --axis sim --connect tcp:127.0.0.1:1502
check "  refused" err_has "only for axis.kind = modbus, and axis.kind is sim"
check_summary
