#!/bin/sh
# Fuzz popc's input parsers with libFuzzer (clang's -fsanitize=fuzzer, with
# ASan and UBSan). Not run by CI: CI replays the checked-in corpus through the
# same harnesses (tests/fuzz/meson.build, test 'fuzz_replay', no clang needed).
#
#   tests/fuzz/run-fuzz.sh [SECONDS] [HARNESS...]
#
# SECONDS per harness (default 300), on one core each, one after another.
# HARNESS: numfmt_parse numfmt_format log_reader scene ini_lines intent
# register_map modbus_uri (default: all). Needs Debian's clang (apt-get
# install clang: libFuzzer ships in its compiler-rt) and the build deps.
#
# Work goes to $POPC_FUZZ_WORK (default /tmp/popc-fuzz): the binaries, a
# growing corpus per harness (seeded from tests/fuzz/corpus, the shipped
# scenes and drive maps) and, on a failure, artifacts/HARNESS-crash-*: replay
# one with the fuzz binary or with the normal build's
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
seconds=${1:-300}
[ $# -gt 0 ] && shift
all="numfmt_parse numfmt_format log_reader scene ini_lines intent register_map modbus_uri"
harnesses=${*:-$all}
CC=${CC:-clang}
command -v "$CC" >/dev/null || { echo "run-fuzz.sh: $CC not found (apt-get install clang)" >&2; exit 2; }

mkdir -p "$work/obj" "$work/artifacts"
# popc_config.h as meson writes it (log_writer.c includes it)
printf '#define POPC_VERSION "fuzz"\n#define POPC_DATADIR "/nonexistent"\n' >"$work/popc_config.h"
flags="-g -O1 -std=c11 -D_POSIX_C_SOURCE=200809L -fno-math-errno -fsanitize=address,undefined \
-fno-sanitize-recover=undefined -fno-omit-frame-pointer -I$root/include -I$work -DPOPC_FUZZ_MODBUS \
$(pkg-config --cflags libmodbus inih)"
libs="$(pkg-config --libs libmodbus inih) -lm -lpthread"

# the library's sources (every layer under src/ but the programs, with the
# Modbus family: not its stand-in for builds without libmodbus), instrumented for coverage
srcs=$(cd "$root/src" && find . -name '*.c' -not -path './cli/*' -not -path './servo_sim/*' \
	-not -name modbus_absent.c | sort)
objs=""
for s in $srcs; do
	o="$work/obj/$(basename "${s%.c}").o"
	# shellcheck disable=SC2086
	$CC $flags -fsanitize=fuzzer-no-link -c "$root/src/$s" -o "$o"
	objs="$objs $o"
done
for f in fuzz_common fuzz_numfmt fuzz_log_reader fuzz_ini fuzz_intent fuzz_modbus_uri; do
	# shellcheck disable=SC2086
	$CC $flags -fsanitize=fuzzer-no-link -c "$here/$f.c" -o "$work/obj/$f.o"
	objs="$objs $work/obj/$f.o"
done

for h in $harnesses; do
	# shellcheck disable=SC2086
	$CC $flags -fsanitize=fuzzer -DPOPC_FUZZ_TARGET="popc_fuzz_$h" "$here/libfuzzer_entry.c" \
		$objs $libs -o "$work/fuzz_$h"
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
