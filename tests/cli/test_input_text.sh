#!/usr/bin/env bash
# Scene, register map and log header text written apart from the project:
# CR-only line ends (classic Mac OS) are refused by all three readers, naming
# line 1 (libinih read such a scene as one line: the defaults, exit 0); an
# unknown section without keys is refused like one with keys; a popc log
# header giving a key twice is refused naming both lines; a header value the
# scene refuses is named with its line. Each failed on 46f30c1.
set -u
POPC=${POPC:?POPC must name the popc program}
case $POPC in /*) ;; *) POPC=$PWD/$POPC ;; esac
SRC=${POPC_SOURCE_ROOT:?}
A=${1:-${POPC_ANALYZE:?popc-analyze: argument 1 or POPC_ANALYZE}}
T=$(mktemp -d /tmp/popc-text-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
CR="a carriage return (CR) inside the line: lines end with LF or CR LF; a file with CR-only line ends (classic Mac OS) reads as one line"

printf '[run]\rduration = 2\r[operator]\rmass = 7\r' > "$T/cr.ini"
expect_exit 2 "a CR-only scene" "$POPC" run "$T/cr.ini" --log "$T/cr.csv"
check "  names line 1 and why" err_has "popc run: $T/cr.ini:1: $CR"
check "  nothing ran" test ! -e "$T/cr.csv"
printf '[run]\r\nduration = 0.01\r\n' > "$T/crlf.ini"
expect_exit 0 "a CRLF scene still runs" "$POPC" run "$T/crlf.ini" -q
printf '[run]\nduration = 0.01\n[contoller]\n[controller]\nvariant = none\n' > "$T/empty.ini"
expect_exit 2 "an unknown section without keys (a misspelt [controller])" "$POPC" run "$T/empty.ini"
check "  named at its line, as one with keys" err_has "popc run: $T/empty.ini:3: unknown section [contoller]; sections are run, operator, device, environment, encoder, controller, admittance, integrator, axis"
printf '[run]\nduration = 0.01\n[nosuch]\n' > "$T/empty2.ini"
expect_exit 2 "an unknown section alone at the end" "$POPC" scene show "$T/empty2.ini"
check "  named" err_has "$T/empty2.ini:3: unknown section [nosuch]"

tr '\n' '\r' < "$SRC/data/drives/generic.ini" > "$T/crmap.ini"
"$POPC" run "$SRC/data/scenes/paper.ini" --axis modbus --map "$T/crmap.ini" --connect tcp:127.0.0.1:9 >"$T/out" 2>"$T/err"
if grep -q "no Modbus support" "$T/err"; then
	echo "# a build without Modbus reads no register map: the CR-only map is not checked"
else
	expect_exit 2 "a CR-only register map" "$POPC" run "$SRC/data/scenes/paper.ini" --axis modbus --map "$T/crmap.ini" --connect tcp:127.0.0.1:9
	check "  names line 1 and why (not a missing key)" err_has "popc run: $T/crmap.ini:1: $CR"
fi

"$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=0.2 -q --log "$T/p.csv"
rate=$(grep -n '^# rate = 1000$' "$T/p.csv" | cut -d: -f1)
sed "${rate}a # rate = 2000" "$T/p.csv" > "$T/dup.csv"
expect_exit 2 "a popc log header giving run.rate twice" "$A" compare "$T/dup.csv"
check "  names both lines" err_has "popc-analyze compare: $T/dup.csv:$((rate + 1)): header key run.rate given twice (first on line $rate)"
sed "${rate}s/1000/1e7/" "$T/p.csv" > "$T/badrate.csv"
expect_exit 2 "a header value out of range" "$A" energy "$T/badrate.csv"
check "  names its line and the key as written" err_has "popc-analyze energy: $T/badrate.csv:$rate: header: run.rate = 1e7: out of range; allowed [1, 1e+06] Hz"
tr '\n' '\r' < "$T/p.csv" > "$T/cr.csv"
expect_exit 2 "a CR-only log" "$A" compare "$T/cr.csv"
check "  names line 1 and why" err_has "popc-analyze compare: $T/cr.csv:1: $CR"
check_summary
