# No output of popc-analyze replaces a log it reads: energy -o onto its
# input, a replay prefix that names its input, a report directory holding a log
# called compare.csv or NAME.dat or a figure name (also through a link). Each is
# refused with exit 2, naming both files, and the input stays byte for byte.
. "$2"
# 1 s: long enough for the limit cycle (half its 2 s window), so that report
# prints no "limit cycle not checked" note and its messages can be counted
run_scene paper.ini "$W/good.csv" --set run.duration=1
cp "$W/good.csv" "$W/keep.csv"
same() { cmp -s "$W/keep.csv" "$1"; }

cp "$W/good.csv" "$W/in.csv"
expect_rc 2 "$A" energy -o "$W/in.csv" "$W/in.csv" &&
	grep -q "energy: -o $W/in.csv is the input log $W/in.csv: refusing to overwrite it" "$W/err" &&
	same "$W/in.csv" && ok "energy -o LOG LOG refused, log intact" || fail "energy -o onto input: $(cat "$W/err")"

cp "$W/good.csv" "$W/x.none.csv"
expect_rc 2 "$A" replay -q --variant improved --variant none --prefix "$W/x." "$W/x.none.csv" &&
	grep -q "replay: $W/x.none.csv is the input log" "$W/err" && same "$W/x.none.csv" &&
	[ ! -e "$W/x.improved.csv" ] && ok "replay onto its input refused before any output is opened" ||
	fail "replay onto input: $(cat "$W/err")"

mkdir "$W/r1" "$W/r2" "$W/r3"
cp "$W/good.csv" "$W/r1/compare.csv"
expect_rc 2 "$A" report --no-draw -o "$W/r1" "$W/r1/compare.csv" &&
	grep -q "report: $W/r1/compare.csv is the input log" "$W/err" && same "$W/r1/compare.csv" &&
	ok "report: a log named compare.csv in DIR kept" || fail "report compare.csv: $(cat "$W/err")"
# run.csv's data file would be run.dat, the second input
cp "$W/good.csv" "$W/r2/run.csv"
cp "$W/good.csv" "$W/r2/run.dat"
expect_rc 2 "$A" report --no-draw -o "$W/r2" "$W/r2/run.csv" "$W/r2/run.dat" &&
	grep -q "report: $W/r2/run.dat is the input log" "$W/err" && same "$W/r2/run.dat" &&
	ok "report: a log named like another's data file kept" || fail "report run.dat: $(cat "$W/err")"
# one clear message, the refusal, and no second line about the same failure
[ "$(grep -c '' "$W/err")" -eq 1 ] && ok "report refusal: one message" ||
	fail "report refusal: $(grep -c '' "$W/err") lines: $(cat "$W/err")"
# a file that cannot be written (a link to /dev/full: ENOSPC at close) is named
# once, with why, for the data file and for the tables
if [ -w /dev/full ]; then
	mkdir "$W/r4" "$W/r5"
	ln -s /dev/full "$W/r4/good.dat"
	expect_rc 2 "$A" report --no-draw -o "$W/r4" "$W/good.csv" &&
		[ "$(cat "$W/err")" = "popc-analyze report: $W/r4/good.dat: write failed: No space left on device" ] &&
		ok "report: a data file that cannot be written, one message" || fail "report /dev/full dat: $(cat "$W/err")"
	ln -s /dev/full "$W/r5/compare.md"
	expect_rc 2 "$A" report --no-draw -o "$W/r5" "$W/good.csv" &&
		[ "$(cat "$W/err")" = "popc-analyze report: $W/r5/compare.md: write failed: No space left on device" ] &&
		ok "report: a table that cannot be written, one message" || fail "report /dev/full md: $(cat "$W/err")"
fi
if command -v gnuplot >/dev/null 2>&1; then
	# the figure b.png is the log itself, reached through the link b.csv
	cp "$W/good.csv" "$W/r3/b.png"
	ln -s b.png "$W/r3/b.csv"
	expect_rc 2 "$A" report -o "$W/r3" "$W/r3/b.csv" &&
		grep -q "report: $W/r3/b.png is the input log $W/r3/b.csv" "$W/err" && same "$W/r3/b.png" &&
		ok "report: a figure that is the log (a link) refused" || fail "report figure: $(cat "$W/err")"
fi
# writing beside the log with other names still works
expect_rc 0 "$A" energy -o "$W/in.energy.csv" "$W/in.csv" && [ -s "$W/in.energy.csv" ] &&
	ok "energy -o another file" || fail "energy -o another file"
finish
