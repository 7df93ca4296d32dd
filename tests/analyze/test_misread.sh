# Inputs that were misread without an error (issue 28): an empty cell of a
# tab-separated row, a comment mark equal to the delimiter, a headerless file
# read without --no-header with every column mapped by position, a popc log
# whose header contradicts its rows. Each is refused (exit 2) for every verb,
# naming the file, the line and what is wrong; the same data written right
# still reads.
. "$2"
VERBS="energy chatter compare events"
# refused FILE FRAGMENT [OPTIONS...]: exit 2 for every verb, the message has FRAGMENT
refused() {
	file=$1 frag=$2; shift 2
	for verb in $VERBS "replay --variant improved -o $W/rep" "report --no-draw -o $W/report"; do
		# shellcheck disable=SC2086
		if expect_rc 2 "$A" $verb "$@" "$file"; then
			grep -q -- "$frag" "$W/err" || fail "$verb $file: message lacks '$frag': $(cat "$W/err")"
		else
			fail "$verb $* $file"
		fi
	done
	ok "$(basename "$file") $*: exit 2 for every verb, '$(grep -v 'note:' "$W/err" | head -1)'"
}
# read FILE [OPTIONS...]: exit 0 for compare and energy
read_ok() {
	file=$1; shift
	for verb in compare energy; do
		expect_rc 0 "$A" $verb "$@" "$file" || fail "$verb $* $file: $(cat "$W/err")"
	done
}

run_scene paper.ini "$W/good.csv" --set run.duration=1.5 --variant improved
names=$(grep -n '^t,' "$W/good.csv" | cut -d: -f1)   # the column names line

# --- 1. tab-separated: "\t\t" is an empty cell, not padding ---------------------
# t x f_e f_c: the third row has an empty cell and one cell too many; it was
# read as f_e = 0.1, f_c = 0.7 (exit 0)
grep -v '^#' "$W/good.csv" | cut -d, -f1,2,6,8 | tr , '\t' >"$W/good.tsv"
awk 'BEGIN { FS = OFS = "\t" } NR == 4 { $3 = "\t" $3 } { print }' "$W/good.tsv" >"$W/extra.tsv"
refused "$W/extra.tsv" "$W/extra.tsv:4: 5 cells, expected 4 (more cells than columns)"
refused "$W/extra.tsv" "$W/extra.tsv:4: 5 cells, expected 4" --delimiter tab
awk 'BEGIN { FS = OFS = "\t" } NR == 4 { $3 = "" } { print }' "$W/good.tsv" >"$W/empty.tsv"
refused "$W/empty.tsv" "$W/empty.tsv:4: column 3 (f_e): empty cell"
read_ok "$W/good.tsv" && ok "the same file without the empty cell reads"
# an empty cell in a column nobody reads (a note) keeps every other in place:
# the same results as the file without the note column
awk 'BEGIN { FS = OFS = "\t" } { n = NR == 1 ? "note" : NR % 2 ? "" : "n" NR; print n, $0 }' \
	"$W/good.tsv" >"$W/note.tsv"
expect_rc 0 "$A" compare --format csv "$W/good.tsv" && cut -d, -f2- "$W/out" >"$W/good.cmp" &&
	expect_rc 0 "$A" compare --format csv "$W/note.tsv" && cut -d, -f2- "$W/out" | cmp -s - "$W/good.cmp" &&
	ok "empty cells of a column nobody reads: the same compare row" || fail "note.tsv: $(cat "$W/err")"

# --- 2. a comment mark that is the delimiter -------------------------------------
# a first column nobody reads, empty on the last rows: they were dropped as
# comments, the log read shorter (exit 0)
awk -F, 'BEGIN { OFS = "," } /^#/ { next } /^t,/ { print "note," $0; next }
	{ print (NR > 1000 ? "" : "n") "," $0 }' "$W/good.csv" >"$W/note.csv"
refused "$W/note.csv" "$W/note.csv: the comment mark ',' is also the delimiter (detected from line 1)" --comment ,
tr , ';' <"$W/note.csv" >"$W/note-semi.csv"
for opts in "--delimiter ; --comment ;" "--comment ; --delimiter ;"; do
	# shellcheck disable=SC2086
	expect_rc 2 "$A" compare $opts "$W/note-semi.csv" &&
		grep -q -- "--comment ';' with --delimiter ';': one character cannot be both" "$W/err" &&
		ok "$opts: exit 2 naming both options" || fail "$opts: $(cat "$W/err")"
done
refused "$W/note-semi.csv" "the comment mark '#' (the default) is also the delimiter" --delimiter '#'
expect_rc 2 "$A" compare --comment space "$W/note.csv" && grep -q -- "--comment 'space': a comment mark is no blank" "$W/err" &&
	ok "--comment space: refused (a blank marks no line)" || fail "--comment space: $(cat "$W/err")"
expect_rc 0 "$A" compare --format csv --comment % "$W/note.csv" && grep -q "^note,unknown,1501," "$W/out" &&
	ok "--comment %: all 1501 rows" || fail "--comment %: $(cat "$W/out" "$W/err")"

# --- 3. a headerless file, every column by position, without --no-header ----------
grep -v '^#' "$W/good.csv" | tail -n +2 | cut -d, -f2,8 | tr , ' ' >"$W/ph.txt"
PH="--column x=#1 --column f_c=#2 --set run.rate=1000"
# shellcheck disable=SC2086
refused "$W/ph.txt" "$W/ph.txt:1: the first line that is no comment holds only numbers, and every --column maps a position: .*needs --no-header" $PH
# shellcheck disable=SC2086
expect_rc 0 "$A" compare --format csv --no-header $PH "$W/ph.txt" && grep -q "^ph.txt,unknown,1501," "$W/out" &&
	ok "--no-header: every row" || fail "--no-header: $(cat "$W/out" "$W/err")"

# --- 4. a popc log's header that contradicts its rows -----------------------------
rate_line=$(grep -n '^# rate = ' "$W/good.csv" | cut -d: -f1)
res_line=$(grep -n '^# resolution = ' "$W/good.csv" | cut -d: -f1)
var_line=$(grep -n '^# variant = ' "$W/good.csv" | head -1 | cut -d: -f1)
sed "${rate_line}s/.*/# rate = 500/" "$W/good.csv" >"$W/rate.csv"
refused "$W/rate.csv" "$W/rate.csv:$((names + 2)): column 1 (t): the time step from line $((names + 1)) (t = 0) is 0.001 s, 50 % off the period 0.002 s of run.rate = 500 (header, line $rate_line), more than 1 %: the header contradicts the rows"
refused "$W/good.csv" "run.rate = 2000 (--set)" --set run.rate=2000
sed "${res_line}s/.*/# resolution = 1e-06/" "$W/good.csv" >"$W/res.csv"
refused "$W/res.csv" "$W/res.csv:$((names + 1)): column 2 (x): x = -0.0065000000000000006 m, but count -650 x encoder.resolution = 1e-06 (header, line $res_line) is"
sed "${var_line}s/.*/# variant = none/" "$W/good.csv" >"$W/var.csv"
refused "$W/var.csv" "$W/var.csv:$var_line: header: variant = none, but controller.variant = improved (line"
# an admittance log's variant is admittance.variant's (docs/ADMITTANCE.md):
# read as it is, refused when the two disagree
run_scene admittance.ini "$W/adm.csv" --set run.duration=0.5
read_ok "$W/adm.csv" && ok "an admittance log's variant is admittance.variant's: it reads"
adm_line=$(grep -n '^# variant = ' "$W/adm.csv" | head -1 | cut -d: -f1)
sed "${adm_line}s/.*/# variant = parallel-hold/" "$W/adm.csv" >"$W/adm-var.csv"
refused "$W/adm-var.csv" "$W/adm-var.csv:$adm_line: header: variant = parallel-hold, but admittance.variant = parallel-pc (line"
sed "s/^# variant = improved$/# variant = none/" "$W/good.csv" >"$W/none.csv"
refused "$W/none.csv" "column 7 (f_pc): f_pc = .* N, but variant = none (header, line $var_line) logs no PC force"
# what popc writes reads: sim, every variant's header; a replay log of a
# recording whose stamps jitter (t copied, the mean step is the period)
read_ok "$W/good.csv" && ok "popc's own log reads"
run_scene paper.ini "$W/none-ok.csv" --set run.duration=0.2 --variant none
read_ok "$W/none-ok.csv" && ok "a variant none log reads"
awk -F, 'BEGIN { OFS = "\t"; print "time_us", "enc", "cmd_N" } /^#/ || /^t,/ { next }
	{ k = NR; printf "%d\t%s\t%s\n", $1 * 1e6 + (k * 7919) % 41, $3, $8 }' "$W/good.csv" >"$W/rig.tsv"
RIG="--column t=time_us --scale t=1e-6 --column count=enc --column f_c=cmd_N --set run.rate=1000 --jitter 0.05"
# shellcheck disable=SC2086
expect_rc 0 "$A" replay $RIG --variant improved -q --prefix "$W/rig-" "$W/rig.tsv" || fail "replay rig.tsv: $(cat "$W/err")"
read_ok "$W/rig-improved.csv" && ok "a replay log of jittered stamps reads"
rig_rate=$(grep -n '^# rate = ' "$W/rig-improved.csv" | cut -d: -f1)
sed "${rig_rate}s/.*/# rate = 500/" "$W/rig-improved.csv" >"$W/rig-500.csv"
last=$(grep -v '^#' "$W/rig-500.csv" | wc -l)
rig_names=$(grep -n '^t,' "$W/rig-500.csv" | cut -d: -f1)
refused "$W/rig-500.csv" "$W/rig-500.csv:$((rig_names + last - 1)): column 1 (t): the mean time step of lines $((rig_names + 1))-$((rig_names + last - 1)) is .* off the period 0.002 s of run.rate = 500 (header, line $rig_rate), more than 1 %: the header contradicts the rows (a replay log's t is its recording's stamps"
finish
