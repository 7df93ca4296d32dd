# Shared helpers of the Modbus tests (sourced by bash scripts).
#
# Servers (popc-servo-sim, socat) start with a known pid, are waited for on
# their readiness line through a FIFO (read -t bounds the wait), and are
# stopped by pid. No sleep-based synchronisation, no killing by name.
#
# Environment: POPC (the popc program), POPC_SOURCE_ROOT; $1 of the test
# script is the popc-servo-sim program.

set -u

SIM=${SIM:-$1}
SCENE="$POPC_SOURCE_ROOT/data/scenes/paper.ini"
DRIVES="$POPC_SOURCE_ROOT/data/drives"
WORK=$(mktemp -d "${TMPDIR:-/tmp}/popc-modbus.XXXXXX")

# The response timeout of the maps the tests run with. A lockstep server
# answers in microseconds, but on a loaded machine a reply can wait for the
# scheduler: the worst lockstep round trip measured here was 67 ms (40 runs
# of 1.5 s, sanitized build, two CPU-bound processes and the sanitized suite
# beside it), and a real-time period of 100.8 ms was seen in CI. A reply
# later than the timeout is a failed transaction that popc retries, and
# every count the tests assert (failed transactions, retries, the ticks
# before a fault) would move. 500 ms is 7.5 times the worst measured round
# trip; with max_failures = 3 it stays within the maps' 2 s silence bound.
# What it costs: each dropped reply waits one timeout (RTU: one more to
# drain the line).
LINK_TIMEOUT_MS=500

# test_map MAP [OUT]: a copy of MAP (in $WORK, or OUT) with the response
# timeout LINK_TIMEOUT_MS and max_failures 3; prints its path.
test_map() {
	local out=${2:-$WORK/$(basename "$1" .ini)-test.ini}
	sed -e "s/^timeout_ms = [0-9]*/timeout_ms = $LINK_TIMEOUT_MS/" \
		-e 's/^max_failures = [0-9]*/max_failures = 3/' "$1" >"$out"
	grep -q "^timeout_ms = $LINK_TIMEOUT_MS" "$out" && grep -q '^max_failures = 3' "$out" ||
		{ echo "test_map: $1 has no timeout_ms or max_failures line" >&2; exit 1; }
	echo "$out"
}
EXACT_MAP="${EXACT_MAP:-$(test_map "$DRIVES/popc-exact.ini")}"
SRV_PID=
SOCAT_PID=
FAILS=0

cleanup() {
	[ -n "$SRV_PID" ] && kill -TERM "$SRV_PID" 2>/dev/null
	[ -n "$SOCAT_PID" ] && kill -TERM "$SOCAT_PID" 2>/dev/null
	wait 2>/dev/null
	rm -rf "$WORK"
}
trap cleanup EXIT

fail() {
	echo "FAIL: $*" >&2
	FAILS=$((FAILS + 1))
}

# start_server ARGS...: popc-servo-sim in the background; sets SRV_PID and
# SRV_URI from its readiness line "popc-servo-sim: listening on URI". Its
# stdout stays open on fd 3 (later lines: --notify-at).
start_server() {
	rm -f "$WORK/srv.fifo"
	mkfifo "$WORK/srv.fifo"
	"$SIM" "$@" >"$WORK/srv.fifo" 2>"$WORK/srv.err" &
	SRV_PID=$!
	exec 3<"$WORK/srv.fifo"
	local line
	if ! read -r -t 10 -u 3 line; then
		echo "popc-servo-sim did not get ready:" >&2
		cat "$WORK/srv.err" >&2
		exit 1
	fi
	SRV_URI=${line#popc-servo-sim: listening on }
	[ "$SRV_URI" != "$line" ] || { echo "unexpected readiness line: $line" >&2; exit 1; }
}

# stop_server: SIGTERM by pid, then its exit status must be 0.
stop_server() {
	kill -TERM "$SRV_PID"
	local rc=0
	wait "$SRV_PID" || rc=$?
	SRV_PID=
	exec 3<&-
	[ $rc -eq 0 ] || fail "popc-servo-sim exited with $rc: $(cat "$WORK/srv.err")"
}

# wait_server_exit: for a server that ends by itself (--exit-after).
wait_server_exit() {
	local rc=0
	wait "$SRV_PID" || rc=$?
	SRV_PID=
	exec 3<&-
	[ $rc -eq 0 ] || fail "popc-servo-sim exited with $rc"
}

# start_socat: a pseudo-terminal pair $WORK/pty-srv <-> $WORK/pty-cli.
start_socat() {
	rm -f "$WORK/socat.fifo"
	mkfifo "$WORK/socat.fifo"
	socat -d -d "pty,raw,echo=0,link=$WORK/pty-srv" "pty,raw,echo=0,link=$WORK/pty-cli" \
		2>"$WORK/socat.fifo" &
	SOCAT_PID=$!
	exec 4<"$WORK/socat.fifo"
	local line n=0
	while read -r -t 10 -u 4 line; do
		case $line in
		*"PTY is"*) n=$((n + 1)) ;;
		*"starting data transfer loop"*) break ;;
		esac
	done
	[ $n -eq 2 ] || { echo "socat did not make a pty pair" >&2; exit 77; }
	# keep draining socat's stderr so that it never blocks on a full pipe
	cat <&4 >/dev/null &
	exec 4<&-
}

stop_socat() {
	kill -TERM "$SOCAT_PID"
	wait "$SOCAT_PID" 2>/dev/null
	SOCAT_PID=
}

# cols LOG: the columns x, count, f_c, W, E_ref of a log's rows, found by name.
cols() {
	awk -F, '/^#/ { next }
		!h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
		{ print $c["x"], $c["count"], $c["f_c"], $c["W"], $c["E_ref"] }' "$1"
}

# adm_cols LOG NAMES...: the named columns of a log's rows
adm_cols() {
	local log=$1
	shift
	awk -F, -v want="$*" '/^#/ { next }
		!h { for (i = 1; i <= NF; i++) c[$i] = i; n = split(want, w, " ")
		     for (j = 1; j <= n; j++) if (!c[w[j]]) { print "no column " w[j]; exit 1 }
		     h = 1; next }
		{ s = ""; for (j = 1; j <= n; j++) s = s (j > 1 ? "," : "") $c[w[j]]; print s }' "$log"
}

# rows LOG: number of data rows.
rows() {
	awk -F, '/^#/ { next } !h { h = 1; next } { n++ } END { print n + 0 }' "$1"
}

# check_log LOG REASON_PATTERN: the log ends with "# stop = ..." matching the
# pattern, and holds every completed tick: rows t = 0, T, 2T, ... without gap.
check_log() {
	local log=$1 pat=$2
	local last
	last=$(tail -n 1 "$log")
	case $last in
	"# stop = "*) ;;
	*) fail "$log: last line is not '# stop = ...': $last"; return ;;
	esac
	echo "$last" | grep -Eq "$pat" || fail "$log: stop line '$last' does not match /$pat/"
	awk -F, -v T=0.001 '/^#/ { next } !h { h = 1; next }
		{ if ($1 - n * T > 1e-9 || n * T - $1 > 1e-9) bad = 1; n++ }
		END { exit bad }' "$log" || fail "$log: ticks missing or out of order"
}

# check_last_writes RECORD OFFWORD: the server's last two writes were zero
# force, then the disable word. The record gives a command's register words
# after the force ("command 0 [0000 0000 0000 0000]"): a zero force is
# all-zero words in every register type (+0.0 for a float, never -0.0).
check_last_writes() {
	local rec=$1 off=$2
	local got
	got=$(tail -n 2 "$rec" | tr '\n' '|')
	[[ $got =~ ^command\ 0\ \[0000(\ 0000)*\]\|enable\ $off\|$ ]] ||
		fail "last writes seen by the server: '$got', want 'command 0 [0000 ...]|enable $off|'"
}

# expect_rc NAME GOT WANT
expect_rc() {
	[ "$2" -eq "$3" ] || fail "$1: exit status $2, want $3 (see $WORK)"
}

finish() {
	if [ $FAILS -ne 0 ]; then
		echo "$FAILS check(s) failed" >&2
		trap - EXIT
		[ -n "$SRV_PID" ] && kill -TERM "$SRV_PID" 2>/dev/null
		[ -n "$SOCAT_PID" ] && kill -TERM "$SOCAT_PID" 2>/dev/null
		echo "work files kept in $WORK" >&2
		exit 1
	fi
	exit 0
}
