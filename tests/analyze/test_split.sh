# Recorded logs in other shapes (docs/READING.md): signals split across files
# (--join, one file per quantity, no time column) and rotary logs in rad and
# N m (--lever). Each reads to compare's row of the popc data it came from bit
# for bit (the log name aside), or is refused naming the file and line, exit 2.
. "$2"
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

# one file per quantity, no names, no time: position, force
grep -v '^t' "$W/plain.csv" | cut -d, -f2 >"$W/pos.txt"
grep -v '^t' "$W/plain.csv" | cut -d, -f3 >"$W/force.txt"
same_as pos.txt --join "$W/force.txt" --no-header --column x=#1 --column f_c=#2 --set run.rate=1000 &&
	ok "--join: headerless position and force files, numbered across the files"
# with names, time in its own file
cut -d, -f1 "$W/plain.csv" >"$W/t.csv"
cut -d, -f2 "$W/plain.csv" >"$W/x.csv"
cut -d, -f3 "$W/plain.csv" >"$W/f.csv"
same_as t.csv --join "$W/x.csv" --join "$W/f.csv" && ok "--join: three named files, time in one"
# ragged: the force file one row short
head -n -1 "$W/force.txt" >"$W/force-short.txt"
expect_rc 2 "$A" compare --join "$W/force-short.txt" --no-header --column x=#1 --column f_c=#2 \
	--set run.rate=1000 "$W/pos.txt" &&
	grep -q "pos.txt: --join: ragged files: .*force-short.txt ends after 1000 rows (line 1000), .*pos.txt has row 1001 (line 1001)" "$W/err" &&
	ok "ragged split files refused, naming both" || fail "ragged: $(cat "$W/err")"
expect_rc 2 "$A" compare --join "$W/pos.txt" --no-header --column x=#1 --column f_c=#2 \
	--set run.rate=1000 "$W/force-short.txt" &&
	grep -q "force-short.txt: --join: ragged files: .*force-short.txt ends after 1000 rows" "$W/err" &&
	ok "ragged the other way round" || fail "ragged 2: $(cat "$W/err")"
# a bad cell in a joined file: named with its own file and line
sed '7s/.*/n\/a/' "$W/force.txt" >"$W/force-bad.txt"
expect_rc 2 "$A" compare --join "$W/force-bad.txt" --no-header --column x=#1 --column f_c=#2 \
	--set run.rate=1000 "$W/pos.txt" &&
	grep -q "force-bad.txt:7: column 1 (#1): not a finite number 'n/a'" "$W/err" &&
	ok "a bad cell in a joined file names that file and line" || fail "bad cell: $(cat "$W/err")"
expect_rc 2 "$A" compare --join "$W/missing.txt" "$W/pos.txt" && grep -q "missing.txt: cannot open" "$W/err" &&
	ok "a missing joined file named" || fail "missing join: $(cat "$W/err")"

# a log read from a pipe loses no byte to the look for a MAT file's header
expect_rc 0 "$A" compare --format csv /dev/stdin <"$W/plain.csv" &&
	tail -n 1 "$W/out" | cut -d, -f2- | cmp -s - "$W/want" && ok "a log from a pipe reads as before" ||
	fail "pipe: $(cat "$W/err")"
mkfifo "$W/fifo" && { cat "$W/plain.csv" >"$W/fifo" & } &&
	expect_rc 0 "$A" compare --format csv "$W/fifo" &&
	tail -n 1 "$W/out" | cut -d, -f2- | cmp -s - "$W/want" && ok "a log from a FIFO reads as before" ||
	fail "fifo: $(cat "$W/err")"
wait

# rotary: theta = x / r rad, tau = f r N m at a lever r = 0.25 m (exact in
# binary, so the row is bit for bit; other levers round once per cell)
awk -F, 'NR == 1 { print "t,theta,tau"; next } { printf "%s,%.17g,%.17g\n", $1, $2 / 0.25, $3 * 0.25 }' \
	"$W/plain.csv" >"$W/rotary.csv"
same_as rotary.csv --column x=theta --column f_c=tau --lever 0.25 --set encoder.resolution=1e-5 &&
	ok "--lever 0.25: rad and N m to m and N, bit for bit"
# energy -o states the lever in its provenance
expect_rc 0 "$A" energy -o "$W/energy.csv" --column x=theta --column f_c=tau --lever 0.25 "$W/rotary.csv" &&
	grep -q "^# lever = 0.25 m" "$W/energy.csv" && ok "energy -o: '# lever = 0.25 m' in the provenance" ||
	fail "lever provenance: $(head -5 "$W/energy.csv" 2>&1)"
before=$FAILS
for bad in 0 -1 nan inf 1e7 x; do
	expect_rc 2 "$A" compare --lever "$bad" "$W/rotary.csv" &&
		grep -q -- "--lever '$bad': expected the lever arm in m, a number in (0, 1e6]" "$W/err" ||
		fail "--lever $bad: $(cat "$W/err")"
done
[ "$FAILS" -eq "$before" ] && ok "--lever refuses 0, -1, nan, inf, 1e7, x"
finish
