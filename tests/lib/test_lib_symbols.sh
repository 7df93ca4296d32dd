#!/usr/bin/env bash
# The symbols libpopc.so exports (nm -D --defined-only) are exactly those
# src/lib/popc.symbols lists: an export added by mistake (a function without
# the -fvisibility=hidden of src/lib, an internal archive's symbol) or one
# removed fails here (docs/LIBRARY.md, "ABI policy").
# Arguments: LIBRARY SYMBOLS_FILE
set -u
lib=${1:?library}
list=${2:?symbols file}
command -v nm >/dev/null || { echo "skipped: no nm (binutils)"; exit 77; }
T=$(mktemp -d /tmp/popc-symbols-XXXXXX)
trap 'rm -rf "$T"' EXIT
# the linker's own markers are not the library's
nm -D --defined-only "$lib" | awk '{ print $NF }' \
  | grep -v -x -E '_init|_fini|_edata|_end|__bss_start' | sort -u > "$T/built"
grep -v -E '^(#|$)' "$list" | sort -u > "$T/listed"
if cmp -s "$T/built" "$T/listed"; then
  echo "ok - $(wc -l < "$T/built") symbols exported, as listed in $list"
  exit 0
fi
echo "not ok - the exports of $lib differ from $list:"
comm -23 "$T/built" "$T/listed" | sed 's/^/  exported, not listed: /'
comm -13 "$T/built" "$T/listed" | sed 's/^/  listed, not exported: /'
exit 1
