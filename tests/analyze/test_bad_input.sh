# Bad input: a clear error naming the line and column, exit 2, no crash, for
# every verb that reads logs.
. "$2"
run_scene paper.ini "$W/good.csv" --set run.duration=0.2
hdr=$(grep -c '^#' "$W/good.csv")       # header comment lines
names=$((hdr + 1))                       # the column names line number

: >"$W/empty.csv"
head -n $((names + 150)) "$W/good.csv" >"$W/truncated.csv"
head -n $((names + 151)) "$W/good.csv" | tail -n 1 | cut -c1-12 | tr -d '\n' >>"$W/truncated.csv"
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 5))' { $6 = "abc" } { print }' "$W/good.csv" >"$W/text.csv"
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 7))' { $9 = "NaN" } { print }' "$W/good.csv" >"$W/nan.csv"
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 9))' { $1 = "0.001" } { print }' "$W/good.csv" >"$W/time.csv"
grep -v '^#' "$W/good.csv" | cut -d, -f1,5- >"$W/noposition.csv"
awk -F, '/^#/ || /^t,/ { print; next } NR == '$((names + 3))' { print $1 "," $2; next } { print }' \
	"$W/good.csv" >"$W/short.csv"
# a repeated column name (t,x,x): rejected, naming the line and both columns
cnames=$(grep -n '^t,' "$W/good.csv" | cut -d: -f1)   # ($names also counts the "# stop" line)
sed "${cnames}s/^t,x,/t,x,x,/; $((cnames + 1)),\$ s/^\([^,#]*\),\([^,]*\),/\1,\2,\2,/" \
	"$W/good.csv" >"$W/dupname.csv"

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
# a popc log cut mid-row (a full disk, a killed run) is an unfinished log, not
# bad input: every verb reads its 151 whole rows (chatter needs 100; $names
# counts the stop line too) and says where they end; nothing else on stderr
# but notes
for verb in energy chatter compare "replay --variant improved -q -o $W" "report --no-draw -o $W/rep"; do
	# shellcheck disable=SC2086
	expect_rc 0 "$A" $verb "$W/truncated.csv" &&
		grep -q "note: $W/truncated.csv: unfinished log: line $((names + 151)), the last, is cut short (no newline) and not read; no '# stop = ...' line; its 151 whole rows to line $((names + 150)) are read" "$W/err" &&
		! grep -qv "note:" "$W/err" || fail "$verb truncated.csv: $(cat "$W/err")"
done
ok "truncated.csv: every verb reads the 151 whole rows, with a note"
check text.csv "$W/text.csv:$((names + 5)): column 6 (f_e)"
check nan.csv "$W/nan.csv:$((names + 7)): column 9 (W): NaN is not allowed"
check time.csv "$W/time.csv:$((names + 9)): column 1 (t): time .* does not increase"
check noposition.csv "missing column 'x'"
check short.csv "$W/short.csv:$((names + 3)): 2 cells, expected 12"
check dupname.csv "$W/dupname.csv:$cnames: column 3 (x) repeats the name of column 2"
# flags is a bit set: a value that is no integer in [0, 2^32 - 1] is refused,
# not truncated (3.5 read as 3, 1e30 and -1 as 0)
# (the cell as written, then as the message shows the value read)
for bad in 3.5:3.5 1e30:1e+30 -1:-1 4294967296:4294967296 0.5:0.5; do
	awk -F, -v bad="${bad%%:*}" 'BEGIN { OFS = "," } NR == '$((names + 4))' { $11 = bad "" } { print }' \
		"$W/good.csv" >"$W/flags.csv"
	check flags.csv "$W/flags.csv:$((names + 4)): column 11 (flags): ${bad#*:} is not a flag word (an integer in \[0, 4294967295\])"
done
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 4))' { $11 = "4294967295" } { print }' "$W/good.csv" >"$W/flags.csv"
expect_rc 0 "$A" compare "$W/flags.csv" && ok "flags 4294967295 (all 32 bits) accepted" || fail "flags max"
check does-not-exist.csv "cannot open"
# a directory opens for reading on Linux; it is no (empty) log
mkdir "$W/adir"
check adir "$W/adir: is a directory, not a log file"
# a failed read is an error, not the end of the log (reading /proc/self/mem
# at offset 0 fails with EIO)
if [ -r /proc/self/mem ]; then
	expect_rc 2 "$A" compare /proc/self/mem && grep -q "/proc/self/mem:1: read error: Input/output error" "$W/err" &&
		ok "read error: named, exit 2" || fail "read error: $(cat "$W/err")"
fi

# a mapping to a header the file lacks
expect_rc 2 "$A" energy --column x=position "$W/good.csv" && grep -q "no column 'position'" "$W/err" &&
	ok "--column to a missing header" || fail "--column missing header: $(cat "$W/err")"
expect_rc 2 "$A" energy --set encoder.resolution=-1 "$W/good.csv" && ok "bad --set value: exit 2"
expect_rc 2 "$A" energy --delimiter 12 "$W/good.csv" && ok "bad --delimiter: exit 2"
expect_rc 2 "$A" bogus-verb && ok "unknown verb: exit 2"
expect_rc 2 "$A" && ok "no verb: exit 2"

# A UTF-8 byte order mark (CSV saved by Excel) before the first line is skipped:
# before a popc header (the scene still read back, so --check holds) and
# before the column names of a foreign log.
printf '\357\273\277' | cat - "$W/good.csv" >"$W/bom.csv"
expect_rc 0 "$A" energy --check "$W/bom.csv" && ok "BOM before a popc header: energy --check passes"
grep -v '^#' "$W/good.csv" | cut -d, -f1,2,8 >"$W/foreign.csv"
printf '\357\273\277' | cat - "$W/foreign.csv" >"$W/bom-foreign.csv"
expect_rc 0 "$A" compare --format csv "$W/foreign.csv" && cp "$W/out" "$W/foreign.out"
expect_rc 0 "$A" compare --format csv "$W/bom-foreign.csv" &&
	[ "$(tail -n 1 "$W/out" | cut -d, -f2-)" = "$(tail -n 1 "$W/foreign.out" | cut -d, -f2-)" ] &&
	ok "BOM before the column names: same row as without" || fail "BOM foreign: $(cat "$W/out" "$W/err")"

# No PC-force source (neither f_pc nor f_c): chatter cannot say "no chatter".
printf 't,x\n0,0\n0.001,1e-6\n' >"$W/nofc.csv"
# (2 ticks: the limit cycle is not checked either, nothing is)
if expect_rc 2 "$A" chatter "$W/nofc.csv"; then
	grep -q "$W/nofc.csv: no PC force: the file has no column 'f_pc' or 'f_c' (map one with --column f_pc=HEADER.*; chatter not checked$" "$W/err" &&
		grep -q "$W/nofc.csv: limit cycle not checked: the log has 2 ticks" "$W/err" &&
		grep -q "^nofc: chatter not checked (no PC force); limit cycle not checked (2 ticks" "$W/out" &&
		! grep -q "no chatter\|no limit cycle" "$W/out" &&
		ok "chatter without a PC force, 2 ticks: exit 2, nothing checked" ||
		fail "chatter nofc: $(cat "$W/out" "$W/err")"
fi
# 1.5 s of positions without a PC force: the limit cycle is still reported
awk 'BEGIN { print "t,x"; for (k = 0; k < 1500; k++) printf "%.3f,1e-3\n", k / 1000 }' >"$W/nofc-long.csv"
if expect_rc 2 "$A" chatter "$W/nofc-long.csv"; then
	grep -q "no PC force: .*; chatter not checked, only the limit cycle$" "$W/err" &&
		grep -q "^nofc-long: chatter not checked (no PC force); no limit cycle" "$W/out" &&
		! grep -q "limit cycle not checked" "$W/err" &&
		ok "chatter without a PC force, 1.5 s: exit 2, limit cycle still reported" ||
		fail "chatter nofc-long: $(cat "$W/out" "$W/err")"
fi
expect_rc 2 "$A" chatter --format csv "$W/nofc.csv" && grep -qx "nofc,chatter_not_checked,,," "$W/out" &&
	ok "chatter csv: chatter_not_checked row" || fail "chatter csv nofc: $(cat "$W/out")"
expect_rc 2 "$A" chatter -q "$W/nofc.csv" && grep -q "no PC force" "$W/err" && ok "chatter -q: still an error" ||
	fail "chatter -q nofc: $(cat "$W/err")"
expect_rc 2 "$A" energy "$W/nofc.csv" && grep -q "no PC force" "$W/err" && ok "energy without a PC force: exit 2" ||
	fail "energy nofc: $(cat "$W/err")"
# compare: PC, chatter and W - E_ref cells empty (CSV) or n/a, never 0; the
# limit cycle too at 2 ticks, not at 1.5 s (nofc-long); a note on stderr
if expect_rc 0 "$A" compare --format csv "$W/nofc.csv" "$W/nofc-long.csv"; then
	awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
		$1 == "nofc-long" { if ($c["chatter_s"] != "" || $c["limit_cycle"] != "0" || $c["lc_amplitude"] == "") exit 1; next }
		{ if ($c["pc_rms"] != "" || $c["pc_max"] != "" || $c["pc_active"] != "" ||
		      $c["chatter_s"] != "" || $c["chatter_intervals"] != "" ||
		      $c["w_minus_eref_end"] != "" || $c["limit_cycle"] != "" || $c["ticks"] != "2") exit 1 }' \
		"$W/out" && grep -q "compare: note: .*no PC force.* are n/a" "$W/err" &&
		ok "compare without a PC force: empty PC cells, note" ||
		fail "compare nofc: $(cat "$W/out" "$W/err")"
fi
expect_rc 0 "$A" compare "$W/nofc.csv" && grep -q "^nofc .* n/a " "$W/out" && ok "compare text: n/a" ||
	fail "compare text nofc: $(cat "$W/out")"
expect_rc 0 "$A" report --no-draw -o "$W/rep-nofc" "$W/nofc.csv" && ! grep -q "using 1:6" "$W/rep-nofc/nofc.gp" &&
	ok "report without a PC force: no PC force panel" || fail "report nofc"
# with f_c mapped, chatter has data again (150 ticks: more than one 100 ms window)
awk 'BEGIN { print "t,x,force"; for (k = 0; k < 150; k++) printf "%.3f,1e-6,0\n", k / 1000 }' >"$W/mapped.csv"
expect_rc 0 "$A" chatter --column f_c=force "$W/mapped.csv" && grep -q "^mapped: no chatter" "$W/out" &&
	ok "--column f_c=force: chatter checked" || fail "mapped: $(cat "$W/out" "$W/err")"

# Parameters a foreign log lacks: one note per log naming each default taken
expect_rc 0 "$A" compare "$W/foreign.csv" "$W/foreign.csv" &&
	[ "$(grep -c "note: .*foreign.csv: the log does not give these parameters; assumed the paper scene's defaults: encoder.resolution = 1e-05, .*environment.stiffness = 1000" "$W/err")" -eq 2 ] &&
	ok "defaults note: once per log" || fail "defaults note: $(cat "$W/err")"
expect_rc 0 "$A" compare --set encoder.resolution=1e-6 "$W/foreign.csv" &&
	grep -q "environment.stiffness = 1000" "$W/err" && ! grep -q "encoder.resolution" "$W/err" &&
	ok "defaults note: a --set parameter is not named" || fail "defaults note with --set: $(cat "$W/err")"
# (a 0.2 s log: a 0.2 s limit-cycle window, so that it is checked and no
# "limit cycle not checked" note, kept under -q, is printed either)
expect_rc 0 "$A" chatter -q --threshold lc_window=0.2 "$W/foreign.csv" && [ ! -s "$W/err" ] &&
	ok "defaults note: -q suppresses it" ||
	fail "chatter -q printed: $(cat "$W/err")"
expect_rc 0 "$A" compare --threshold lc_window=0.2 "$W/good.csv" && [ ! -s "$W/err" ] && ok "a popc log: no defaults note" ||
	fail "popc log note: $(cat "$W/err")"
# One number grammar (popc/util/parse.h): a hex float as a threshold, a --scale
# factor or --late-from was taken by strtod; refused with exit 2 naming the option
expect_rc 2 "$A" chatter --threshold window=0x1p1 "$W/good.csv" && grep -q -- "--threshold: threshold window = '0x1p1'" "$W/err" &&
	ok "--threshold window=0x1p1 refused" || fail "--threshold hex float: $(cat "$W/err")"
expect_rc 2 "$A" compare --threshold pc_rms_share=inf "$W/good.csv" && grep -q -- "--threshold" "$W/err" &&
	ok "--threshold pc_rms_share=inf refused" || fail "--threshold inf: $(cat "$W/err")"
expect_rc 2 "$A" energy --scale t=0x1p0 "$W/good.csv" && grep -q -- "--scale t=0x1p0" "$W/err" &&
	ok "--scale t=0x1p0 refused" || fail "--scale hex float: $(cat "$W/err")"
expect_rc 2 "$A" compare --late-from 0x1p-1 "$W/good.csv" && grep -q -- "--late-from '0x1p-1'" "$W/err" &&
	ok "--late-from 0x1p-1 refused" || fail "--late-from hex float: $(cat "$W/err")"
expect_rc 2 "$A" report --points 0x100 --no-draw -o "$W/rep-hex" "$W/good.csv" && grep -q -- "--points '0x100'" "$W/err" &&
	ok "--points 0x100 refused" || fail "--points hex: $(cat "$W/err")"
expect_rc 0 "$A" chatter --threshold window=2e-1 "$W/good.csv" && ok "--threshold window=2e-1: a decimal exponent is fine" ||
	fail "--threshold 2e-1: $(cat "$W/err")"
# a cell that would read as 0 (below the smallest double) is refused like any bad number
awk -F, 'BEGIN { OFS = "," } NR == '$((names + 5))' { $6 = "1e-400" } { print }' "$W/good.csv" >"$W/underflow.csv"
expect_rc 2 "$A" compare "$W/underflow.csv" && grep -q "below the smallest double" "$W/err" &&
	ok "a cell of 1e-400 refused, naming why" || fail "underflow cell: $(cat "$W/err")"
# chatter's exit status must not be 1 ("flagged") when the input is bad
expect_rc 2 "$A" chatter "$W/good.csv" "$W/empty.csv" && ok "chatter: trouble wins over flagged"
finish
