#!/bin/sh
# Fuzz popc's input parsers with libFuzzer (clang's -fsanitize=fuzzer, with
# ASan and UBSan). Every build replays the checked-in corpus through the same
# harnesses (tests/fuzz/meson.build, test 'fuzz_replay', no clang needed); CI
# also fuzzes a few seconds per harness through this script (test 'libfuzzer',
# suites fuzz and slow, in a build without sanitizers).
#
#   tests/fuzz/run-fuzz.sh [SECONDS] [HARNESS...]
#
# SECONDS per harness (default 300), on one core each, one after another.
# HARNESS: one of fuzz_harnesses in tests/fuzz/meson.build (numfmt_parse
# numfmt_format log_reader analyze_input scene ini_lines intent sweep_dir map register_map
# modbus_uri; default: all). Needs Debian's clang (apt-get install clang:
# libFuzzer ships in its compiler-rt, libclang-rt-14-dev on Debian 12's
# clang-14 packaging) and the build deps. Exits 0 when every harness ran
# without a failure, 1 when one failed (its artifacts are kept), 2 on a
# bad argument or a failed build, 77 when clang or its libFuzzer is missing
# (meson's "skipped").
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
command -v "$CC" >/dev/null || { echo "run-fuzz.sh: skipped: $CC not found (apt-get install clang)"; exit 77; }
# libFuzzer is a part of clang's runtime that a distribution may split off:
# a program that links with -fsanitize=fuzzer says whether it is here
probe=$(mktemp -d "${TMPDIR:-/tmp}/popc-fuzz-probe.XXXXXX")
printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n);\nint LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { return (int)(d && n > 99); }\n' \
	>"$probe/probe.c"
if ! "$CC" -fsanitize=fuzzer,address,undefined "$probe/probe.c" -o "$probe/probe" >"$probe/log" 2>&1; then
	echo "run-fuzz.sh: skipped: $CC cannot link -fsanitize=fuzzer (libFuzzer missing; Debian: libclang-rt-dev or clang's compiler-rt):"
	cat "$probe/log"
	rm -rf "$probe"
	exit 77
fi
rm -rf "$probe"

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

failed=""
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
		"$work/corpus/$h" "$here/corpus/$h" || { echo "== $h: FAILED (see $work/artifacts)"; failed="$failed $h"; }
done
if [ -n "$failed" ]; then
	echo "run-fuzz.sh: failed:$failed (reproducers in $work/artifacts)"
	exit 1
fi
echo "run-fuzz.sh: every harness ran $seconds s without a failure"
