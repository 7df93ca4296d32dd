#!/usr/bin/env bash
# Real readers read popc logs right (docs/READING.md): every row, every
# column named and typed (floating point, count and flags integers), every
# cell bit for bit against the log's text and popc-analyze's values.
#
#   readers.sh pandas|duckdb|gnuplot [SERVO_SIM]   (POPC, POPC_ANALYZE, POPC_SOURCE_ROOT,
#                                           POPC_BUILD_ROOT from the environment)
#
# Logs of every source: sim (the paper scene, improved), modbus (the same
# through popc-servo-sim in lockstep, when SERVO_SIM is given), replay
# (popc-analyze replay of the sim log, hold), and a 60 s run whose forces are
# zero for its first 30 s (contact at 30.2 s): DuckDB samples the first 20480
# rows to type a column, and cells written "0" typed f_pc, W and f_e as BIGINT.
#
# gnuplot (Debian's gnuplot-nox) is checked by its stats command on every
# column, by name: the record count, minimum and maximum (printed with 17
# digits) equal the log's, bit for bit.
# pandas is Debian's python3-pandas. DuckDB is the npm package pinned in
# package.json / package-lock.json, installed here with `npm ci` into the
# build directory; exit 77 (skip), saying why, when node or npm is missing or
# the npm registry cannot be reached.
set -u
READER=${1:?pandas or duckdb}
SIM=${2:-}
POPC=${POPC:?}
ANALYZE=${POPC_ANALYZE:?}
SRC=${POPC_SOURCE_ROOT:?}
HERE=$SRC/tests/readers
W=$(mktemp -d "${TMPDIR:-/tmp}/popc-readers.XXXXXX")
SRV_PID=
cleanup() {
	[ -n "$SRV_PID" ] && kill -TERM "$SRV_PID" 2>/dev/null && wait "$SRV_PID" 2>/dev/null
	rm -rf "$W"
}
trap cleanup EXIT
die() { echo "FAIL: $*" >&2; exit 1; }
skip() { echo "SKIP: $*" >&2; exit 77; }

case $READER in
pandas)
	# Debian's python3 (another python3 first in PATH, e.g. pyenv's, may lack it)
	PY=
	for p in python3 /usr/bin/python3; do
		"$p" -c 'import pandas' 2>/dev/null && { PY=$p; break; }
	done
	[ -n "$PY" ] ||
		skip "no python3 imports pandas (Debian: apt-get install python3-pandas; tools/install-deps.sh test)" ;;
duckdb)
	command -v node >/dev/null && command -v npm >/dev/null ||
		skip "node or npm missing (Debian: apt-get install nodejs npm; tools/install-deps.sh test)"
	# the pinned package, once per lock file, in the build directory
	NPM=${POPC_BUILD_ROOT:?}/tests/readers-npm
	if ! cmp -s "$HERE/package-lock.json" "$NPM/package-lock.json" ||
		[ ! -d "$NPM/node_modules/@duckdb/node-api" ]; then
		rm -rf "$NPM" && mkdir -p "$NPM" || die "cannot make $NPM"
		cp "$HERE/package.json" "$HERE/package-lock.json" "$NPM/"
		if ! (cd "$NPM" && timeout 300 npm ci --no-audit --no-fund --loglevel=error) >"$W/npm.log" 2>&1; then
			# unreachable registry, or one this machine cannot trust (a
			# TLS-intercepting proxy whose CA a fresh root lacks: seen in
			# tools/check-fresh-root.sh's root): skip; any other npm
			# failure: fail
			if grep -qiE 'ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ECONNRESET|ETIMEDOUT|ENETUNREACH|network|proxy|SELF_SIGNED_CERT|UNABLE_TO_GET_ISSUER_CERT|UNABLE_TO_VERIFY_LEAF_SIGNATURE|CERT_UNTRUSTED' "$W/npm.log"; then
				rm -rf "$NPM"
				skip "the npm registry is unreachable, DuckDB's package not installed: $(grep -m1 -iE 'err' "$W/npm.log")"
			fi
			cat "$W/npm.log" >&2
			rm -rf "$NPM"
			die "npm ci of tests/readers/package-lock.json failed"
		fi
	fi
	cp "$HERE/read_duckdb.mjs" "$NPM/" ;; # node finds node_modules beside the script
gnuplot)
	command -v gnuplot >/dev/null || skip "gnuplot missing (Debian: apt-get install gnuplot-nox)" ;;
*) die "unknown reader $READER" ;;
esac

export POPC_DATA_PATH=$SRC/data
SCENE=$SRC/data/scenes/paper.ini
logs=()
"$POPC" run "$SCENE" -q --variant improved --log "$W/sim.csv" || die "sim run failed"
logs+=("$W/sim.csv")
"$POPC" run "$SCENE" -q --set run.duration=60 --set operator.t0=30 --log "$W/late-contact.csv" ||
	die "60 s run failed"
logs+=("$W/late-contact.csv")
"$ANALYZE" replay "$W/sim.csv" --variant hold -o "$W" -q || die "replay failed"
logs+=("$W/sim.hold.csv")
if [ -n "$SIM" ]; then
	# a lockstep server answers every tick at once: the modbus log's rows
	# (with dt and rtt) without waiting for a real period
	sed -e 's/^timeout_ms = [0-9]*/timeout_ms = 500/' "$SRC/data/drives/popc-exact.ini" >"$W/map.ini"
	mkfifo "$W/srv.fifo"
	"$SIM" --map "$W/map.ini" --listen tcp:127.0.0.1:0 --scene "$SCENE" --lockstep \
		>"$W/srv.fifo" 2>"$W/srv.err" &
	SRV_PID=$!
	exec 3<"$W/srv.fifo"
	read -r -t 10 -u 3 line || die "popc-servo-sim did not get ready: $(cat "$W/srv.err")"
	uri=${line#popc-servo-sim: listening on }
	"$POPC" run "$SCENE" -q --set run.duration=1.5 --axis modbus --map "$W/map.ini" \
		--connect "$uri" --free-run --log "$W/modbus.csv" || die "modbus run failed"
	kill -TERM "$SRV_PID"; wait "$SRV_PID"; SRV_PID=
	exec 3<&-
	grep -q '^# source = modbus' "$W/modbus.csv" || die "modbus.csv: source is not modbus"
	logs+=("$W/modbus.csv")
fi

# the logs mean something: contact and PC force in each, none before 30 s in
# the long one, dt and rtt in the modbus one, source = replay in the replay
for log in "${logs[@]}"; do
	awk -F, '/^#/ { next } !h { for (i = 1; i <= NF; i++) c[$i] = i; h = 1; next }
		$c["f_pc"] != 0 { pc = 1; if ($c["t"] < first || !seen) first = $c["t"]; seen = 1 }
		END { print (pc ? first : -1) }' "$log" >"$W/first"
	first=$(cat "$W/first")
	[ "$first" != -1 ] || die "$log: no PC force in any row"
	case $log in *late-contact.csv)
		awk -v f="$first" 'BEGIN { exit !(f >= 30) }' || die "$log: PC force at $first s, before 30 s" ;;
	esac
done
grep -q '^# source = replay' "$W/sim.hold.csv" || die "sim.hold.csv: source is not replay"
[ -z "$SIM" ] || head -c 100000 "$W/modbus.csv" | grep -q '^t,.*,dt,rtt$' || die "modbus.csv has no dt, rtt columns"

pairs=()
for log in "${logs[@]}"; do
	"$ANALYZE" energy "$log" -o "$log.energy.csv" --check >/dev/null || die "$log: popc-analyze energy --check"
	pairs+=("$log" "$log.energy.csv")
done
status=0
if [ "$READER" = pandas ]; then
	PYTHONPATH=$HERE "$PY" "$HERE/read_pandas.py" "${pairs[@]}" || status=1
elif [ "$READER" = gnuplot ]; then
	for log in "${logs[@]}"; do
		names=$(grep -v '^#' "$log" | head -n 1)
		{
			echo "set datafile separator ','"
			for c in ${names//,/ }; do
				echo "stats '$log' using '$c' nooutput"
				echo "print sprintf('$c %d %.17g %.17g', STATS_records, STATS_min, STATS_max)"
			done
		} >"$W/stats.gp"
		gnuplot "$W/stats.gp" >"$W/stats.txt" 2>&1 || { cat "$W/stats.txt" >&2; die "$log: gnuplot failed"; }
		python3 - "$log" "$W/stats.txt" <<'PY' || status=1
import struct, sys
log, stats = sys.argv[1:3]
lines = [l.rstrip("\n") for l in open(log) if not l.startswith("#")]
header, rows = lines[0].split(","), [l.split(",") for l in lines[1:]]
bits = lambda v: struct.pack("<d", v)
fails = 0
got = {l.split()[0]: l.split()[1:] for l in open(stats)}
for j, name in enumerate(header):
    col = [float(r[j]) for r in rows]
    want = [str(len(col)), min(col), max(col)]
    g = got.get(name)
    if not g or g[0] != want[0] or bits(float(g[1])) != bits(want[1]) or bits(float(g[2])) != bits(want[2]):
        print(f"FAIL: gnuplot: {log}: column {name}: records, min, max {g}, want {want[0]} {want[1]!r} {want[2]!r}")
        fails += 1
if not fails:
    print(f"gnuplot: {log}: {len(header)} columns by name, {len(rows)} records, minima and maxima bit for bit")
sys.exit(1 if fails else 0)
PY
	done
else
	for log in "${logs[@]}"; do
		node "$NPM/read_duckdb.mjs" "$log" "$log.json" || die "$log: DuckDB read failed"
		python3 "$HERE/check_cells.py" "$log" "$log.energy.csv" "$log.json" || status=1
	done
fi
[ $status -eq 0 ] && echo "$READER: ${#logs[@]} logs read right"
exit $status
