# Bad input: a clear error naming the line and column, exit 2, no crash, for
# every verb that reads logs.
. "$2"
run_scene paper.ini "$W/good.csv" --set run.duration=0.2
hdr=$(grep -c '^#' "$W/good.csv")       # header comment lines
names=$((hdr + 1))                       # the column names line number

: >"$W/empty.csv"
head -n $((names + 20)) "$W/good.csv" >"$W/truncated.csv"
head -n $((names + 21)) "$W/good.csv" | tail -n 1 | cut -c1-12 | tr -d '\n' >>"$W/truncated.csv"
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 5))' { $6 = "abc" } { print }' "$W/good.csv" >"$W/text.csv"
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 7))' { $9 = "NaN" } { print }' "$W/good.csv" >"$W/nan.csv"
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 9))' { $1 = "0.001" } { print }' "$W/good.csv" >"$W/time.csv"
grep -v '^#' "$W/good.csv" | cut -d, -f1,5- >"$W/noposition.csv"
awk -F, '/^#/ || /^t,/ { print; next } NR == '$((names + 3))' { print $1 "," $2; next } { print }' \
	"$W/good.csv" >"$W/short.csv"

# case file expected-message-fragment
check() {
	for verb in energy chatter compare "replay --variant improved -o $W" "report --no-draw -o $W/rep"; do
		# shellcheck disable=SC2086
		if expect_rc 2 "$A" $verb "$W/$1"; then
			grep -q -- "$2" "$W/err" || fail "$verb $1: message lacks '$2': $(cat "$W/err")"
		else
			fail "$verb $1"
		fi
	done
	ok "$1: exit 2 for every verb, '$(head -1 "$W/err")'"
}
check empty.csv "empty file"
check truncated.csv "$W/truncated.csv:$((names + 21)): .*truncated last line"
check text.csv "$W/text.csv:$((names + 5)): column 6 (f_e)"
check nan.csv "$W/nan.csv:$((names + 7)): column 9 (W): NaN is not allowed"
check time.csv "$W/time.csv:$((names + 9)): column 1 (t): time .* does not increase"
check noposition.csv "missing column 'x'"
check short.csv "$W/short.csv:$((names + 3)): 2 cells, expected 11"
check does-not-exist.csv "cannot open"

# a mapping to a header the file lacks
expect_rc 2 "$A" energy --column x=position "$W/good.csv" && grep -q "no column 'position'" "$W/err" &&
	ok "--column to a missing header" || fail "--column missing header: $(cat "$W/err")"
expect_rc 2 "$A" energy --set encoder.resolution=-1 "$W/good.csv" && ok "bad --set value: exit 2"
expect_rc 2 "$A" energy --delimiter 12 "$W/good.csv" && ok "bad --delimiter: exit 2"
expect_rc 2 "$A" bogus-verb && ok "unknown verb: exit 2"
expect_rc 2 "$A" && ok "no verb: exit 2"
# chatter's exit status must not be 1 ("flagged") when the input is bad
expect_rc 2 "$A" chatter "$W/good.csv" "$W/empty.csv" && ok "chatter: trouble wins over flagged"
finish
