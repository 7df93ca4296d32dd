#!/bin/sh
# The chatter detector's verdicts on a scene as distributions: each variant
# (VARIANTS, default all ten) at 5 s and 20 s, over 10 sub-count start
# offsets (operator.x0 = the scene's x0 + j delta / 10, j = 0..9: tenths of a
# count; x0 and delta read from `popc scene show` with the given options).
# Prints per variant and duration how many runs have chatter (and when the
# first interval starts) and a limit cycle, and the range of the largest
# window PC RMS. docs/ANALYSIS.md quotes its output.
#   tools/chatter-offsets.sh build/src/popc build/analysis/popc-analyze \
#       data/scenes/paper.ini [--set k=v ...]
set -eu
[ $# -ge 3 ] || { echo "usage: $0 POPC POPC_ANALYZE SCENE [popc run options]" >&2; exit 2; }
P=$1 A=$2 S=$3
shift 3
W=$(mktemp -d "${TMPDIR:-/tmp}/chatter-offsets.XXXXXX")
resolved=$("$P" scene show "$S" "$@")
x0_base=$(echo "$resolved" | awk -F' = ' '/^\[/ { s = $0 } s == "[operator]" && $1 == "x0" { print $2 }')
delta=$(echo "$resolved" | awk -F' = ' '/^\[/ { s = $0 } s == "[encoder]" && $1 == "resolution" { print $2 }')
trap 'rm -rf "$W"' EXIT
for d in 5 20; do
	for v in ${VARIANTS:-none po-pc ref-energy filtered-velocity ignore hold improved pc-off-reversals energy-bounding windowed-po}; do
		: >"$W/v.txt"
		: >"$W/rms.txt"
		for j in 0 1 2 3 4 5 6 7 8 9; do
			x0=$(awk -v b="$x0_base" -v d="$delta" -v j="$j" 'BEGIN { printf "%.12g", b + j * d / 10 }')
			"$P" run "$S" --variant "$v" --set run.duration="$d" --set operator.x0="$x0" \
				"$@" --log "$W/l.csv" -q
			"$A" chatter --format csv "$W/l.csv" >"$W/o.csv" 2>/dev/null || true
			"$A" chatter "$W/l.csv" 2>/dev/null | sed -n 2p |
				sed 's/.*max PC RMS \([0-9.e+-]*\) N.*/\1/' >>"$W/rms.txt" || true
			awk -F, 'NR > 1 && $2 == "chatter" { c = 1; if (s == "") s = $3 }
				 NR > 1 && $2 == "limit_cycle" { l = 1 }
				 END { print c + 0, l + 0, s }' "$W/o.csv" >>"$W/v.txt"
		done
		awk -v d="$d" -v v="$v" '{ c += $1; l += $2
			if ($1) { if (mn == "" || $3 < mn) mn = $3; if ($3 > mx) mx = $3 } }
			END { printf "%s s %-18s chatter %2d/10", d, v, c
			      if (c) printf " (from %s-%s s)", mn, mx
			      printf ", limit cycle %2d/10", l }' "$W/v.txt"
		sort -g "$W/rms.txt" | awk '{ a[NR] = $1 } END { printf ", max window PC RMS %s-%s N\n", a[1], a[NR] }'
	done
done
