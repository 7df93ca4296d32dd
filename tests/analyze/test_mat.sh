# MAT files (docs/READING.md "MAT files"): made from a popc log with libmatio
# itself (make_mat.c), each kind reads to compare's row of the CSV it came from
# bit for bit (the log name aside: the doubles in a MAT file are exact), or is
# refused naming the file and the variable, exit 2. $3 is make_mat, or "none"
# in a build without libmatio: then a MAT file is refused, and the test skips.
. "$2"
MAKE_MAT=$3
if [ "$MAKE_MAT" = none ]; then
	# the text header a MAT v5 file begins with is enough to be taken for one
	printf 'MATLAB 5.0 MAT-file, Platform: GLNXA64, Created on: Sat Dec  5 12:00:00 2026   ' >"$W/any.mat"
	expect_rc 2 "$A" compare "$W/any.mat" &&
		grep -q "any.mat: a MAT file, and this popc-analyze was built without libmatio" "$W/err" &&
		ok "without libmatio a MAT file is refused, exit 2" || fail "no matio: $(cat "$W/err")"
	[ "$FAILS" -eq 0 ] || finish
	exit 77
fi
run_scene paper.ini "$W/popc.csv" --set run.duration=1
grep -v '^#' "$W/popc.csv" | cut -d, -f1,2,8 >"$W/plain.csv"     # t,x,f_c
expect_rc 0 "$A" compare --format csv "$W/plain.csv" || finish
tail -n 1 "$W/out" | cut -d, -f2- >"$W/want"
same_as() {
	f=$1; shift
	if expect_rc 0 "$A" compare --format csv "$@" "$W/$f"; then
		tail -n 1 "$W/out" | cut -d, -f2- | cmp -s - "$W/want" && return 0
		fail "$f: row differs: $(tail -n 1 "$W/out")"
	fi
	return 1
}
# make VERSION KIND NAME: 0 made, 77 this libmatio writes no v7.3
make() { "$MAKE_MAT" "$1" "$2" "$W/plain.csv" "$W/$3" 2>"$W/make.err"; }

# 5z: v5 with compressed variables, as MATLAB's save writes them
for ver in 5 5z 73; do
	make "$ver" matrix m$ver.mat
	rc=$?
	if [ "$ver" = 73 ] && [ "$rc" = 77 ]; then
		ok "MAT v7.3 not checked: this libmatio has no HDF5"
		continue
	fi
	[ "$rc" = 0 ] || { fail "make_mat $ver matrix: $(cat "$W/make.err")"; continue; }
	same_as m$ver.mat --variable log --names names &&
		ok "MAT v$ver matrix, columns named by a cell array (--names)"
	same_as m$ver.mat --variable log --column t=#1 --column x=#2 --column f_c=#3 &&
		ok "MAT v$ver matrix, columns by position (#N)"
	make "$ver" swt s$ver.mat || { fail "make_mat $ver swt: $(cat "$W/make.err")"; continue; }
	same_as s$ver.mat --column t=time && ok "MAT v$ver StructureWithTime (labels t... x, f_c)"
done

# bad input: named, exit 2
expect_rc 2 "$A" compare "$W/m5.mat" &&
	grep -q "m5.mat: several variables: choose one with --variable NAME (the file holds: log names)" "$W/err" &&
	ok "several variables, none chosen: listed" || fail "several: $(cat "$W/err")"
expect_rc 2 "$A" compare --variable nope "$W/m5.mat" &&
	grep -q "m5.mat: --variable nope: no such variable" "$W/err" &&
	ok "missing variable named" || fail "missing variable: $(cat "$W/err")"
expect_rc 2 "$A" compare --variable log --names nope "$W/m5.mat" &&
	grep -q "m5.mat: --names nope: no such variable" "$W/err" &&
	ok "missing names variable named" || fail "missing names: $(cat "$W/err")"
expect_rc 2 "$A" compare --variable log --names log "$W/m5.mat" &&
	grep -q "m5.mat: --names log: not a cell array, expected a cell array of 3 strings" "$W/err" &&
	ok "names variable not a cell array" || fail "names not cell: $(cat "$W/err")"
make 5 int32 int.mat && expect_rc 2 "$A" compare --column t=#1 --column x=#2 "$W/int.mat" &&
	grep -q "int.mat: variable log: not of class double, expected real doubles" "$W/err" &&
	ok "non-double class refused" || fail "int32: $(cat "$W/err")"
make 5 nan nan.mat && expect_rc 2 "$A" compare --column t=#1 --column x=#2 "$W/nan.mat" &&
	grep -q "nan.mat: variable log: row 5, column 2: NaN, not a finite number" "$W/err" &&
	ok "NaN cell refused, its row and column named" || fail "nan: $(cat "$W/err")"
make 5 cube cube.mat && expect_rc 2 "$A" compare "$W/cube.mat" &&
	grep -q "cube.mat: variable log: 3 dimensions, expected a matrix (N x M)" "$W/err" &&
	ok "wrong dimensions refused" || fail "cube: $(cat "$W/err")"
make 5 swt_rows short.mat && expect_rc 2 "$A" compare --column t=time "$W/short.mat" &&
	grep -q "short.mat: variable log.signals(2).values: 1000 rows, and log.time has 1001" "$W/err" &&
	ok "a signal of another length than time refused" || fail "swt rows: $(cat "$W/err")"
# an error about the CSV text a MAT file becomes names the MAT file, not the
# temporary file (libFuzzer found it naming /tmp/popc-analyze-XXXXXX:1)
expect_rc 2 "$A" compare --variable log --column t=#1 --column x=nope "$W/m5.mat" &&
	grep -q "popc-analyze compare: $W/m5.mat: --column x=nope: the file has no column 'nope'" "$W/err" &&
	ok "a missing column named with the MAT file" || fail "column: $(cat "$W/err")"
# a nested header damaged to 1 x 2147483647 struct elements: refused before
# libmatio allocates them (it crashed on this file: read_mat_check.c)
make 5 swt_huge huge.mat && expect_rc 2 "$A" compare --column t=time "$W/huge.mat" &&
	grep -q "huge.mat: variable log: a nested cell or struct declares 6442450941 elements in [0-9]* bytes: a damaged file" "$W/err" &&
	ok "a damaged nested header refused before it is read" || fail "huge: $(cat "$W/err")"
# a string's data damaged to 2147483640 bytes: refused at once (libmatio
# allocated and cleared them for about 30 s, then called the cell no text)
make 5 data_huge dh.mat && expect_rc 2 "$A" compare --variable log --names names "$W/dh.mat" &&
	grep -q "dh.mat: variable names: an element larger than the array that holds it: a damaged file" "$W/err" &&
	ok "a damaged data element refused before it is read" || fail "data_huge: $(cat "$W/err")"
# a file that only says it is one
printf 'MATLAB 5.0 MAT-file, but cut\n' >"$W/cut.mat"
expect_rc 2 "$A" compare "$W/cut.mat" && grep -q "cut.mat: cannot read as a MAT file" "$W/err" &&
	ok "a damaged MAT file refused" || fail "cut: $(cat "$W/err")"
# --lever on a MAT file: the same option table as a CSV's
expect_rc 2 "$A" compare --lever 0 "$W/s5.mat" && grep -q -- "--lever '0': expected the lever arm in m" "$W/err" &&
	ok "--lever 0 refused" || fail "lever 0: $(cat "$W/err")"
finish
