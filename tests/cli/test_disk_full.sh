#!/usr/bin/env bash
# A disk that fills mid-run: popc run exits 1 naming the log, and the log left
# is a valid prefix: whole rows, then "# stop = log write failed: ..." where
# the space allowed; popc-analyze reads it (energy --check: the rows are what
# ran). Without root: a file size limit (ulimit -f) stands for the full
# disk; /dev/full gives ENOSPC at once. popc of 46f30c1 left the row cut at
# the limit and no stop line, and popc-analyze refused the whole file (exit
# 2). popc itself ignores SIGXFSZ, so that the write fails with EFBIG: this
# script ignores no signal (until issue 28 it set trap '' XFSZ, which hid
# that popc was killed by SIGXFSZ at the limit, exit 153).
set -u
POPC=${POPC:?POPC must name the popc program}
case $POPC in /*) ;; *) POPC=$PWD/$POPC ;; esac
SRC=${POPC_SOURCE_ROOT:?}
A=${1:-${POPC_ANALYZE:?popc-analyze: argument 1 or POPC_ANALYZE}}
T=$(mktemp -d /tmp/popc-full-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
SCENE=$SRC/data/scenes/paper.ini

# 100 to 104 KiB (ulimit -f counts 1024 bytes): the paper log is 0.75 MB, so
# each run stops near 1.1 s, each limit cutting a row at another place
with_stop=0 without_stop=0
for kib in 100 101 102 103 104; do
	log=$T/full$kib.csv
	(ulimit -f "$kib"; exec "$POPC" run "$SCENE" --log "$log" -q) 2>"$T/err"
	rc=$?
	check "limit $kib KiB: exit 1 (got $rc)" test "$rc" -eq 1
	check "  names the log and why" err_has "popc run: $log: write failed: File too large"
	check "  within the limit" test "$(stat -c %s "$log")" -le $((kib * 1024))
	check "  ends with a whole line" test "$(tail -c 1 "$log" | od -An -c | tr -d ' ')" = '\n'
	last=$(tail -n 1 "$log")
	case $last in
	"# stop = log write failed: $log: write failed: File too large") with_stop=$((with_stop + 1)) ;;
	[0-9]*) without_stop=$((without_stop + 1))
		check "  the last row is whole (12 cells)" test "$(echo "$last" | awk -F, '{print NF}')" -eq 12 ;;
	*) bad "  ends in neither a row nor the stop line: '$last'" ;;
	esac
	expect_exit 0 "  popc-analyze energy --check reads it" "$A" energy --check "$log"
	rows=$(grep -c '^[0-9]' "$log")
	if [ "${last#\# stop}" = "$last" ]; then
		check "  with a note naming the file and its last row's line" \
			err_has "popc-analyze energy: note: $log: unfinished log: no '# stop = ...' line; its $rows whole rows to line $(grep -c '' "$log") are read"
	else
		check "  without a note (it has its stop line)" test ! -s "$T/err"
	fi
	expect_exit 0 "  compare reads its $rows rows" "$A" compare --format csv "$log"
	check "  $rows ticks" bash -c "tail -n 1 '$T/out' | cut -d, -f3 | grep -qx '$rows'"
done
check "the stop line fitted at some limits ($with_stop) and not at others ($without_stop)" \
	test "$with_stop" -gt 0 -a "$without_stop" -gt 0

# no room at all: refused before the first tick, named
expect_exit 1 "--log /dev/full" "$POPC" run "$SCENE" --log /dev/full -q
check "  names it and why" err_has "popc run: /dev/full: write failed: No space left on device"
expect_exit 1 "--log - onto a full standard output" bash -c "'$POPC' run '$SCENE' --log - -q > /dev/full"
check "  names it and why" err_has "popc run: -: write failed: No space left on device"
check_summary
