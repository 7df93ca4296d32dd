# The chatter and limit-cycle thresholds relative to the scene (docs/
# ANALYSIS.md, "Thresholds relative to the scene"), on synthetic logs written
# here whose truth is known by construction, read as foreign logs that get the
# scene from --set, and on popc logs that carry it in their header. Each case
# also runs with the absolute thresholds of before, written as relative ones
# for the scene (0.5 N of PC RMS, 50 counts, 50 Hz), to show what they missed.
. "$2"

# synth NAME SECONDS RESOLUTION_M X_EXPR F_PC_EXPR: a 1 kHz log t,x,f_pc; x is
# X_EXPR (in m, of t and k) floored to the encoder's count as a real encoder
# reads it; the wall is at 0, so x > 0 is contact.
synth() {
	awk -v n="$2" -v d="$3" 'BEGIN {
		pi = 3.141592653589793; print "t,x,f_pc"
		for (k = 0; k <= n * 1000; k++) {
			t = k / 1000
			x = '"$4"'; f = '"$5"'
			c = x / d; c = (c >= 0) ? int(c) : -int(-c) - (int(-c) != -c)
			printf "%.17g,%.17g,%.17g\n", t, c * d, f
		}
	}' >"$W/$1.csv"
}
# verdict NAME WANT_RC [--set/--threshold ...]: chatter's exit status and the
# kinds of its CSV rows (chatter, limit_cycle) as one word, e.g. "chatter" or
# "limit_cycle" or "none"
verdict() {
	name=$1; shift
	"$A" chatter --format csv "$@" "$W/$name.csv" >"$W/out" 2>"$W/err"
	rc=$?
	kinds=$(awk -F, 'NR > 1 && !seen[$2]++ { printf "%s%s", n++ ? "+" : "", $2 } END { if (!n) printf "none" }' "$W/out")
	echo "$rc $kinds"
}
# check NAME WANT [options]: WANT is "RC KINDS" as verdict prints
check() {
	name=$1 want=$2; shift 2
	got=$(verdict "$name" "$@")
	[ "$got" = "$want" ] && ok "$name $*: $got" ||
		{ fail "$name $*: got '$got', want '$want'"; cat "$W/out" "$W/err" >&2; }
}
# the old absolute thresholds for a scene with PC bound B (N) at 1 kHz
old() { echo "--threshold pc_rms_share=$(awk -v b="$1" 'BEGIN { print 0.5 / b }') --threshold lc_amplitude=50 --threshold lc_hysteresis=5 --threshold lc_freq_share=0.05"; }
scene() { echo "--set encoder.resolution=$1 --set controller.pc_bound=$2"; }

# 1. A decaying contact oscillation (9 Hz, 1.5 mm, time constant 1 s, 5 s):
#    no limit cycle, no chatter, before and now.
synth decay 5 1e-5 '3e-3 + 1.5e-3 * exp(-t) * sin(2 * pi * 9 * t)' 0
check decay "0 none" $(scene 1e-5 5)
check decay "0 none" $(scene 1e-5 5) $(old 5)

# 2. A sustained 9 Hz oscillation of 20 counts (0.2 mm), below the 50 counts
#    of before: a limit cycle now.
synth small 5 1e-5 '3e-3 + 2e-4 * sin(2 * pi * 9 * t)' 0
check small "1 limit_cycle" $(scene 1e-5 5)
check small "0 none" $(scene 1e-5 5) $(old 5)
"$A" chatter --format csv $(scene 1e-5 5) "$W/small.csv" >"$W/out" 2>/dev/null
awk -F, 'NR == 2 { exit !($2 == "limit_cycle" && $5 > 1.8e-4 && $5 < 2.1e-4) }' "$W/out" &&
	ok "small: amplitude 0.2 mm measured" || fail "small amplitude: $(cat "$W/out")"

# 3. A 60 Hz buzz of 20 counts, sustained, no PC force: above the 50 Hz of
#    before, below a tenth of the 1 kHz control rate now.
synth buzz 3 1e-5 '3e-3 + 2e-4 * sin(2 * pi * 60 * t)' 0
check buzz "1 limit_cycle" $(scene 1e-5 5)
check buzz "0 none" $(scene 1e-5 5) $(old 5)
# ... and the same buzz in a 200 Hz log is above a tenth of that rate: none
awk -F, 'NR == 1 || (NR - 2) % 5 == 0' "$W/buzz.csv" >"$W/buzz200.csv"
check buzz200 "0 none" $(scene 1e-5 5)

# 4. A one-count dither with the PC switching +-0.3 N every tick (bound 5 N:
#    6 % of it), in contact: chatter now, not with 0.5 N of RMS.
synth dither 3 1e-5 '3e-3 + 0.5e-5 + (k % 2) * 1e-5' '(k % 2) ? 0.3 : -0.3'
check dither "1 chatter" $(scene 1e-5 5)
check dither "0 none" $(scene 1e-5 5) $(old 5)
# the same PC force is 1.5 % of a 20 N bound: below 5 %, not chatter
check dither "0 none" $(scene 1e-5 20)

# 5. Chatter at a low bound: +-0.4 N every tick with pc_bound 0.4 N.
synth lowbound 3 1e-5 '3e-3 + 0.5e-5 + (k % 2) * 1e-5' '(k % 2) ? 0.4 : -0.4'
check lowbound "1 chatter" $(scene 1e-5 0.4)
check lowbound "0 none" $(scene 1e-5 0.4) $(old 0.4)
# the scene from a popc log's header: ref-energy on the paper scene with
# controller.pc_bound = 0.4 chatters at its bound from about 3.8 s
run_scene paper.ini "$W/bound04.csv" --variant ref-energy --set controller.pc_bound=0.4
check bound04 "1 chatter"
check bound04 "0 none" $(old 0.4)

# 6. The same 1.6 mm, 9.25 Hz limit cycle at several resolutions: flagged
#    from 1e-6 to 4e-4 m (1600 to 4 counts), its amplitude measured within
#    one count; 1e-3 m (1.6 counts) is below what the detector can tell from
#    quantization (4 counts) and is not flagged. Before: 1e-4 (16 counts)
#    was missed while 1e-5 (160 counts) was flagged.
for res in 1e-6 1e-5 1e-4 4e-4 1e-3; do
	synth "lc$res" 5 "$res" '3e-3 + 1.6e-3 * sin(2 * pi * 9.25 * t)' 0
	want="1 limit_cycle"
	[ "$res" = 1e-3 ] && want="0 none"
	check "lc$res" "$want" $(scene "$res" 5)
	[ "$res" = 1e-3 ] && continue
	awk -F, -v d="$res" 'NR == 2 { a = $5 - 1.6e-3; exit !(a < d + 1e-6 && -a < d + 1e-6) }' "$W/out" &&
		ok "lc$res: amplitude 1.6 mm within a count" || fail "lc$res amplitude: $(cat "$W/out")"
done
check lc1e-5 "1 limit_cycle" $(scene 1e-5 5) $(old 5)
check lc1e-4 "0 none" $(scene 1e-4 5) $(old 5)

# A foreign log without --set: the note names the PC bound assumed.
"$A" chatter "$W/dither.csv" >/dev/null 2>"$W/err"
grep -q "controller.pc_bound = 5" "$W/err" && ok "note names the PC bound assumed" ||
	fail "no pc_bound note: $(cat "$W/err")"
finish
