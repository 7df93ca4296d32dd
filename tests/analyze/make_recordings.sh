#!/bin/sh
# make_recordings.sh LOG [LOG2] DIR: turns popc logs into files shaped like
# recordings from real haptic setups, for popc-analyze's "Recorded device
# logs" (docs/ANALYSIS.md). The numbers are popc's cells copied as text (no
# arithmetic on positions or forces), so that each file holds the same data
# as LOG and must analyse the same; only the time stamps are changed where a
# recording's clock differs (ms, us with jitter).
#
#   DIR/phantom.txt  no column names, no time column, blanks between right-
#                    aligned columns: x y z (m) fx fy fz (N), PHANToM-style; x
#                    and fx are LOG's x and f_c, the other axes filler.
#                    Read with: --no-header --column x=#1 --column f_c=#4
#                    --set run.rate=HZ
#   DIR/jitter.tsv   tab-separated, named columns time_us, enc, cmd_N: LOG's
#                    encoder count and f_c, time stamps in us: k T plus a
#                    delay of 0..40 us (the clock read after the sample; a
#                    deterministic Park-Miller sequence, the same file on
#                    every machine): steps within 4 % of a 1 kHz period.
#                    Read with: --column t=time_us --scale t=1e-6 --column
#                    count=enc --column f_c=cmd_N --set run.rate=1000
#                    --jitter 0.05
#   DIR/twoaxis.txt  (with LOG2) a '%' comment, then blanks between columns
#                    t_ms x1 fc1 x2 fc2: time in integer ms (k), axis 1 from
#                    LOG, axis 2 from LOG2 (same rate and length).
#                    Read with: --comment % --column t=t_ms --scale t=1e-3 --column x=x2
#                    --column f_c=fc2 (or x=#4 f_c=#5)
# The time in ms is k exactly; k x 1e-3 is the double popc writes as
# t = k T at 1 kHz (T = 1/1000 and 1e-3 are the same double).
set -eu
log=$1
if [ $# -eq 3 ]; then log2=$2; dir=$3; else log2=; dir=$2; fi
mkdir -p "$dir"
# the rows of a popc log, without comments and column names
rows() { grep -v '^#' "$1" | tail -n +2; }
col() { # col LOG NAME: the index of column NAME
	grep -v '^#' "$1" | head -n 1 | tr ',' '\n' | grep -n -x "$2" | cut -d: -f1
}
ix=$(col "$log" x); ic=$(col "$log" count); ifc=$(col "$log" f_c)
{
	echo "# PHANToM servo loop log: position (m) and force (N), one line per 1 ms tick"
	rows "$log" | awk -F, -v ix="$ix" -v ifc="$ifc" \
		'{ printf "%24s %8s %8s %24s %6s %6s\n", $ix, "0.012", "-0.003", $ifc, "0", "0.1" }'
} >"$dir/phantom.txt"
{
	printf 'time_us\tenc\tcmd_N\n'
	rows "$log" | awk -F, -v ic="$ic" -v ifc="$ifc" 'BEGIN { s = 20240501 }
		{ s = (s * 16807) % 2147483647; j = s % 41
		  printf "%d\t%s\t%s\n", (NR - 1) * 1000 + j, $ic, $ifc }'
} >"$dir/jitter.tsv"
if [ -n "$log2" ]; then
	ix2=$(col "$log2" x); ifc2=$(col "$log2" f_c)
	{
		echo "% two-axis rig, 1 kHz"
		echo "t_ms x1 fc1 x2 fc2"
		rows "$log2" | cut -d, -f"$ix2,$ifc2" >"$dir/.axis2"
		rows "$log" | cut -d, -f"$ix,$ifc" | paste -d, - "$dir/.axis2" |
			awk -F, '{ printf "%d %s %s %s %s\n", NR - 1, $1, $2, $3, $4 }'
		rm -f "$dir/.axis2"
	} >"$dir/twoaxis.txt"
fi
