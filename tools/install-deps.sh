#!/usr/bin/env bash
# Installs the Debian 12 packages of one or more sets, those that are missing.
# Needs root (or sudo) only when something is missing.
#
#   tools/install-deps.sh paper        what tools/paper.sh needs (Quick start
#                                      command 1): build popc, draw the report.
#                                      No package that installs a service.
#   tools/install-deps.sh [test]       what tools/run-tests.sh and .ci/run need
#                                      (command 2): the paper set and the test
#                                      tools; the default.
#   tools/install-deps.sh --list SET   print the set's packages, one a line.
#
# Packages are installed without their recommends, so every package a step
# needs is named here: on a minimal root (debootstrap --variant=minbase) gcc
# without recommends brings no libc6-dev, and then meson says "Compiler cc can
# not compile programs". tools/check-fresh-root.sh installs both sets into such
# a root and checks that the paper set starts and enables no service.
set -euo pipefail

# build popc (meson.build: a C compiler with the C library's headers, inih,
# libmodbus, threads and libm from libc6-dev; and cmocka, because meson setup
# configures tests/ always and tests/meson.build requires it) and draw the
# report (gnuplot's pngcairo/pdfcairo terminals are in gnuplot-nox)
paper=(gcc libc6-dev meson ninja-build pkg-config libinih-dev libmodbus-dev libcmocka-dev gnuplot-nox)
# the tests: socat (RTU over a pty pair), GNU parallel
# (sweep-parallel; it depends on sysstat, a service), Slurm and munge (the
# single-node cluster of sweep-slurm; services), python3 (run-tests.sh's
# tally) and clang (the second compiler), scdoc (the man pages; without it
# the build skips them, -Dman=auto) and man-db (tests/cli/test_install.sh
# reads the installed pages with man). Not gawk: the tests run with
# Debian's default awk, mawk (under gawk realtime.sh's field loop never ends).
# python3-pandas and nodejs with npm: tests/readers reads logs with real
# pandas and with DuckDB's npm package (which the test installs itself with
# `npm ci` from tests/readers/package-lock.json; it skips when the registry
# is unreachable). npm only where no npm is there: NodeSource's nodejs
# bundles its own, and Debian's npm package cannot be installed beside it.
# bash-completion: on most Debian installs (priority standard); its
# pkg-config file once made `meson install --prefix=SCRATCH` write into
# /usr/share (tests/cli/test_install.sh checks every file lands under the
# prefix), so the tests run with it installed.
# libmatio-dev: popc-analyze's MAT input and tests/analyze/test_mat.sh (which
# writes its MAT files with it; -Dmatio=auto builds without it, the test then
# skips); not in the paper set: command 1 reads no MAT file. zlib1g-dev:
# analysis/read_mat_check.c inflates a MAT v5 file's compressed variables to
# check their headers before libmatio reads them (libmatio-dev depends on it).
# g++ and libfast-float-dev: bench/fastfloat_reader, the reference reader of
# docs/BENCHMARKS.md section 3 (built by every build where they are found);
# g++ also compiles popc/popc.h as C++ (test lib-cxx).
# libclang-rt-dev: clang's runtime with libFuzzer (only recommended by clang,
# so not installed here without it): the test 'libfuzzer' fuzzes each harness
# of tests/fuzz for a few seconds (it skips, exit 77, without it).
# python3-numpy: the popc Python module (python/popc, docs/LIBRARY.md) and
# its tests (lib-python, install); python3-pandas depends on it, named here
# because the module needs it on its own. It is also a reader of
# docs/READING.md (test recipes_numpy).
# octave, r-base-core, r-cran-data.table, r-cran-readr, jq: the other readers
# of docs/READING.md, whose recipes tests/readers/recipes.sh runs as written
# (recipes_octave, _r, _datatable, _readr, _jq; each skips without its reader).
# python3-numba: bench/tick_jit.py, the JIT reference of the tick (issue 23):
# the test tick-jit checks its end values against popc run's bit for bit
# (without numba it checks the same Python plain and skips, exit 77), and
# bench/tick_vs_jit.sh times popc's tick beside it (docs/BENCHMARKS.md).
test=("${paper[@]}" socat parallel slurm-wlm munge python3 clang libclang-rt-dev scdoc man-db python3-numpy python3-numba python3-pandas nodejs g++ libfast-float-dev bash-completion libmatio-dev octave r-base-core r-cran-data.table r-cran-readr jq zlib1g-dev)
command -v npm >/dev/null 2>&1 || test+=(npm)

usage() { echo "usage: tools/install-deps.sh [--list] [paper|test]..." >&2; exit 2; }
list=
sets=()
for a in "$@"; do
  case $a in
    --list) list=1 ;;
    paper|test) sets+=("$a") ;;
    -h|--help) sed -n '2,17s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) usage ;;
  esac
done
[ ${#sets[@]} -gt 0 ] || sets=(test)
pkgs=()
for s in "${sets[@]}"; do
  case $s in
    paper) pkgs+=("${paper[@]}") ;;
    test) pkgs+=("${test[@]}") ;;
  esac
done
if [ -n "$list" ]; then printf '%s\n' "${pkgs[@]}" | awk '!seen[$0]++'; exit 0; fi

missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "popc: installing (${sets[*]}): ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
log=$(mktemp "${TMPDIR:-/tmp}/popc-install-deps.XXXXXX")
trap 'rm -f "$log"' EXIT
# quiet when it works; the whole output when it does not
run() {
  "$@" </dev/null >"$log" 2>&1 && return 0
  local rc=$?
  cat "$log" >&2
  echo "popc: install-deps: '$*' failed (exit $rc)" >&2
  exit 1
}
# another apt (an unattended upgrade, a second install-deps) may hold dpkg's
# lock: wait for it (up to 10 minutes) instead of failing at once
lock=(-o DPkg::Lock::Timeout=600)
run $SUDO apt-get "${lock[@]}" update -qq
run $SUDO apt-get "${lock[@]}" install -y -qq --no-install-recommends "${missing[@]}"
