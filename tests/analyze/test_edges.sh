# Synthetic logs at the edges of a double: every number popc-analyze prints is
# finite and accurate, or the log is refused (exit 2) naming the line and the
# quantity that a double cannot hold; no verb prints inf or NaN, and replay
# never writes a log the other verbs refuse. popc-analyze of 46f30c1 printed
# pc_rms inf for forces of 1e308, 'W_end -nan' (exit 0) for a time step of
# 5e-324 s, and replay wrote a log with run.rate = inf.
. "$2"
finite_out() { ! grep -qiE '(^|[^a-z])(-?nan|-?inf)([^a-z]|$)' "$W/out"; }
gen() { awk -v n="$2" "BEGIN { $3 }" >"$W/$1"; }

# forces of +-1e308 on every row (a plain sum of f^2 overflows at the first);
# accurate: within the rounding of a sum of 3000 squares, n eps / 2 = 3.3e-13
# (measured 1.9e-14)
gen big.csv 3000 'print "t,x,f_pc,f_c"; for (k = 0; k < n; k++) { f = k % 2 ? "1e308" : "-1e308"; printf "%.17g,%.17g,%s,%s\n", k * 0.001, (k % 4 < 2 ? 0 : 1e-5) + 0.001, f, f }'
expect_rc 0 "$A" compare --format csv "$W/big.csv" && finite_out &&
	tail -n 1 "$W/out" | awk -F, '{ r = $5 / 1e308; exit !(r > 1 - 4e-13 && r < 1 + 4e-13 && $6 == $5) }' &&
	ok "forces of 1e308: pc_rms and pc_rms_late are 1e308 within 4e-13 ($(tail -n 1 "$W/out" | cut -d, -f5))" ||
	fail "1e308 forces, compare: $(tail -n 1 "$W/out") $(cat "$W/err")"
expect_rc 1 "$A" chatter "$W/big.csv" && finite_out && grep -q "PC RMS up to 1e+308 N" "$W/out" &&
	ok "forces of 1e308: chatter flags them (exit 1), its RMS 1e308" || fail "1e308 chatter: $(cat "$W/out")"
expect_rc 0 "$A" energy "$W/big.csv" && finite_out && ok "forces of 1e308: energy finite" ||
	fail "1e308 energy: $(cat "$W/out")"
# and tiny ones: 1e-300 N (a plain f^2 underflows to 0)
sed 's/1e308/1e-300/g' "$W/big.csv" >"$W/tinyf.csv"
expect_rc 0 "$A" compare --format csv "$W/tinyf.csv" &&
	tail -n 1 "$W/out" | awk -F, '{ r = $5 / 1e-300; exit !(r > 1 - 4e-13 && r < 1 + 4e-13) }' &&
	ok "forces of 1e-300: pc_rms 1e-300 ($(tail -n 1 "$W/out" | cut -d, -f5))" || fail "1e-300 forces: $(tail -n 1 "$W/out")"

# a time step of 5e-324 s (the smallest double): no finite rate
printf 't,x,f_c\n0,0,1\n5e-324,1e-05,1\n1e-323,2e-05,1\n1.5e-323,3e-05,1\n' >"$W/step.csv"
for verb in energy chatter compare "report --no-draw -o $W/rep"; do
	# shellcheck disable=SC2086
	expect_rc 2 "$A" $verb "$W/step.csv" && finite_out &&
		grep -q "step.csv:3: column 1 (t): the first time step, 4.94066e-324 s (lines 2-3), cannot be the period: its rate 1/T overflows a double" "$W/err" ||
		fail "5e-324 step, $verb: $(cat "$W/out" "$W/err")"
done
ok "a 5e-324 s step: refused by every verb, naming lines 2-3"
expect_rc 2 "$A" replay --variant improved --prefix "$W/step-" "$W/step.csv" && [ ! -e "$W/step-improved.csv" ] &&
	ok "a 5e-324 s step: replay refuses it and writes nothing" || fail "5e-324 replay: $(cat "$W/err")"
# 10 MHz: a period the replay logs' header cannot hold as run.rate
gen fast.csv 200 'print "t,x,f_c"; for (k = 0; k < n; k++) printf "%.17g,%.17g,1\n", k * 1e-7, (k % 3) * 1e-5'
expect_rc 2 "$A" replay --variant none --prefix "$W/fast-" "$W/fast.csv" && [ ! -e "$W/fast-none.csv" ] &&
	grep -q "fast.csv: the period 1e-07 s (the first time step) is a rate of 10000000: out of range; allowed \[1, 1e+06\] Hz, which the replay logs' header must hold as run.rate" "$W/err" &&
	ok "replay of a 10 MHz log: refused, the rate named" || fail "10 MHz replay: $(cat "$W/err")"
expect_rc 0 "$A" energy "$W/fast.csv" && finite_out && ok "  energy reads it (no run.rate needed)" || fail "10 MHz energy"

# positions of 1e-300 m, and steps of 1e-300 s: finite or refused by name
gen tinyx.csv 3000 'print "t,x,f_c"; for (k = 0; k < n; k++) printf "%.17g,%.17g,1\n", k * 0.001, k * 1e-300'
for verb in energy chatter compare; do
	expect_rc 0 "$A" "$verb" "$W/tinyx.csv" && finite_out || fail "1e-300 m positions, $verb: $(cat "$W/out" "$W/err")"
done
ok "positions of 1e-300 m: energy, chatter, compare finite"
gen tinyt.csv 3000 'print "t,x,f_c"; for (k = 0; k < n; k++) printf "%.17g,%.17g,1\n", k * 1e-300, (k % 2) * 1e-5'
expect_rc 0 "$A" energy "$W/tinyt.csv" && finite_out && ok "steps of 1e-300 s: energy finite" ||
	fail "1e-300 s energy: $(cat "$W/out" "$W/err")"
expect_rc 2 "$A" compare "$W/tinyt.csv" && grep -q "tinyt.csv: chatter detector: window 0.1 s and lc_window 2 s at a period of 1e-300 s are 1e+299 and 2e+300 ticks" "$W/err" &&
	ok "steps of 1e-300 s: compare names the file and the windows it cannot count" || fail "1e-300 s compare: $(cat "$W/err")"
# ... and a velocity dx/T that a double cannot hold: 100 m in 1e-307 s
gen fastv.csv 3 'print "t,x,f_c"; for (k = 0; k < n; k++) printf "%.17g,%.17g,1\n", k * 1e-307, k * 100'
expect_rc 2 "$A" energy --set encoder.resolution=1 "$W/fastv.csv" && finite_out &&
	grep -q "fastv.csv:3: the velocity v = (x(k) - x(k-1)) / T overflows a double" "$W/err" &&
	ok "v = 100 m / 1e-307 s: refused at its line" || fail "huge v: $(cat "$W/out" "$W/err")"

# logged energies whose difference overflows, and a PC energy sum that does
gen wme.csv 3 'print "t,x,f_c,W,E_ref"; for (k = 0; k < n; k++) printf "%.17g,0,0,%s,%s\n", k * 0.001, k ? "1e308" : "0", k ? "-1e308" : "0"'
expect_rc 2 "$A" compare "$W/wme.csv" && finite_out && grep -q "wme.csv:3: W - E_ref overflows a double" "$W/err" &&
	ok "W - E_ref = 1e308 - (-1e308): refused at its line" || fail "W - E_ref: $(cat "$W/out" "$W/err")"
# (W and E_ref logged: a recomputed W would overflow first)
gen pce.csv 4 'print "t,x,f_pc,f_c,W,E_ref"; for (k = 0; k < n; k++) printf "%.17g,%d,1e308,1e308,0,0\n", k * 0.001, (k % 2) * 10'
expect_rc 2 "$A" compare --set encoder.resolution=1 "$W/pce.csv" && finite_out &&
	grep -q "pce.csv:3: the PC energy, the sum of f_pc(k-1) (x(k) - x(k-1)), overflows a double here" "$W/err" &&
	ok "PC energy 1e308 N x 10 m: refused at its line" || fail "PC energy: $(cat "$W/out" "$W/err")"
expect_rc 2 "$A" energy --set encoder.resolution=1 "$W/pce.csv" && finite_out &&
	grep -q "pce.csv:3: observer .*: W, E_ref or W - E_ref overflows a double here" "$W/err" &&
	ok "  energy: the observer's W, refused at its line" || fail "energy W: $(cat "$W/out" "$W/err")"
finish
