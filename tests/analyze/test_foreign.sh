# Logs recorded elsewhere, in the shapes other tools write them: each reads to
# the same numbers as the plain CSV it came from (compare's CSV row, the log
# name aside), or is refused naming the file, line and column.
. "$2"
run_scene paper.ini "$W/popc.csv" --set run.duration=1
grep -v '^#' "$W/popc.csv" | cut -d, -f1,2,8 >"$W/plain.csv"     # t,x,f_c
expect_rc 0 "$A" compare --format csv "$W/plain.csv" || finish
tail -n 1 "$W/out" | cut -d, -f2- >"$W/want"
# same_as FILE [options]: FILE's compare row equals plain.csv's
same_as() {
	f=$1; shift
	if expect_rc 0 "$A" compare --format csv "$@" "$W/$f"; then
		tail -n 1 "$W/out" | cut -d, -f2- | cmp -s - "$W/want" && return 0
		fail "$f: row differs: $(tail -n 1 "$W/out")"
	fi
	return 1
}

sed 's/$/\r/' "$W/plain.csv" >"$W/crlf.csv"
same_as crlf.csv && ok "CRLF line ends"
awk -F, '{ print "\"" $1 "\",\"" $2 "\",\"" $3 "\"" }' "$W/plain.csv" >"$W/quoted.csv"
same_as quoted.csv && ok "every cell in double quotes (RFC 4180)"
# pandas' to_csv: an unnamed index column first
awk 'NR == 1 { print "," $0; next } { print NR - 2 "," $0 }' "$W/plain.csv" >"$W/pandas.csv"
same_as pandas.csv && ok "pandas index column (empty name)"
sed 's/$/,/' "$W/plain.csv" >"$W/trailing.csv"
same_as trailing.csv && ok "a delimiter at the end of every line"
# columns the analysis does not read may hold text, even with the delimiter
awk 'NR == 1 { print $0 ",state,stamp"; next } { print $0 ",RUN,\"2024-05-01, 10:00\"" }' \
	"$W/plain.csv" >"$W/text.csv"
same_as text.csv && ok "text columns not read (a quoted cell holding ',')"
# but text in a column that is read is still an error, named
awk 'NR == 1 { print "t,x,f_c,state"; next } NR == 7 { print $0 ",RUN"; next } { print $0 ",1" }' \
	"$W/plain.csv" | sed '7s/^\([^,]*\),[^,]*,/\1,RUN,/' >"$W/textx.csv"
expect_rc 2 "$A" compare "$W/textx.csv" && grep -q "textx.csv:7: column 2 (x): not a finite number 'RUN'" "$W/err" &&
	ok "text in a column that is read: named" || fail "text in x: $(cat "$W/err")"
# a file without a newline at its end (RFC 4180 allows it) reads the same
head -c -1 "$W/plain.csv" >"$W/nonl.csv"
same_as nonl.csv && ok "foreign log without a final newline"
# a popc log always ends its rows with a newline: a last row without one was
# cut, even when every cell is there (its last number may be short); it is
# the end of an unfinished log, not a row: the rows before it are read, noted
grep -v '^# stop' "$W/popc.csv" | head -c -1 >"$W/popc-cut.csv"
cutline=$(grep -c '' "$W/popc-cut.csv")
expect_rc 0 "$A" compare "$W/popc-cut.csv" &&
	grep -q "popc-cut.csv: unfinished log: line $cutline, the last, is cut short (no newline) and not read; no '# stop = ...' line; its .* whole rows to line $((cutline - 1)) are read" "$W/err" &&
	ok "popc log cut after its last cell: its last line is not read, noted" || fail "popc cut: $(cat "$W/err")"
# line numbers stay right when comments and blank lines come between the
# first rows (the reader looks two rows ahead for the period)
printf 't,x,count\n0,0,1.5\n# note\n\n0.001,0,1\n' >"$W/lines.csv"
expect_rc 2 "$A" compare "$W/lines.csv" && grep -q "lines.csv:2: column 3 (count): 1.5 is not an integer count" "$W/err" &&
	ok "line number of a look-ahead row after comments" || fail "look-ahead line: $(cat "$W/err")"
# a count beyond 2^53 is an integer, but no longer exact: said so (issue
# 28: "1e+20 is not an integer count")
printf 't,x,count\n0,0,1e20\n0.001,0,1\n' >"$W/huge.csv"
expect_rc 2 "$A" compare "$W/huge.csv" &&
	grep -q "huge.csv:2: column 3 (count): 1e+20 is beyond 2^53 = 9007199254740992, where counts stop being exact" "$W/err" &&
	ok "a count beyond 2^53: named as such" || fail "count 1e20: $(cat "$W/err")"
printf 't,x,count\n0,0,-9007199254740994\n0.001,0,1\n' >"$W/huge2.csv"
expect_rc 2 "$A" compare "$W/huge2.csv" &&
	grep -q "huge2.csv:2: column 3 (count): -9007199254740994 is beyond 2^53" "$W/err" &&
	ok "a count just beyond -2^53: named as such" || fail "count -2^53-2: $(cat "$W/err")"

# --column: a misspelt popc name or a name mapped twice is refused, not ignored
awk -F, 'NR == 1 { print "t,x,force"; next } { print }' "$W/plain.csv" >"$W/force.csv"
same_as force.csv --column f_c=force && ok "--column f_c=force"
expect_rc 2 "$A" chatter --column F_c=force "$W/force.csv" &&
	grep -q -- "--column F_c=force: 'F_c' is not a popc column name (t x count" "$W/err" &&
	ok "misspelt --column name refused" || fail "misspelt --column: $(cat "$W/err")"
expect_rc 2 "$A" compare --column f_c=force --column f_c=x "$W/force.csv" &&
	grep -q -- "--column f_c=x: f_c is already mapped to 'force'" "$W/err" &&
	ok "--column name mapped twice refused" || fail "double --column: $(cat "$W/err")"

# --scale: other units and sign conventions. Exact factors give the same row
# bit for bit: x in half-metres (x2 is exact in binary), the force with the
# other sign (-1).
awk -F, 'NR == 1 { print "t,x_half,f_dev"; next } { printf "%s,%.17g,%.17g\n", $1, $2 / 2, -$3 }' \
	"$W/plain.csv" >"$W/units.csv"
same_as units.csv --column x=x_half --column f_c=f_dev --scale x=2 --scale f_c=-1 &&
	ok "--scale x=2 --scale f_c=-1: same row bit for bit"
# time in milliseconds: 1e-3 is inexact, so only the duration is checked
# (to the rounding of 1000 x 1e-3, well within 1e-12 s)
awk -F, 'NR == 1 { print "t_ms,x,f_c"; next } { printf "%.17g,%s,%s\n", $1 * 1000, $2, $3 }' \
	"$W/plain.csv" >"$W/ms.csv"
expect_rc 0 "$A" compare --format csv --column t=t_ms --scale t=1e-3 "$W/ms.csv" &&
	awk -F, 'NR == 2 { exit !($3 == 1001 && $4 > 1 - 1e-12 && $4 < 1 + 1e-12) }' "$W/out" &&
	ok "--scale t=1e-3: 1 s, 1001 ticks" || fail "ms log: $(cat "$W/out")"
expect_rc 0 "$A" compare --format csv --column t=t_ms "$W/ms.csv" &&
	awk -F, 'NR == 2 { exit !($4 == 1000) }' "$W/out" && ok "(unscaled it reads as 1000 s)" ||
	fail "ms log unscaled: $(cat "$W/out")"
for bad in "x=abc" "y=2" "t=-1" "x=0" "flags=2" "x"; do
	expect_rc 2 "$A" compare --scale "$bad" "$W/plain.csv" &&
		grep -q -- "--scale $bad: expected NAME=FACTOR" "$W/err" || fail "--scale $bad: $(cat "$W/err")"
done
ok "--scale with a bad name or factor refused"
# a factor that overflows a value is refused naming line and column (the
# energies came out NaN with exit 0)
awk -F, 'NR == 5 { print $1 "," $2 ",1e300"; next } { print }' "$W/plain.csv" >"$W/huge.csv"
for verb in energy compare; do
	expect_rc 2 "$A" $verb --scale f_c=1e10 "$W/huge.csv" &&
		grep -q "huge.csv:5: column 3 (f_c): 1e+300 x --scale 1e+10 overflows a double" "$W/err" &&
		ok "$verb: --scale overflowing a value refused, named" || fail "$verb overflow: $(cat "$W/err")"
done
expect_rc 2 "$A" compare --scale count=2 "$W/plain.csv" &&
	grep -q "plain.csv: --scale count=2: the log has no column 'count'" "$W/err" &&
	ok "--scale of a column the log lacks refused" || fail "--scale missing column: $(cat "$W/err")"

# A log's name is its file name, which may hold the CSV delimiter or a quote:
# the CSV cell is quoted (RFC 4180), the Markdown cell escapes '|'.
cp "$W/plain.csv" "$W/run 1, \"fast\".csv"
expect_rc 0 "$A" compare --format csv "$W/run 1, \"fast\".csv" &&
	[ "$(tail -n 1 "$W/out" | cut -c1-18)" = '"run 1, ""fast""",' ] &&
	[ "$(tail -n 1 "$W/out" | sed 's/^"run 1, ""fast""",//')" = "$(cat "$W/want")" ] &&
	ok "compare CSV: a name with ',' and '\"' quoted" || fail "CSV name quoting: $(cat "$W/out")"
# (thresholds 0: every window flagged, so there is a row to print)
expect_rc 1 "$A" chatter --format csv --threshold pc_rms_share=0 --threshold pc_flip_share=0 \
	--threshold vsign_share=0 --threshold contact=0 "$W/run 1, \"fast\".csv" &&
	grep -q '^"run 1, ""fast""",chatter,' "$W/out" && ok "chatter CSV: name quoted" ||
	fail "chatter CSV name: $(cat "$W/out")"
cp "$W/plain.csv" "$W/a|b.csv"
expect_rc 0 "$A" compare --format markdown "$W/a|b.csv" && grep -q '^| a\\|b | unknown | 1001 |' "$W/out" &&
	ok "compare Markdown: '|' in a name escaped" || fail "Markdown name: $(cat "$W/out")"

# Decimal commas (European rigs: ';' between cells, '1,5'): --decimal , reads
# them bit for bit as the same file written with points (compare's row and
# every energy -o row equal); a '.' in such a log, --decimal , with
# --delimiter , (either order) and an unknown mark are refused.
sed 's/,/;/g; s/\./,/g' "$W/plain.csv" >"$W/eu.csv"
grep -q '^0,001;' "$W/eu.csv" || fail "eu.csv has no decimal comma: $(sed -n 3p "$W/eu.csv")"
same_as eu.csv --decimal , && ok "--decimal ,: the same row as with points"
expect_rc 0 "$A" energy -o "$W/eu.energy" --decimal , "$W/eu.csv" &&
	expect_rc 0 "$A" energy -o "$W/plain.energy" "$W/plain.csv" &&
	grep -v '^#' "$W/eu.energy" >"$W/eu.rows" && grep -v '^#' "$W/plain.energy" >"$W/plain.rows" &&
	[ "$(wc -l <"$W/eu.rows")" -eq 1002 ] && cmp -s "$W/eu.rows" "$W/plain.rows" &&
	ok "--decimal ,: every energy -o row bitwise equal" || fail "decimal comma energy rows differ"
expect_rc 2 "$A" compare "$W/eu.csv" && grep -q "eu.csv:2: column 1 (t): not a finite number '0,0'" "$W/err" &&
	ok "a decimal-comma log without --decimal: refused, not misread" || fail "eu without --decimal: $(cat "$W/err")"
sed '9s/^\([^;]*\);\([^;]*\),/\1;\2./' "$W/eu.csv" >"$W/eu-mixed.csv"
expect_rc 2 "$A" compare --decimal , "$W/eu-mixed.csv" &&
	grep -q "eu-mixed.csv:9: column 2 (x): '.*\..*' has a '.', but the decimal mark is ','" "$W/err" &&
	ok "--decimal ,: a '.' in a number refused" || fail "eu mixed: $(cat "$W/err")"
expect_rc 2 "$A" compare --decimal , --delimiter , "$W/eu.csv" &&
	grep -q -- "--delimiter ',' with --decimal ','" "$W/err" &&
	expect_rc 2 "$A" compare --delimiter , --decimal , "$W/eu.csv" &&
	grep -q -- "--decimal ',' with --delimiter ','" "$W/err" && ok "--decimal , --delimiter , refused (both orders)" ||
	fail "decimal and delimiter ',': $(cat "$W/err")"
expect_rc 2 "$A" compare --decimal x "$W/eu.csv" && ok "--decimal x refused"
expect_rc 0 "$A" compare --help && grep -q -- "--decimal .|," "$W/out" && ok "--decimal in --help"

# Uneven time steps in a log without a rate (its period is its first step):
# refused by every verb, naming the first offending line. A dropped sample
# (line 501 of plain.csv, t = 0.499) makes the step from line 500 2 ms.
sed '501d' "$W/plain.csv" >"$W/dropped.csv"
for verb in energy chatter compare "replay --variant improved --prefix $W/drop-" "report --no-draw -o $W/rep-drop"; do
	# shellcheck disable=SC2086
	expect_rc 2 "$A" $verb "$W/dropped.csv" &&
		grep -q "dropped.csv:501: column 1 (t): uneven time steps: the step from line 500 (t = 0.498) is 0.002.* s, 100 % off the period 0.001 s (the first step, lines 2-3; the log gives no rate), more than 1 %" "$W/err" ||
		fail "uneven $verb: $(cat "$W/err")"
done
ok "a dropped sample: every verb refuses, naming line 501"
# the tolerance (ANA_PERIOD_REL_TOL, 1 %): time stamps written with 6 decimals
# pass; one step off by 0.5 % passes, by 2 % does not
awk -F, 'NR == 1 { print; next } { printf "%.6f,%s,%s\n", $1, $2, $3 }' "$W/plain.csv" >"$W/fixed6.csv"
same_as fixed6.csv && ok "t with 6 decimals: even"
awk -F, 'NR == 1 { print; next } NR == 300 { $1 = $1 + 5e-6 } { print $1 "," $2 "," $3 }' "$W/plain.csv" >"$W/jitter.csv"
expect_rc 0 "$A" compare "$W/jitter.csv" && ok "one step 0.5 % off: accepted" || fail "0.5 % jitter: $(cat "$W/err")"
awk -F, 'NR == 1 { print; next } NR == 300 { $1 = $1 + 2e-5 } { print $1 "," $2 "," $3 }' "$W/plain.csv" >"$W/jitter2.csv"
expect_rc 2 "$A" compare "$W/jitter2.csv" && grep -q "jitter2.csv:300: .* 2 % off the period" "$W/err" &&
	ok "one step 2 % off: refused" || fail "2 % jitter: $(cat "$W/err")"
# a rate given: the time column is not the period's source, nothing to check
expect_rc 0 "$A" compare --set run.rate=1000 "$W/dropped.csv" && ok "--set run.rate: not checked"
# energy --allow-uneven: the definitions that do not use T, bit for bit what
# they give with any rate (250 Hz here: T unused); 'filtered' left out, or refused when asked
expect_rc 0 "$A" energy --format csv --set run.rate=250 --observer eq3 --observer eq2 --observer ignore \
	"$W/dropped.csv" && cut -d, -f2- "$W/out" >"$W/rated"
if expect_rc 0 "$A" energy --format csv --allow-uneven "$W/dropped.csv"; then
	grep -q "note: .*dropped.csv: --allow-uneven: observer 'filtered' left out: it uses the period T" "$W/err" &&
		! grep -q ",filtered," "$W/out" && grep -v -e ",online=" -e ",ignore-undo," "$W/out" | cut -d, -f2- |
		cmp -s - "$W/rated" && ok "energy --allow-uneven: eq3, eq2, ignore as with a rate; filtered left out" ||
		fail "allow-uneven: $(cat "$W/out" "$W/err" "$W/rated")"
fi
expect_rc 2 "$A" energy --allow-uneven --observer filtered "$W/dropped.csv" &&
	grep -q "dropped.csv: --allow-uneven: the observer 'filtered' uses the period T" "$W/err" &&
	ok "--allow-uneven --observer filtered: refused" || fail "allow-uneven filtered: $(cat "$W/err")"
expect_rc 2 "$A" energy --allow-uneven --set environment.damping=0.5 "$W/dropped.csv" &&
	grep -q "E_ref uses the period here" "$W/err" && ok "--allow-uneven with a damping f_e derived: refused" ||
	fail "allow-uneven damping: $(cat "$W/err")"
expect_rc 2 "$A" compare --allow-uneven "$W/dropped.csv" && ok "--allow-uneven is energy's only"
finish
