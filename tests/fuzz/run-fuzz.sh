#!/bin/sh
# Fuzz popc's input parsers with libFuzzer (clang's -fsanitize=fuzzer, with
# ASan and UBSan). Not run by CI: CI replays the checked-in corpus through the
# same harnesses (tests/fuzz/meson.build, test 'fuzz_replay', no clang needed).
#
#   tests/fuzz/run-fuzz.sh [SECONDS] [HARNESS...]
#
# SECONDS per harness (default 300), on one core each, one after another.
# HARNESS: one of fuzz_harnesses in tests/fuzz/meson.build (numfmt_parse
# numfmt_format log_reader scene ini_lines intent map register_map modbus_uri;
# default: all). Needs Debian's clang (apt-get install clang: libFuzzer ships
# in its compiler-rt) and the build deps.
#
# The harnesses are built by Meson: a build directory $POPC_FUZZ_WORK/build
# (default /tmp/popc-fuzz/build) configured with -Dfuzzing=libfuzzer (every
# object instrumented for coverage, meson_options.txt), ASan and UBSan
# stopping at the first report, -O1 -g; ninja rebuilds what changed on every
# run. Work goes to $POPC_FUZZ_WORK: fuzz_HARNESS (a link to the build's
# tests/fuzz/fuzz_HARNESS), a growing corpus per harness (seeded from
# tests/fuzz/corpus, the shipped scenes and drive maps) and, on a failure,
# artifacts/HARNESS-crash-*: replay one with the fuzz binary or with the
# normal build's
#   build/tests/fuzz/fuzz_replay HARNESS FILE
# Fix it, then add the (minimized: fuzz_HARNESS -minimize_crash=1 FILE) input
# to tests/fuzz/corpus/HARNESS/. To refresh the checked-in corpus with the
# inputs that add coverage, keeping it small:
#   $POPC_FUZZ_WORK/fuzz_HARNESS -merge=1 NEWDIR tests/fuzz/corpus/HARNESS $POPC_FUZZ_WORK/corpus/HARNESS
# and copy NEWDIR's new files in. The corpus stays at a few hundred KB: for
# log_reader only the merged inputs up to 1 KB were kept (coverage 499 of 500).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=${POPC_FUZZ_WORK:-/tmp/popc-fuzz}
build=$work/build
seconds=${1:-300}
[ $# -gt 0 ] && shift
CC=${CC:-clang}
command -v "$CC" >/dev/null || { echo "run-fuzz.sh: $CC not found (apt-get install clang)" >&2; exit 2; }

# a build directory configured from another source tree (another checkout
# sharing $POPC_FUZZ_WORK) would fuzz that tree's code: start it afresh
if [ -f "$build/meson-info/meson-info.json" ]; then
	configured=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["directories"]["source"])' \
		"$build/meson-info/meson-info.json")
	[ "$configured" = "$root" ] || rm -rf "$build"
fi
mkdir -p "$work/artifacts"
if [ ! -f "$build/build.ninja" ]; then
	CC=$CC meson setup "$build" "$root" -Dfuzzing=libfuzzer -Db_sanitize=address,undefined \
		-Db_lundef=false -Doptimization=1 -Ddebug=true \
		-Dc_args='-fno-sanitize-recover=undefined -fno-omit-frame-pointer' >"$work/setup.log" 2>&1 ||
		{ cat "$work/setup.log" >&2; exit 2; }
fi

# the harnesses meson.build declares (executables fuzz_*, but the corpus replay)
all=$(meson introspect --targets "$build" | python3 -c '
import json, sys
names = sorted(t["name"] for t in json.load(sys.stdin) if t["type"] == "executable")
print(" ".join(n[len("fuzz_"):] for n in names if n.startswith("fuzz_") and n != "fuzz_replay"))')
harnesses=${*:-$all}
targets=""
for h in $harnesses; do
	case " $all " in
	*" $h "*) targets="$targets tests/fuzz/fuzz_$h" ;;
	*) echo "run-fuzz.sh: no harness '$h' (harnesses: $all)" >&2; exit 2 ;;
	esac
done
# shellcheck disable=SC2086
ninja -C "$build" $targets

for h in $harnesses; do
	ln -sf "$build/tests/fuzz/fuzz_$h" "$work/fuzz_$h"
	mkdir -p "$work/corpus/$h"
	case $h in
	scene) cp "$root"/data/scenes/*.ini "$work/corpus/$h/" ;;
	register_map) cp "$root"/data/drives/*.ini "$work/corpus/$h/" ;;
	esac
	dict=""
	[ -f "$here/dict/$h.dict" ] && dict="-dict=$here/dict/$h.dict"
	echo "== $h: $seconds s"
	# -timeout: one input taking 10 s is a hang; -rss_limit_mb: a leak or a
	# runaway allocation; the checked-in corpus is read, never written
	# shellcheck disable=SC2086
	"$work/fuzz_$h" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
		-print_final_stats=1 $dict -artifact_prefix="$work/artifacts/$h-" \
		"$work/corpus/$h" "$here/corpus/$h" || echo "== $h: FAILED (see $work/artifacts)"
done
