# popc-analyze replay: variants run open loop over a recorded position trace;
# the logs it writes are popc logs the other verbs read.
. "$2"
run_scene paper.ini "$W/ref-energy.csv"

# Replaying a log with its own variant reproduces its rows exactly (the
# controller is a function of the position trace).
mkdir "$W/r"
expect_rc 0 "$A" replay "$W/ref-energy.csv" --variant all -o "$W/r" &&
	[ "$(wc -l <"$W/out")" -eq 10 ] && ok "10 variants written" || fail "replay all: $(cat "$W/out")"
grep -v '^#' "$W/ref-energy.csv" >"$W/a"
grep -v '^#' "$W/r/ref-energy.ref-energy.csv" >"$W/b"
if [ "$(wc -l <"$W/a")" -eq 5002 ] && cmp -s "$W/a" "$W/b"; then
	ok "own variant replay reproduces the rows"
else
	fail "own variant replay differs"
fi
grep -q '^# source = replay$' "$W/r/ref-energy.improved.csv" && ok "source = replay" || fail "source header"
expect_rc 0 "$A" energy --check --observer online "$W"/r/*.csv && ok "replayed logs pass energy --check"
# improved on the same trace commands much less PC force than ref-energy
expect_rc 0 "$A" compare --format csv "$W/r/ref-energy.ref-energy.csv" "$W/r/ref-energy.improved.csv" &&
	awk -F, 'NR == 2 { a = $5 } NR == 3 { b = $5 } END { exit !(b < a / 2) }' "$W/out" &&
	ok "improved replay: PC RMS below half of ref-energy's" || fail "replay compare: $(cat "$W/out")"

# A device-like log: time and position only, tab separated, no header; the
# rate comes from the time column, the parameters from --set.
awk -F, '/^#/ { next } /^t,/ { print "time_s\tpos"; next } { print $1 "\t" $2 }' \
	"$W/ref-energy.csv" >"$W/device.tsv"
expect_rc 0 "$A" replay "$W/device.tsv" --column t=time_s --column x=pos \
	--set encoder.resolution=1e-5 --variant ref-energy --variant improved --prefix "$W/dev-" &&
	[ -s "$W/dev-ref-energy.csv" ] && [ -s "$W/dev-improved.csv" ] && ok "device log replay (--prefix)" ||
	fail "device replay"
grep -v '^#' "$W/dev-ref-energy.csv" >"$W/c"
grep -v '^#' "$W/ref-energy.csv" | cut -d, -f1-3,5-11 >"$W/d"
cmp -s "$W/c" "$W/d" && ok "device trace replay equals the original run (x_true and E_port aside)" ||
	fail "device trace replay differs: $(diff "$W/c" "$W/d" | head -3)"

expect_rc 2 "$A" replay "$W/ref-energy.csv" && ok "missing --variant: exit 2"
expect_rc 2 "$A" replay "$W/ref-energy.csv" --variant bogus && ok "unknown variant: exit 2"
expect_rc 0 "$A" replay --help && ok "--help"
finish
