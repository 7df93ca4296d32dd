# popc-analyze energy: the offline recompute with the library's observer equals
# the logged W and E_ref bit for bit for every variant, and a log rewritten with
# other column names, order, delimiter and comment character (mapped with
# --column) recomputes to exactly the same numbers.
. "$2"

for v in none po-pc ref-energy filtered-velocity ignore hold improved; do
	run_scene paper.ini "$W/$v.csv" --variant "$v"
	if expect_rc 0 "$A" energy --check --format csv "$W/$v.csv"; then
		# the online row: max |dW|, max |dE_ref| and differing rows all exactly 0
		line=$(grep ",online=" "$W/out")
		case "$line" in
		*,0,0,0) ok "$v: online recompute bitwise equal ($line)" ;;
		*) fail "$v: online recompute differs: $line" ;;
		esac
	fi
done

# The other definitions really differ (a check that cannot fail is no check):
# eq. 2 pairs f_c(k) with dx(k) and ends far from the logged W on ref-energy.
expect_rc 0 "$A" energy --format csv --observer eq2 "$W/ref-energy.csv" &&
	awk -F, 'NR == 2 { exit !($8 > 1e-3) }' "$W/out" &&
	ok "eq2 differs from the logged W (>1 mJ)" || fail "eq2 should differ from eq3 on ref-energy"

# --check fails (exit 1) when the log's W was tampered with in its last digit.
awk -F, 'BEGIN { OFS = "," } /^#/ || /^t,/ { print; next } NR == 3000 { $9 = $9 + 1e-9 } { print }' \
	"$W/ref-energy.csv" >"$W/tampered.csv"
expect_rc 1 "$A" energy --check --observer online "$W/tampered.csv" && ok "--check catches a changed W"

# -o ends like a popc log: '# stop = completed', or, cut short by bad input
# (text in f_c at line 3000), '# stop = input error' after every row read
# before it, each equal to the complete recompute's row.
expect_rc 0 "$A" energy -o "$W/full.energy.csv" "$W/ref-energy.csv" &&
	[ "$(tail -n 1 "$W/full.energy.csv")" = "# stop = completed" ] && ok "energy -o: '# stop = completed'" ||
	fail "energy -o end: $(tail -n 1 "$W/full.energy.csv")"
awk -F, 'BEGIN { OFS = "," } NR == 3000 { $8 = "abc" } { print }' "$W/ref-energy.csv" >"$W/bad-fc.csv"
before=$(head -n 2999 "$W/bad-fc.csv" | grep -v '^#' | tail -n +2 | wc -l)
if expect_rc 2 "$A" energy -o "$W/cut.energy.csv" "$W/bad-fc.csv"; then
	grep -v '^#' "$W/cut.energy.csv" >"$W/cut.rows"
	grep -v '^#' "$W/full.energy.csv" | head -n $((before + 1)) >"$W/full.rows"
	[ "$(tail -n 1 "$W/cut.energy.csv")" = "# stop = input error" ] &&
		[ "$(wc -l <"$W/cut.rows")" -eq $((before + 1)) ] && cmp -s "$W/cut.rows" "$W/full.rows" &&
		grep -q "bad-fc.csv:3000: column 8 (f_c)" "$W/err" &&
		ok "energy -o cut by bad input: $before rows kept, '# stop = input error'" ||
		fail "energy -o cut: $(tail -n 2 "$W/cut.energy.csv"), $(wc -l <"$W/cut.rows") lines, want $((before + 1))"
fi

# A foreign rewrite of the improved log: no popc header, other names and order,
# ';' delimiter, '%' comments; the scene's parameters come from --set.
awk -F, '
	/^#/ { next }
	/^t,/ { print "% recorded elsewhere"; print "Eref;PO;F_cmd;F_pc;F_env;vel;enc;pos_m;time"; next }
	{ print $10 ";" $9 ";" $8 ";" $7 ";" $6 ";" $5 ";" $3 ";" $2 ";" $1 }' \
	"$W/improved.csv" >"$W/foreign.txt"
MAP="--column t=time --column x=pos_m --column count=enc --column v=vel --column f_e=F_env
     --column f_pc=F_pc --column f_c=F_cmd --column W=PO --column E_ref=Eref"
SETS="--set controller.variant=improved --set encoder.resolution=1e-5 --set run.rate=1000"
# shellcheck disable=SC2086
expect_rc 0 "$A" energy $MAP --comment % $SETS -o "$W/foreign.energy.csv" "$W/foreign.txt" ||
	cat "$W/err"
expect_rc 0 "$A" energy -o "$W/own.energy.csv" "$W/improved.csv"
grep -v '^#' "$W/own.energy.csv" >"$W/a"
grep -v '^#' "$W/foreign.energy.csv" >"$W/b"
if [ "$(wc -l <"$W/a")" -eq 5002 ] && cmp -s "$W/a" "$W/b"; then
	ok "foreign column order and names: recompute identical to popc's own log"
else
	fail "foreign recompute differs from the own-log recompute"; diff "$W/a" "$W/b" | head -5 >&2
fi
# and --check passes on it: the mapped W, E_ref are the logged ones
# shellcheck disable=SC2086
expect_rc 0 "$A" energy --check --observer online $MAP --comment % $SETS "$W/foreign.txt" &&
	ok "foreign log --check"

# Without f_e, v and W columns: derived from x, the environment and the observer.
awk -F, '/^#/ { next } /^t,/ { print "t,x,f_c"; next } { print $1 "," $2 "," $8 }' \
	"$W/ref-energy.csv" >"$W/minimal.csv"
expect_rc 0 "$A" energy --format csv --observer eq3 --set run.rate=1000 "$W/minimal.csv" &&
	awk -F, -v want="$(awk -F, '/^[0-9]/ { w = $9 - $10 } END { printf "%.6e", w }' "$W/ref-energy.csv")" \
		'NR == 2 { got = sprintf("%.6e", $6); exit !(got == want) }' "$W/out" &&
	ok "minimal log (t, x, f_c): W - E_ref end matches the full log" ||
	fail "minimal log recompute: $(cat "$W/out")"

expect_rc 0 "$A" energy --help && ok "--help"
finish
