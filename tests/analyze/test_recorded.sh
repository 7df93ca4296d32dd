# Recorded device logs (docs/ANALYSIS.md, "Recorded device logs"): files
# shaped like recordings from real setups (make_recordings.sh makes them from
# two popc runs: a PHANToM-style file without column names or time, a 1 kHz
# log with time stamps in us that jitter by up to 4 % of a step, a two-axis
# file) give the same analysis as the same data written by popc (the run's
# t, x or count, f_c as CSV) with energy, compare, chatter and replay: bit for
# bit where the data are the same bits; where the stamps jitter, within the
# bounds stated at each check. Bad recordings are refused naming file, line
# and column, exit 2.
. "$2"
run_scene paper.ini "$W/a.csv"                                     # ref-energy: chatter from 3.83 s
run_scene paper.ini "$W/b.csv" --set controller.variant=none       # a limit cycle
sh "$POPC_SOURCE_ROOT/tests/analyze/make_recordings.sh" "$W/a.csv" "$W/b.csv" "$W/rec" ||
	{ fail "make_recordings.sh"; finish; }
R=$W/rec
# plain LOG OUT NAME...: LOG's columns NAME... as popc wrote them (CSV)
plain() {
	log=$1; out=$2; shift 2
	grep -v '^#' "$log" | awk -F, -v want="$*" '
		NR == 1 { n = split(want, w, " "); for (i = 1; i <= NF; i++) ix[$i] = i }
		{ line = ""; for (i = 1; i <= n; i++) line = line (i > 1 ? "," : "") $(ix[w[i]]); print line }' >"$out"
}
plain "$W/a.csv" "$W/a-x.csv" t x f_c
plain "$W/a.csv" "$W/a-count.csv" t count f_c
plain "$W/b.csv" "$W/b-x.csv" t x f_c
SETS="--set run.rate=1000 --set controller.variant=ref-energy"

# run_both NAME VERB REF REC [REC's options]: VERB on the reference and on
# the recording, outputs $W/NAME.ref and $W/NAME.rec without the log column
# (the file name), exit codes equal
run_both() {
	name=$1; verb=$2; ref=$3; rec=$4; shift 4
	# shellcheck disable=SC2086
	"$A" $verb --format csv $SETS "$ref" >"$W/o" 2>"$W/e"; rc_ref=$?
	cut -d, -f2- "$W/o" >"$W/$name.ref"
	# shellcheck disable=SC2086
	"$A" $verb --format csv $SETS "$@" "$rec" >"$W/o" 2>"$W/e"; rc_rec=$?
	cut -d, -f2- "$W/o" >"$W/$name.rec"
	if [ "$rc_ref" -ne "$rc_rec" ] || [ "$rc_ref" -ge 2 ]; then
		fail "$name $verb: exit $rc_ref (reference) and $rc_rec (recording): $(cat "$W/e")"
		return 1
	fi
	return 0
}
# same NAME VERB REF REC [options]: the two outputs equal bit for bit
same() {
	name=$1
	run_both "$@" || return 1
	[ "$(wc -l <"$W/$name.ref")" -ge 2 ] || { fail "$name: no rows: $(cat "$W/$name.ref")"; return 1; }
	cmp -s "$W/$name.ref" "$W/$name.rec" ||
		{ fail "$name: differs: $(diff "$W/$name.ref" "$W/$name.rec" | head -4)"; return 1; }
}
# same_replay NAME REF REC [options]: replay's logs of both are equal but for
# the replay_of line (and the t column when JITTER is set: within 40 us)
same_replay() {
	name=$1; ref=$2; rec=$3; shift 3
	# shellcheck disable=SC2086
	expect_rc 0 "$A" replay -q $SETS --variant improved --prefix "$W/$name-ref-" "$ref" &&
		expect_rc 0 "$A" replay -q $SETS --variant improved --prefix "$W/$name-rec-" "$@" "$rec" ||
		return 1
	grep -v '^# replay_of' "$W/$name-ref-improved.csv" >"$W/o1"
	grep -v '^# replay_of' "$W/$name-rec-improved.csv" >"$W/o2"
	if [ -n "${JITTER:-}" ]; then
		grep -v '^#' "$W/o1" | cut -d, -f1 >"$W/t1"
		grep -v '^#' "$W/o2" | cut -d, -f1 >"$W/t2"
		paste -d, "$W/t1" "$W/t2" | awk -F, 'NR > 1 { d = $2 - $1; if (d < -1e-12 || d > 40e-6 + 1e-12) bad++ }
			END { exit bad > 0 }' || { fail "$name replay: t off by more than the 40 us delay"; return 1; }
		for f in o1 o2; do grep -v '^#' "$W/$f" | cut -d, -f2- >"$W/$f.c"; grep '^#' "$W/$f" >>"$W/$f.c"; done
		cmp -s "$W/o1.c" "$W/o2.c" || { fail "$name replay: rows differ (t aside)"; return 1; }
		return 0
	fi
	[ "$(grep -vc '^#' "$W/o1")" -eq 5002 ] && cmp -s "$W/o1" "$W/o2" ||
		{ fail "$name replay: differs: $(diff "$W/o1" "$W/o2" | head -4)"; return 1; }
}

# 1. PHANToM-style: no column names, no time (the rate gives t = k T, as popc
# writes it), blanks between right-aligned columns, the axis's position and
# force picked by position among six columns.
PH="--no-header --column x=#1 --column f_c=#4"
same ph-energy energy "$W/a-x.csv" "$R/phantom.txt" $PH &&
	same ph-compare compare "$W/a-x.csv" "$R/phantom.txt" $PH &&
	same ph-chatter chatter "$W/a-x.csv" "$R/phantom.txt" $PH &&
	grep -q '^chatter,3.83,5,' "$W/ph-chatter.rec" && same_replay ph "$W/a-x.csv" "$R/phantom.txt" $PH &&
	ok "PHANToM-style file (no header, no time, blanks, x=#1 f_c=#4): energy, compare, chatter, replay bit for bit"

# 2. Two axes in one file, '%' comments, time in integer ms (k x 1e-3 is the
# double popc writes as k T): each axis picked by the column mapping, by name
# or by position, analyses as its own run.
TA="--comment % --column t=t_ms --scale t=1e-3"
same ax1-compare compare "$W/a-x.csv" "$R/twoaxis.txt" $TA --column x=x1 --column f_c=fc1 &&
	same ax1-energy energy "$W/a-x.csv" "$R/twoaxis.txt" $TA --column x=x1 --column f_c=fc1 &&
	ok "two-axis file, axis 1 by name: compare, energy bit for bit"
same ax2-compare compare "$W/b-x.csv" "$R/twoaxis.txt" $TA --column x=x2 --column f_c=fc2 &&
	same ax2-compare-pos compare "$W/b-x.csv" "$R/twoaxis.txt" $TA --column x=#4 --column f_c=#5 &&
	same ax2-chatter chatter "$W/b-x.csv" "$R/twoaxis.txt" $TA --column x=#4 --column f_c=#5 &&
	grep -q '^limit_cycle,' "$W/ax2-chatter.rec" &&
	same_replay ax2 "$W/b-x.csv" "$R/twoaxis.txt" $TA --column x=#4 --column f_c=#5 &&
	ok "two-axis file, axis 2 by name and by position (x=#4 f_c=#5): compare, chatter, replay bit for bit"

# 3. A 1 kHz log, tabs, time in us late by 0..40 us (steps within 4 %),
# encoder counts: --jitter 0.05 accepts it.
J="--column t=time_us --scale t=1e-6 --column count=enc --column f_c=cmd_N --jitter 0.05"
# energy: every definition but filtered sums f_c dx and uses no step: bit
# for bit. filtered, W += f_c(k-1) v(k) dt, takes the measured step (v =
# dx/dt from the stamps): (dx/dt) dt against the reference's (dx/T) T, each
# dx to within a few roundings, so |dW| <= (n + 6) 2^-53 sum |f_c(k-1) dx(k)|
# (n rows, the sums' own roundings included).
if run_both jit-energy energy "$W/a-count.csv" "$R/jitter.tsv" $J; then
	# the largest step off T, as the stamps give it (checked here with awk:
	# the line named has a step of the largest |step - 1000 us|; steps of
	# equal integer us tie up to the roundings of us x 1e-6)
	nl=$(sed -n 's/.*jitter.tsv: the time steps are within 4 % of the nominal period 0.001 s (the largest at line \([0-9]*\); --jitter 0.05 allows 5 %)$/\1/p' "$W/e")
	[ -n "$nl" ] && awk -F'\t' -v nl="$nl" 'NR > 2 { d = $1 - p - 1000; if (d < 0) d = -d; if (d > m) m = d; if (NR == nl) at = d }
		NR > 1 { p = $1 } END { exit !(m == 40 && at == m) }' "$R/jitter.tsv" &&
		ok "jittered log: the note names the largest step (40 us, 4 %, line $nl)" || fail "jitter note: $(cat "$W/e")"
	grep -v '^filtered,' "$W/jit-energy.ref" >"$W/o1"
	grep -v '^filtered,' "$W/jit-energy.rec" >"$W/o2"
	[ "$(wc -l <"$W/o1")" -eq 6 ] && cmp -s "$W/o1" "$W/o2" &&
		ok "jittered log, energy: online, eq3, eq2, ignore, ignore-undo bit for bit" ||
		fail "jittered energy differs: $(diff "$W/o1" "$W/o2" | head -4)"
	bound=$(awk -F, 'NR > 1 { x = $2 * 1e-5; if (NR > 2) { d = f * (x - xp); s += d < 0 ? -d : d }; f = $3; xp = x }
		END { printf "%.17g", (NR + 6) * 2^-53 * s }' "$W/a-count.csv")
	grep '^filtered,' "$W/jit-energy.ref" >"$W/f1"
	grep '^filtered,' "$W/jit-energy.rec" >"$W/f2"
	paste -d, "$W/f1" "$W/f2" | awk -F, -v b="$bound" '{
		if ($2 != $11) exit 1
		for (i = 3; i <= 6; i++) { d = $i - $(i + 9); if (d < 0) d = -d; if (d > b) exit 1 } }' &&
		[ -s "$W/f1" ] && ok "jittered log, energy filtered on measured steps: W within $bound J" ||
		fail "filtered beyond $bound J: $(cat "$W/f1" "$W/f2")"
fi
# compare: the nominal T (windows, rates), steps within --jitter: every
# column equal but the spans of time read from the stamps, duration_s and
# chatter_s, off by the delays (<= 40 us)
if run_both jit-compare compare "$W/a-count.csv" "$R/jitter.tsv" $J; then
	paste -d, "$W/jit-compare.ref" "$W/jit-compare.rec" | awk -F, 'NR == 2 {
		n = NF / 2
		for (i = 1; i <= n; i++) {
			if (i == 3 || i == 13) { d = $(i + n) - $i; if (!(d > -40e-6 && d < 40e-6)) exit 1 }
			else if ($i != $(i + n)) exit 1
		} }' && head -n 1 "$W/jit-compare.ref" | cut -d, -f3,13 | grep -q '^duration_s,chatter_s$' &&
		ok "jittered log, compare: every column bit for bit but duration_s and chatter_s (within 40 us)" ||
		fail "jittered compare: $(cat "$W/jit-compare.ref" "$W/jit-compare.rec")"
fi
# chatter: the same intervals and values, their times from the stamps (<= 40 us)
if run_both jit-chatter chatter "$W/a-count.csv" "$R/jitter.tsv" $J; then
	paste -d, "$W/jit-chatter.ref" "$W/jit-chatter.rec" | awk -F, 'NR > 1 {
		if ($1 != $5 || $4 != $8) bad++
		for (i = 2; i <= 3; i++) { d = $(i + 4) - $i; if (d < -1e-12 || d > 40e-6 + 1e-12) bad++ } }
		END { exit bad > 0 || NR < 2 }' && ok "jittered log, chatter: same intervals, times within 40 us" ||
		fail "jittered chatter: $(cat "$W/jit-chatter.ref" "$W/jit-chatter.rec")"
fi
JITTER=1 same_replay jit "$W/a-count.csv" "$R/jitter.tsv" $J &&
	ok "jittered log, replay (the controller on the nominal T): rows bit for bit, t within 40 us"

# Where the measured step changes a result: a device that logs its own
# velocity. At v = 0.01 m/s and f_c = 1 N, x = v t from the jittered stamps:
# filtered's W = sum f_c(k-1) v(k) dt is the work sum f_c dx, eq3's W, to the
# roundings (1e-15 J here); on the nominal T it would be v n T, off by the
# stamps' drift (4 us here: the last delay minus the first, 4e-8 J).
awk -F'\t' 'NR == 1 { print "t_us\tx\tv\tf_c"; next }
	{ printf "%s\t%.17g\t0.01\t1\n", $1, 0.01 * $1 * 1e-6 }' "$R/jitter.tsv" >"$W/vel.tsv"
VEL="--column t=t_us --scale t=1e-6 --set run.rate=1000 --observer eq3 --observer filtered"
if expect_rc 0 "$A" energy --format csv $VEL --jitter 0.05 "$W/vel.tsv"; then
	awk -F, '$2 == "eq3" { a = $4 } $2 == "filtered" { b = $4 } END { d = a - b; exit !(a > 0.049 && d < 1e-15 && d > -1e-15) }' "$W/out" &&
		ok "a logged velocity: filtered W on measured steps equals the work (eq3) within 1e-15 J" ||
		fail "filtered with logged v: $(cat "$W/out")"
	expect_rc 0 "$A" energy --format csv $VEL "$W/vel.tsv" &&
		awk -F, '$2 == "eq3" { a = $4 } $2 == "filtered" { b = $4 } END { d = a - b; exit !(d > 1e-9 || d < -1e-9) }' "$W/out" &&
		ok "  (without --jitter, on the nominal T, it is off by more than 1e-9 J)" ||
		fail "filtered nominal: $(cat "$W/out")"
fi

# Jitter beyond the tolerance: the first step more than 1 % off 1 ms, found
# here independently of popc-analyze
first=$(awk -F'\t' 'NR > 2 { d = $1 - p; if (d < 990 || d > 1010) { print NR; exit } } NR > 1 { p = $1 }' "$R/jitter.tsv")
J1="--column t=time_us --scale t=1e-6 --column count=enc --column f_c=cmd_N --set run.rate=1000 --jitter 0.01"
for verb in compare chatter "replay --variant improved --prefix $W/j1-"; do
	# shellcheck disable=SC2086
	expect_rc 2 "$A" $verb $J1 "$R/jitter.tsv" &&
		grep -q "jitter.tsv:$first: column 1 (t): the time step from line $((first - 1)) .* off the nominal period 0.001 s (run.rate), more than --jitter 0.01 (1 %)" "$W/err" ||
		fail "--jitter 0.01 $verb: $(cat "$W/err")"
done
ok "--jitter 0.01 on 4 % jitter: compare, chatter, replay refuse naming line $first"
# energy's definitions use the measured step or none: the tolerance does not
# apply, the same numbers as with --jitter 0.05 ...
expect_rc 0 "$A" energy --format csv $J1 --set controller.variant=ref-energy "$R/jitter.tsv" &&
	cut -d, -f2- "$W/out" | cmp -s - "$W/jit-energy.rec" && ok "energy --jitter 0.01: measured steps, accepted" ||
	fail "energy --jitter 0.01: $(cat "$W/err")"
# ... except the observer that ran on the nominal T: 'online' of a
# filtered-velocity log (W += f_c v T)
expect_rc 2 "$A" energy $J1 --set controller.variant=filtered-velocity --observer online "$R/jitter.tsv" &&
	grep -q "jitter.tsv:$first: column 1 (t): .* more than --jitter 0.01 (1 %): energy uses the nominal T" "$W/err" &&
	ok "energy online filtered-velocity (nominal T) beyond --jitter: refused, line $first" ||
	fail "energy online filtered: $(cat "$W/err")"
expect_rc 0 "$A" energy $J1 --set controller.variant=filtered-velocity --observer filtered "$R/jitter.tsv" &&
	ok "  its 'filtered' on measured steps: accepted" || fail "filtered measured: $(cat "$W/err")"
# without --jitter and a rate: uneven, as before, with the hint
expect_rc 2 "$A" compare --column t=time_us --scale t=1e-6 --column count=enc "$R/jitter.tsv" &&
	grep -q "jitter.tsv:4: column 1 (t): uneven time steps: .*--set run.rate=HZ and --jitter FRACTION" "$W/err" &&
	ok "jitter without --jitter: refused as uneven, naming --jitter" || fail "no --jitter: $(cat "$W/err")"

# Usage and bad recordings: exit 2, named
expect_rc 2 "$A" compare --column t=time_us --scale t=1e-6 --column count=enc --jitter 0.05 "$R/jitter.tsv" &&
	grep -q "jitter.tsv: --jitter 0.05: jitter is measured against the nominal period: give the device's rate with --set run.rate=HZ" "$W/err" &&
	ok "--jitter without a rate: refused" || fail "--jitter no rate: $(cat "$W/err")"
expect_rc 2 "$A" compare $PH --set run.rate=1000 --jitter 0.05 "$R/phantom.txt" &&
	grep -q "phantom.txt: --jitter 0.05: the log has no time column" "$W/err" &&
	ok "--jitter without a time column: refused" || fail "--jitter no t: $(cat "$W/err")"
for bad in 0 0.6 -0.1 abc; do
	expect_rc 2 "$A" compare --jitter "$bad" "$W/a-x.csv" && grep -q -- "--jitter '$bad': expected a fraction" "$W/err" ||
		fail "--jitter $bad: $(cat "$W/err")"
done
ok "--jitter outside (0, 0.5]: usage error"
expect_rc 2 "$A" compare $PH "$R/phantom.txt" &&
	grep -q "phantom.txt: missing column 't': map the time column with --column t=HEADER (or t=#N, its position), or give the rate of a log without one with --set run.rate=HZ" "$W/err" &&
	ok "no time column and no rate: refused, naming both ways out" || fail "no t no rate: $(cat "$W/err")"
grep -v '^#' "$R/phantom.txt" >"$W/ph-nocomment.txt"
expect_rc 2 "$A" compare --column t=1 "$W/ph-nocomment.txt" &&
	grep -q "ph-nocomment.txt:1: --column t=1: the file has no column '1' (a column by position is '#1'; a file without a column names line needs --no-header)" "$W/err" &&
	ok "a headerless file read with names: the hint names --no-header" || fail "numeric names: $(cat "$W/err")"
# a first row whose numbers repeat, read as names: the duplicate-name error
# says the names line holds only numbers
printf '0.5 0.0 0.0\n0.6 0.1 0.2\n' >"$W/num-names.txt"
expect_rc 2 "$A" compare "$W/num-names.txt" &&
	grep -q "num-names.txt:1: column 3 (0.0) repeats the name of column 2.*(line 1, read as the column names, holds only numbers: a file without a column names line needs --no-header)" "$W/err" &&
	ok "numeric column names: the hint names --no-header" || fail "numeric names (duplicate): $(cat "$W/err")"
expect_rc 2 "$A" compare --column t=1 "$W/a-x.csv" &&
	grep -q "a-x.csv:1: --column t=1: the file has no column '1' (a column by position is '#1'; a file without a column names line needs --no-header)" "$W/err" &&
	ok "--column t=1: the hint names '#1'" || fail "t=1: $(cat "$W/err")"
expect_rc 2 "$A" compare --no-header --column x=#9 "$R/phantom.txt" &&
	grep -q "phantom.txt:2: --column x=#9: the file has no column '#9' (it has 6 columns)" "$W/err" &&
	ok "--column x=#9 of 6 columns: refused" || fail "#9: $(cat "$W/err")"
awk 'NR == 40 { $4 = "n/a" } { print }' "$R/phantom.txt" >"$W/ph-bad.txt"
expect_rc 2 "$A" compare $PH --set run.rate=1000 "$W/ph-bad.txt" &&
	grep -q "ph-bad.txt:40: column 4 (#4): not a finite number 'n/a'" "$W/err" &&
	ok "text in a headerless column that is read: file, line, column" || fail "bad cell: $(cat "$W/err")"
awk 'NR == 40 { $6 = "" } { print }' "$R/phantom.txt" >"$W/ph-short.txt"
expect_rc 2 "$A" compare $PH --set run.rate=1000 "$W/ph-short.txt" &&
	grep -q "ph-short.txt:40: 5 cells, expected 6 (short row)" "$W/err" &&
	ok "a short headerless row: file, line" || fail "short row: $(cat "$W/err")"
# a step no double can divide by (subnormal): energy does not check the
# tolerance, but v = dx/dt would be inf: refused, named
printf 't,x,f_c\n0,0,0\n5e-324,1e-5,1\n0.001,2e-5,1\n' >"$W/tiny.csv"
expect_rc 2 "$A" energy --set run.rate=1000 --jitter 0.5 "$W/tiny.csv" &&
	grep -q "tiny.csv:3: column 1 (t): the time step from line 2, 4.94066e-324 s, is no usable step" "$W/err" &&
	ok "--jitter: a subnormal step refused, named" || fail "subnormal step: $(cat "$W/err")"
# the first row of a headerless file is a row: its errors name line 2 (after a comment)
sed '2s/^ *[^ ]* /  zz /' "$R/phantom.txt" >"$W/ph-first.txt"
expect_rc 2 "$A" compare $PH --set run.rate=1000 "$W/ph-first.txt" &&
	grep -q "ph-first.txt:2: column 1 (#1): not a finite number 'zz'" "$W/err" &&
	ok "the first row of a headerless file: read as a row, named line 2" || fail "first row: $(cat "$W/err")"
finish
