#!/usr/bin/env bash
# A teleoperation channel's delays in seconds, from a trace file and as a
# random walk, and its per-packet event log (docs/TELEOPERATION.md, "Delays
# in seconds and from a trace", "The channel log"): a delay in seconds runs
# the rows of the same delay in ticks and is written only when given; a
# delay that is no whole number of ticks, two spellings of one delay and bad
# trace files are exit 2 naming the key or file:line and the allowed range;
# a trace's digest is in the log header; the channel log's events add up,
# per direction, against the main log's flags; slave.rate = run.rate runs
# today's rows, a faster slave passes energy --check and the two-port
# condition. No clock: events are counted. Argument: the popc-analyze program.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
ANALYZE=${1:?popc-analyze}
T=$(mktemp -d /tmp/popc-teleop-channel-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

WALL=$SRC/data/scenes/teleop-wall.ini
TRACE=$SRC/data/traces/wifi-burst.txt
rows() { grep -v '^#' "$1"; }

# delays in seconds: the rows of the same delays in ticks
expect_exit 0 "teleop-wall, delays in ticks" "$POPC" run "$WALL" -q --set run.duration=2 --log "$T/ticks.csv"
check "  no seconds key written (not used)" sh -c "! grep -qE '^# (delay_s|jitter_s|jitter_model|trace) = ' '$T/ticks.csv'"
expect_exit 0 "the same delays in seconds" "$POPC" run "$WALL" -q --set run.duration=2 \
	--set forward.delay_ticks=0 --set forward.delay_s=0.1 --set backward.delay_ticks=0 \
	--set backward.delay_s=0.1 --log "$T/seconds.csv"
check "  the same rows" cmp -s <(rows "$T/ticks.csv") <(rows "$T/seconds.csv")
check "  delay_s written, under [forward]" sh -c "grep -A12 -x '# \[forward\]' '$T/seconds.csv' | grep -qx '# delay_s = 0.1'"
expect_exit 0 "jitter in seconds at 2 kHz" "$POPC" run "$WALL" -q --set run.duration=1 --set run.rate=2000 \
	--set forward.jitter_s=0.0105 --set forward.in_order=off --channel-log "$T/j.csv"
check "  drawn delays within 100 + [0, 21] ticks, some above 100" sh -c "awk -F, '\$2 == \"forward\" && \$4 == \"sent\" {if (\$5 < 100 || \$5 > 121) bad = 1; if (\$5 > 100) up = 1} END {exit bad || !up}' '$T/j.csv'"

# bad input: exit 2 before any work, naming the key or file:line and what is allowed
bad_case() { # DESC TEXT ASSIGNMENT...
	local what=$1 text=$2; shift 2
	local sets=()
	for a in "$@"; do sets+=(--set "$a"); done
	rm -f "$T/bad.csv"
	expect_exit 2 "$what" "$POPC" run "$WALL" "${sets[@]}" --log "$T/bad.csv"
	check "  says: $text" err_has "$text"
	check "  no log written" test ! -e "$T/bad.csv"
}
bad_case "delay_ticks and delay_s" "forward.delay_ticks = 100 and forward.delay_s = 0.1 s: give one of them" \
	forward.delay_s=0.1
bad_case "half a tick" "backward.delay_s = 0.0005 s is 0.5 ticks at run.rate = 1000 Hz, not a whole number" \
	backward.delay_ticks=0 backward.delay_s=0.0005
bad_case "  names the nearest whole delays" "e.g. 0 s (0 ticks) or 0.001 s (1)" \
	backward.delay_ticks=0 backward.delay_s=0.0005
bad_case "seconds beyond the channel" "is 200000 ticks at run.rate = 2000 Hz; allowed at most 100000 ticks (50 s)" run.rate=2000 forward.delay_ticks=0 forward.delay_s=100
bad_case "a walk without jitter" "forward.jitter_model = walk needs forward.jitter_ticks" forward.jitter_model=walk
bad_case "a trace and a delay" "forward.trace and forward's delay (100 ticks)" "forward.trace=$TRACE"

trace_case() { # DESC TEXT CONTENT
	printf '%b' "$3" >"$T/trace.txt"
	bad_case "$1" "$2" forward.delay_ticks=0 "forward.trace=$T/trace.txt"
}
trace_case "a trace without header" "trace.txt:2: '40': expected the header delay_ticks or delay_s" '# c\n40\n'
trace_case "a delay out of range" "trace.txt:4: '100001': expected a delay in ticks, a whole number; allowed [0, 100000]" \
	'delay_ticks\n40\n\n100001\n'
trace_case "a negative delay" "trace.txt:3: '-1'" 'delay_ticks\n40\n-1\n'
trace_case "a fraction of a tick" "trace.txt:2: '2.5'" 'delay_ticks\n2.5\n'
trace_case "seconds not whole ticks" "trace.txt:3: delay_s 0.0015 s is 1.5 ticks" 'delay_s\n0.04\n0.0015\n'
trace_case "a trace of no delay" "trace.txt: no delays after the header" '# nothing\ndelay_s\n\n'
trace_case "an empty trace" "trace.txt: no header" ''
bad_case "a missing trace" "nosuch.txt: cannot open delay trace" forward.delay_ticks=0 "forward.trace=$T/nosuch.txt"

# a trace: its delays in use, its digest in the header; found by name in traces/
expect_exit 0 "the shipped trace forward" "$POPC" run "$WALL" -q --set run.duration=2 --set forward.delay_ticks=0 \
	--set "forward.trace=$TRACE" --log "$T/trace.csv" --channel-log "$T/trace-ch.csv"
check "  the digest in the header" grep -qE '^# forward_trace = fnv1a-[0-9a-f]{16} \(1000 delays\)$' "$T/trace.csv"
check "  the path in the resolved scene" grep -qx "# trace = $TRACE" "$T/trace.csv"
check "  packet k took trace line k mod 1000 (sent 650: 80, 1650: 80, 10: 41)" sh -c "awk -F, '\$2 == \"forward\" && \$4 == \"sent\" && ((\$3 == 650 || \$3 == 1650) && \$5 == 80 || \$3 == 10 && \$5 == 41) {n++} END {exit n != 3}' '$T/trace-ch.csv'"
mkdir -p "$T/scenes"
printf '[teleop]\narchitecture = position-force\n[forward]\ntrace = wifi-burst.txt\n' >"$T/scenes/by-name.ini"
expect_exit 0 "a trace named in a scene, found in the data directory" \
	env POPC_DATA_PATH="$SRC/data" "$POPC" scene show "$T/scenes/by-name.ini"
check "  resolved to the shipped file" grep -qx "trace = $(realpath "$TRACE")" "$T/out"
printf 'delay_ticks\n7\n' >"$T/scenes/wifi-burst.txt"
expect_exit 0 "  a local file of that name wins" env POPC_DATA_PATH="$SRC/data" "$POPC" scene show "$T/scenes/by-name.ini"
check "  the local file" grep -qx "trace = $T/scenes/wifi-burst.txt" "$T/out"

# the channel log: per direction sent = delivered + stale + lost + in flight,
# sent once a tick, lost at the main log's lost flags, delivered at its fresh flags
lossy=(--set run.duration=3 --set forward.jitter_ticks=30 --set forward.in_order=off --set forward.loss=0.2
	--set backward.jitter_ticks=10 --set backward.jitter_model=walk --set backward.loss=0.1)
expect_exit 0 "a lossy reordering channel with --channel-log" "$POPC" run "$WALL" -q "${lossy[@]}" \
	--log "$T/main.csv" --channel-log "$T/ch.csv"
check "  the header and the columns" sh -c "head -1 '$T/ch.csv' | grep -qx '# popc channel log' && grep -qx 'tick,direction,seq,event,delay_ticks' '$T/ch.csv'"
ticks=$(rows "$T/main.csv" | tail -n +2 | wc -l)
for d in forward:16:64 backward:32:128; do
	name=${d%%:*} lostbit=$(echo "$d" | cut -d: -f2) freshbit=${d##*:}
	counts=$(awk -F, -v d="$name" '$2 == d {n[$4]++} END {printf "%d %d %d %d", n["sent"], n["delivered"], n["stale"], n["lost"]}' "$T/ch.csv")
	read -r sent delivered stale lost <<<"$counts"
	inflight=$(sed -n "s/^# ${name}_in_flight = //p" "$T/ch.csv")
	check "  $name: sent $sent = delivered $delivered + stale $stale + lost $lost + in flight $inflight" \
		test "$sent" -eq $((delivered + stale + lost + inflight))
	check "  $name: one packet sent a tick ($ticks rows)" test "$sent" -eq "$ticks"
	flag_lost=$(rows "$T/main.csv" | awk -F, -v b="$lostbit" 'NR > 1 && int($11 / b) % 2 {n++} END {print n + 0}')
	check "  $name: lost $lost = ticks flagged lost $flag_lost" test "$lost" -eq "$flag_lost"
	fresh_ticks=$(awk -F, -v d="$name" '$2 == d && $4 == "delivered" {t[$1] = 1} END {print length(t)}' "$T/ch.csv")
	flag_fresh=$(rows "$T/main.csv" | awk -F, -v b="$freshbit" 'NR > 1 && int($11 / b) % 2 {n++} END {print n + 0}')
	check "  $name: ticks with a delivery $fresh_ticks = ticks flagged fresh $flag_fresh" test "$fresh_ticks" -eq "$flag_fresh"
done
check "  forward reorders: some packets stale" sh -c "awk -F, '\$2 == \"forward\" && \$4 == \"stale\" {n++} END {exit !n}' '$T/ch.csv'"
check "  backward's walk: consecutive packets' delays 1 tick apart at most, within [100, 110]" sh -c "awk -F, '\$2 == \"backward\" && \$4 == \"sent\" && \$5 >= 0 {if (\$5 < 100 || \$5 > 110) bad = 1; if (p != \"\" && (\$5 - p > 1 || p - \$5 > 1) && \$3 == q + 1) bad = 1; p = \$5; q = \$3} END {exit bad}' '$T/ch.csv'"
expect_exit 0 "  again" "$POPC" run "$WALL" -q "${lossy[@]}" --channel-log "$T/ch2.csv"
check "  the same events (the same seeds)" cmp -s <(rows "$T/ch.csv") <(rows "$T/ch2.csv")
expect_exit 0 "the direct link's channel log" "$POPC" run "$WALL" -q --set run.duration=0.5 --set teleop.link=direct --channel-log "$T/direct.csv"
check "  each packet sent and delivered at once" sh -c "awk -F, '!/^#/ && NR > 1 && \$1 != \"tick\" {n[\$4]++; if (\$5 != 0) bad = 1} END {exit bad || n[\"sent\"] != 1002 || n[\"delivered\"] != 1002}' '$T/direct.csv'"

# --channel-log refused where it cannot be: exit 2, nothing written
expect_exit 2 "--channel-log on a one-port scene" "$POPC" run "$SRC/data/scenes/paper.ini" --channel-log "$T/one.csv"
check "  says why" err_has "only for a teleoperation scene"
check "  nothing written" test ! -e "$T/one.csv"
expect_exit 2 "--channel-log onto --log" "$POPC" run "$WALL" --log "$T/same.csv" --channel-log "$T/same.csv"
check "  says so" err_has "are the same file"
cp "$TRACE" "$T/in.txt"
expect_exit 2 "--channel-log onto the trace" "$POPC" run "$WALL" --set forward.delay_ticks=0 --set "forward.trace=$T/in.txt" --channel-log "$T/in.txt"
check "  the trace kept" cmp -s "$TRACE" "$T/in.txt"

# each side its own rate: the slave's local loop N times a tick
expect_exit 0 "slave.rate = run.rate" "$POPC" run "$WALL" -q --set run.duration=2 --set slave.rate=1000 --log "$T/rate1.csv"
check "  today's rows, bit for bit" cmp -s <(rows "$T/ticks.csv") <(rows "$T/rate1.csv")
check "  slave.rate written, under [slave]" sh -c "grep -A8 -x '# \[slave\]' '$T/rate1.csv' | grep -qx '# rate = 1000'"
for n in 4 10; do
	expect_exit 0 "slave.rate = $n x run.rate, 200 ms round trip" "$POPC" run "$WALL" -q --set run.duration=2 \
		--set slave.rate=${n}000 --log "$T/rate$n.csv"
	check "  other rows (the slave steps T / $n)" bash -c "! cmp -s <(grep -v '^#' '$T/ticks.csv') <(grep -v '^#' '$T/rate$n.csv')"
	expect_exit 0 "  energy --check: both ports bit for bit, the two-port condition" "$ANALYZE" energy --check "$T/rate$n.csv"
	check "  no row differing, the condition never broken" grep -q "rows differing 0  two-port condition broken on 0 rows" "$T/out"
done
bad_case "a slave rate no whole multiple" "slave.rate = 1500 Hz is not a whole multiple of run.rate = 1000 Hz; allowed 0 (run.rate) or N x run.rate with N whole, 1 to 1000" slave.rate=1500
bad_case "a slave slower than the master" "slave.rate = 500 Hz is not a whole multiple" slave.rate=500
check_summary
