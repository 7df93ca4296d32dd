#!/bin/bash
# Benchmark, not a test: achieved control rate and period jitter of popc run on
# the Modbus axis against popc-servo-sim, over TCP loopback and over RTU on a
# socat pseudo-terminal pair, with and without pacing the pty at 115200 baud.
# Prints a Markdown table (docs/BENCHMARKS.md, section 7 holds a run of it).
#
#   POPC=build/src/popc POPC_SOURCE_ROOT=. \
#     bash tests/modbus/bench_modbus.sh build/src/servo_sim/popc-servo-sim [SECONDS]
. "$(dirname "$0")/lib.sh"
SECS=${2:-10}
MAP=$EXACT_MAP   # FC23, one transaction per tick (23-byte request, 13-byte reply on RTU:
                 # position, status and the sequence register read back)
# No wall: at rates the link cannot keep, the 1000 N/m wall behind a
# several-millisecond delay is unstable and the soft limits stop the run. The
# hand still follows the ramp, so the position moves.
FREE="environment.position=1"

# bench LABEL RATE_HZ CONNECT [popc options]: one run, one table row
bench() {
	local label=$1 rate=$2 connect=$3
	shift 3
	"$POPC" run "$SCENE" --set run.duration="$SECS" --set run.rate="$rate" --set $FREE --axis modbus \
		--map "$MAP" --connect "$connect" --log /dev/null "$@" 2>"$WORK/bench.err" ||
		{ cat "$WORK/bench.err" >&2; return; }
	awk -v label="$label" -v rate="$rate" '
		/ticks at/ { ticks = $(NF - 4) }
		/simulated .* wall/ { for (i = 1; i <= NF; i++) if ($i == "wall:") wall = $(i - 2) }
		/period dt:/ { for (i = 1; i <= NF; i++) { k = $i; v = $(i + 1); sub(/,$/, "", v); sub(/;$/, "", v); d[k] = v } ov = d["overruns"] }
		/latency rtt:/ { for (i = 1; i <= NF; i++) { k = $i; v = $(i + 1); sub(/,$/, "", v); r[k] = v } }
		END {
			printf "| %s | %s | %.1f | %s | %s | %s | %s | %s | %s | %s |\n", label, rate,
				ticks / wall, d["p50"], d["p99"], d["p99.9"], d["max"], ov, r["p50"], r["p99"]
		}' "$WORK/bench.err"
}

echo "| link | target Hz | achieved Hz | dt p50 ms | dt p99 ms | dt p99.9 ms | dt max ms | overruns | rtt p50 ms | rtt p99 ms |"
echo "|---|---|---|---|---|---|---|---|---|---|"

# serve ARGS...: a fresh server (the plant from its initial state) per run
serve() { start_server --map "$MAP" --scene "$SCENE" --set $FREE "$@"; }

serve --listen tcp:127.0.0.1:0
bench "TCP loopback, real-time server" 1000 "$SRV_URI"
stop_server
serve --listen tcp:127.0.0.1:0
bench "TCP loopback, real-time server, --rt" 1000 "$SRV_URI" --rt
stop_server
serve --listen tcp:127.0.0.1:0 --lockstep
bench "TCP loopback, lockstep server, --free-run" 1000 "$SRV_URI" --free-run
stop_server

start_socat
RTU_SRV="rtu:$WORK/pty-srv:115200:8N1" RTU_CLI="rtu:$WORK/pty-cli:115200:8N1"
serve --listen "$RTU_SRV"
bench "RTU pty at '115200' (a pty does not pace)" 1000 "$RTU_CLI"
stop_server
serve --listen "$RTU_SRV" --pace-baud
bench "RTU pty paced at 115200 baud by the server" 1000 "$RTU_CLI"
stop_server
serve --listen "$RTU_SRV" --pace-baud
bench "RTU pty paced at 115200 baud by the server" 100 "$RTU_CLI"
stop_server
stop_socat
finish
