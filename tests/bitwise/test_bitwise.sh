#!/usr/bin/env bash
# Bitwise logs (docs/BENCHMARKS.md, "Bitwise across compilers"): runs every
# case of lib.sh with $POPC and
#  1. checks each 'exact' case's rows against expected.sha256 (written by a
#     gcc 12 release build; a build whose flags or compiler change one bit of
#     one row fails here, on any machine);
#  2. when POPC_REFERENCE names another build's popc (tools/run-tests.sh: the
#     gcc release build, for its clang build), runs every case with it too
#     and compares the two logs of each case with cmp, header included.
# Usage: test_bitwise.sh              (meson test; POPC, POPC_SOURCE_ROOT)
#        test_bitwise.sh --update POPC   rewrite expected.sha256 with POPC's
#          logs, after a change that is meant to move the bits (say so in
#          the commit: every popc log of these scenes changes with it)
set -u
bitwise_here=$(cd "$(dirname "$0")" && pwd)
bitwise_src=$(cd "$bitwise_here/../.." && pwd)
. "$bitwise_here/lib.sh"
expected=$bitwise_here/expected.sha256
T=$(mktemp -d /tmp/popc-bitwise-XXXXXX)
trap 'rm -rf "$T"' EXIT

if [ "${1:-}" = --update ]; then
  POPC=${2:?usage: test_bitwise.sh --update POPC}
  write_logs "$POPC" "$T/a" || exit 1
  {
    echo "# SHA-256 of each exact case's log rows (tests/bitwise/lib.sh);"
    echo "# tests/bitwise/test_bitwise.sh --update POPC rewrites it"
    bitwise_cases | while read -r kind name _; do
      [ "$kind" = exact ] && echo "$(rows_digest "$T/a/$name.csv")  $name"
    done
  } > "$expected"
  echo "wrote $expected ($(grep -vc '^#' "$expected") cases)"
  exit 0
fi

POPC=${POPC:?POPC must name the popc program}
. "$bitwise_src/tests/check.sh"
check "every case runs with $POPC" write_logs "$POPC" "$T/a"
declare -A want
while read -r digest name; do want[$name]=$digest; done < <(grep -v '^#' "$expected")
changed=0
while read -r kind name _; do
  [ "$kind" = exact ] || continue
  got=$(rows_digest "$T/a/$name.csv")
  if [ -z "${want[$name]:-}" ]; then bad "$name: no digest in expected.sha256"
  elif [ "$got" = "${want[$name]}" ]; then ok "$name: rows as expected.sha256"
  else bad "$name: rows differ from expected.sha256 (sha256 $got)"; changed=1
  fi
done < <(bitwise_cases)
[ $changed -eq 0 ] || echo "# if the change of bits is meant: tests/bitwise/test_bitwise.sh --update BUILD/src/popc"

if [ -n "${POPC_REFERENCE:-}" ]; then
  check "every case runs with $POPC_REFERENCE" write_logs "$POPC_REFERENCE" "$T/b"
  while read -r kind name _; do
    if cmp -s "$T/a/$name.csv" "$T/b/$name.csv"; then ok "$name: log bitwise the same from both builds"
    else
      n=$(paste -d'\n' <(sed -n '/^t,/,$p' "$T/a/$name.csv") <(sed -n '/^t,/,$p' "$T/b/$name.csv") |
          awk 'NR % 2 { l = $0; next } l != $0 { n++ } END { print n + 0 }')
      bad "$name: logs differ between the builds ($n rows; first at $(cmp "$T/a/$name.csv" "$T/b/$name.csv" 2>&1 | sed -n "s/.*differ: //p"))"
    fi
  done < <(bitwise_cases)
else
  echo "# POPC_REFERENCE unset: no other build to compare with (tools/run-tests.sh sets it for build-clang)"
fi
check_summary
