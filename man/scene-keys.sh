#!/bin/sh
# Makes popc-scene.5.scd from its template at build time (man/meson.build):
# the line @SCENE_KEYS@ becomes the key list of `popc scene keys`, in scdoc,
# so that the page lists exactly the keys the program knows; @DATADIR@ and
# @DOCDIR@ become the installed directories.
#   scene-keys.sh POPC TEMPLATE OUTPUT DATADIR DOCDIR
set -eu
popc=$1 in=$2 out=$3 datadir=$4 docdir=$5
keys=$("$popc" scene keys)
[ -n "$keys" ] || { echo "scene-keys.sh: '$popc scene keys' printed nothing" >&2; exit 1; }
# `popc scene keys` prints per key
#   "  section.key   default D   allowed RANGE" and "      help"
# scdoc reads '*' and '_' as bold and underline: escape them first.
list=$(printf '%s\n' "$keys" | sed 's/[*_]/\\&/g' | awk '
  /^  [^ ]/ {
    name = $1; def = $3
    allowed = $0; sub(/^.* allowed /, "", allowed)
    split(name, part, "."); section = part[1]
    next
  }
  /^      / {
    help = $0; sub(/^ +/, "", help)
    if (section != last) { printf "## [%s]\n\n", section; last = section }
    printf "*%s*\n\t%s. Default %s; allowed %s.\n\n", name, help, def, allowed
    n++
  }
  END { if (n == 0) exit 1 }')
tmp=$out.tmp
# through the environment: awk -v would read the backslashes as escapes
LIST=$list DATADIR=$datadir DOCDIR=$docdir awk '
  $0 == "@SCENE_KEYS@" { print ENVIRON["LIST"]; next }
  { gsub(/@DATADIR@/, ENVIRON["DATADIR"]); gsub(/@DOCDIR@/, ENVIRON["DOCDIR"]); print }' "$in" > "$tmp"
mv "$tmp" "$out"
