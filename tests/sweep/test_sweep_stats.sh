#!/bin/sh
# popc sweep stats: the distribution per group, on a summary whose answer is
# known by construction and on a real sweep (checked against awk), and its
# refusals.
set -u
W=$(mktemp -d "${TMPDIR:-/tmp}/popc-sweep-stats.XXXXXX") || exit 99
trap 'rm -rf "$W"' EXIT
FAILS=0
fail() { echo "FAIL: $*" >&2; FAILS=$((FAILS + 1)); }
ok() { echo "ok: $*"; }

# group a: pc_rms_late 1,2,3,4,10 (median 3, q1 2, q3 4, min 1, max 10); a failed
# run (exit 1, 99) is left out; group b: 0.5 and one empty chatter cell
mkdir -p "$W/fake"
cat >"$W/fake/summary.csv" <<'CSV'
run,controller.variant,exit_status,pc_rms_late,chatter_s,wall_time_s
0000,a,0,3,0.1,1
0001,a,0,1,0.2,1
0002,a,0,10,0.3,1
0003,a,0,2,0.4,1
0004,a,1,99,0.5,1
0005,a,0,4,0.5,1
0006,b,0,0.5,,1
0007,b,0,1.5,2,1
CSV
"$POPC" sweep stats "$W/fake" --by controller.variant --metrics pc_rms_late,chatter_s --format csv \
	>"$W/out" 2>"$W/err" || fail "stats on the fake summary: $(cat "$W/err")"
want='controller.variant,metric,n,median,min,q1,q3,max
a,pc_rms_late,5,3,1,2,4,10
a,chatter_s,5,0.3,0.1,0.2,0.4,0.5
b,pc_rms_late,2,1,0.5,0.75,1.25,1.5
b,chatter_s,1,2,2,2,2,2'
[ "$(cat "$W/out")" = "$want" ] && ok "known summary: n, median, quartiles, range" ||
	fail "known summary: $(cat "$W/out")"
grep -q "1 failed run left out" "$W/err" && ok "the failed run is counted in a note" ||
	fail "no note on the failed run: $(cat "$W/err")"
"$POPC" sweep stats "$W/fake" --by controller.variant --metrics pc_rms_late >"$W/out" &&
	grep -q '^a  5  3 \[1, 10\]$' "$W/out" && ok "text: median [min, max]" || fail "text: $(cat "$W/out")"

# a real sweep: the medians equal awk's over summary.csv
"$POPC" sweep "$POPC_SOURCE_ROOT/data/scenes/paper.ini" --vary controller.variant=none,improved \
	--vary operator.x0=-0.0065,-0.0064995,-0.006499 --set run.duration=1 --no-log -o "$W/real" -q -j 2 ||
	fail "the sweep failed"
"$POPC" sweep stats "$W/real" --by controller.variant --metrics pc_rms --format csv >"$W/out" ||
	fail "stats on a real sweep"
for v in none improved; do
	want=$(awk -F, -v v="$v" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
		$c["controller.variant"] == v { print $c["pc_rms"] }' "$W/real/summary.csv" | sort -g | sed -n 2p)
	got=$(awk -F, -v v="$v" '$1 == v { print $4 }' "$W/out")
	awk -v a="$want" -v b="$got" 'BEGIN { exit !(a + 0 == b + 0) }' &&
		ok "real sweep, $v: median pc_rms $got" || fail "real sweep, $v: median $got, awk $want"
done

# refusals: exit 2, naming what is wrong
refuse() {
	what=$1; pattern=$2; shift 2
	"$POPC" sweep stats "$@" >/dev/null 2>"$W/err"
	rc=$?
	[ "$rc" -eq 2 ] && grep -q -- "$pattern" "$W/err" && ok "refused: $what" ||
		fail "$what: exit $rc, $(cat "$W/err")"
}
refuse "no --by" "missing --by" "$W/fake"
refuse "a --by column the summary lacks" "no such column" "$W/fake" --by operator.x0
refuse "a metric that is not one" "not a metric column" "$W/fake" --by controller.variant --metrics wall_time_s
refuse "no summary" "summary.csv" "$W/none" --by controller.variant
refuse "a bad format" "text, csv, markdown or json" "$W/fake" --by controller.variant --format xml
# --by names varied keys only (the columns between run and exit_status),
# each once, no empty item (issue 28: all of these were accepted)
refuse "--by a metric" "--by pc_rms_late: $W/fake/summary.csv names no varied key there" "$W/fake" --metrics pc_rms_late --by pc_rms_late
refuse "--by run" "--by run: $W/fake/summary.csv names no varied key there" "$W/fake" --metrics pc_rms_late --by run
refuse "--by exit_status" "--by exit_status: $W/fake/summary.csv names no varied key there" "$W/fake" --metrics pc_rms_late --by exit_status
refuse "--by a key twice" "--by controller.variant,controller.variant: 'controller.variant' given twice (items 1 and 2)" "$W/fake" --metrics pc_rms_late --by controller.variant,controller.variant
refuse "--by an empty item" "--by controller.variant,: item 2 is empty" "$W/fake" --metrics pc_rms_late --by controller.variant,
refuse "--by an empty item inside" "--by ,controller.variant: item 1 is empty" "$W/fake" --metrics pc_rms_late --by ,controller.variant
refuse "--metrics an empty item" "--metrics pc_rms_late,,chatter_s: item 2 is empty" "$W/fake" --by controller.variant --metrics pc_rms_late,,chatter_s

# values at the ends of the doubles: the interpolation between 1.7e308 and
# -1.7e308 overflowed (a median of inf, a min of nan); the median of the two
# is their mean, 0, and min and max are the values themselves; a quartile
# is the weighted mean 0.75 (-1.7e308) + 0.25 (1.7e308), -8.5e307 within
# its rounding (an ulp below)
mkdir -p "$W/big"
cat >"$W/big/summary.csv" <<'CSV'
run,controller.variant,exit_status,pc_rms_late,wall_time_s
0000,a,0,1.7e308,1
0001,a,0,-1.7e308,1
0002,b,0,1.7e308,1
0003,b,0,1.7e308,1
0004,b,0,-1.7e308,1
CSV
"$POPC" sweep stats "$W/big" --by controller.variant --metrics pc_rms_late --format csv >"$W/out" 2>"$W/err" ||
	fail "stats at the ends of the doubles: $(cat "$W/err")"
want='controller.variant,metric,n,median,min,q1,q3,max
a,pc_rms_late,2,0,-1.7e+308,-8.499999999999999e+307,8.499999999999999e+307,1.7e+308
b,pc_rms_late,3,1.7e+308,-1.7e+308,0,1.7e+308,1.7e+308'
[ "$(cat "$W/out")" = "$want" ] && ok "1.7e308 and -1.7e308: finite median, min, quartiles" ||
	fail "at the ends of the doubles: $(cat "$W/out")"

# markdown: a '|' in a value is escaped, so the row keeps its cells
mkdir -p "$W/pipe"
printf 'run,operator.table,exit_status,pc_rms_late,wall_time_s\n0000,a|b.csv,0,1,1\n' >"$W/pipe/summary.csv"
"$POPC" sweep stats "$W/pipe" --by operator.table --metrics pc_rms_late --format markdown >"$W/out" 2>"$W/err" ||
	fail "markdown with a '|': $(cat "$W/err")"
grep -qxF '| a\|b.csv | 1 | 1 [1, 1] |' "$W/out" && ok "markdown: '|' in a value escaped" ||
	fail "markdown: $(cat "$W/out")"

[ "$FAILS" -eq 0 ] || { echo "$FAILS failure(s)" >&2; exit 1; }
