#!/usr/bin/env bash
# Scenes and drive maps found by name (src/scene/data_path.c, popc(1)
# "FINDING SCENES AND MAPS"), with the build's programs and data directories
# of the test's own given by POPC_DATA_PATH: a name with a '/' is never looked
# up, a local file wins, NAME before NAME.ini, directories in order, an empty
# entry for the built-in directory, the path found recorded absolute.
# tests/cli/test_install.sh checks the built-in directory of an installed popc.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
BUILD=${POPC_BUILD_ROOT:?}
T=$(mktemp -d /tmp/popc-data-path-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
unset POPC_DATA_PATH
DATA=$SRC/data
# the first line of `popc scene show`: "; resolved scene from PATH"
from() { sed -n '1s/^; resolved scene from //p' "$T/out"; }
has_line() { grep -qxF -- "$1" "$T/out" || { echo "   no line '$1' in:"; head -3 "$T/out" | sed 's/^/   | /'; return 1; }; }

mkdir -p "$T/wd" "$T/d1/scenes" "$T/d1/drives" "$T/wd/sub"
cd "$T/wd" || exit 1
printf '[run]\nduration = 0.25\n' > "$T/d1/scenes/paper.ini"
printf '[run]\nduration = 0.5\n' > "$T/d1/scenes/both"
printf '[run]\nduration = 0.75\n' > "$T/d1/scenes/both.ini"
printf '[axis]\nmap = mymap\n' > "$T/d1/scenes/withmap.ini"
printf '[axis]\nmap = beside.ini\n' > "$T/d1/scenes/beside-map.ini"
: > "$T/d1/scenes/beside.ini" # a file named like the map, in the scene's directory
cp "$DATA/drives/generic.ini" "$T/d1/drives/mymap.ini"
BUILTIN=$(env -u POPC_DATA_PATH "$POPC" scene --help | sed -n 's/.*entry stands for the built-in one); now: //p')
check "the built-in data directory is named in the help ('$BUILTIN')" test -n "$BUILTIN"

# ---- scenes
expect_exit 2 "an unknown name" env POPC_DATA_PATH="$DATA" "$POPC" run nosuch -q
check "  names where it looked" err_has "nosuch: no such file in the working directory, nor scenes/nosuch or scenes/nosuch.ini in the data directory $DATA"
expect_exit 2 "  without POPC_DATA_PATH: the built-in directory" "$POPC" run nosuch -q
check "  named" err_has "in the data directory $BUILTIN (POPC_DATA_PATH sets them"
expect_exit 0 "popc run paper: the installed paper.ini" env POPC_DATA_PATH="$DATA" "$POPC" run paper -q --set run.duration=0.1
expect_exit 0 "popc scene show paper" env POPC_DATA_PATH="$DATA" "$POPC" scene show paper
check "  read from the data directory, absolute" test "$(from)" = "$DATA/scenes/paper.ini"
expect_exit 0 "popc scene show paper.ini" env POPC_DATA_PATH="$DATA" "$POPC" scene show paper.ini
check "  the same file" test "$(from)" = "$DATA/scenes/paper.ini"
printf '[run]\nduration = 0.125\n' > paper.ini
expect_exit 0 "a local paper.ini wins" env POPC_DATA_PATH="$DATA" "$POPC" scene show paper.ini
check "  the local file, as given" test "$(from)" = "paper.ini"
check "  its keys" has_line "duration = 0.125"
expect_exit 0 "  'paper' is no local file: still looked up" env POPC_DATA_PATH="$DATA" "$POPC" scene show paper
check "  in the data directory" test "$(from)" = "$DATA/scenes/paper.ini"
rm paper.ini
expect_exit 2 "a path with a '/' is never looked up" env POPC_DATA_PATH="$DATA" "$POPC" scene show ./paper.ini
check "  cannot open it" err_has "./paper.ini: cannot open scene: No such file or directory"
expect_exit 2 "  nor one in a subdirectory" env POPC_DATA_PATH="$DATA" "$POPC" scene show sub/paper.ini
check "  named as given" err_has "sub/paper.ini: cannot open scene"
expect_exit 0 "directories in order: the first holding the name" env POPC_DATA_PATH="$T/d1:$DATA" "$POPC" scene show paper
check "  d1's paper.ini" test "$(from)" = "$T/d1/scenes/paper.ini"
check "  its keys" has_line "duration = 0.25"
expect_exit 0 "a directory that does not exist is passed over" env POPC_DATA_PATH="$T/none:$DATA" "$POPC" scene show fig3
check "  the next one's" test "$(from)" = "$DATA/scenes/fig3.ini"
expect_exit 0 "NAME before NAME.ini" env POPC_DATA_PATH="$T/d1" "$POPC" scene show both
check "  the file named exactly so" has_line "duration = 0.5"
expect_exit 0 "  NAME.ini asked for" env POPC_DATA_PATH="$T/d1" "$POPC" scene show both.ini
check "  that one" has_line "duration = 0.75"
expect_exit 0 "an empty entry stands for the built-in directory" env POPC_DATA_PATH="$T/d1:" "$POPC" scene --help
check "  listed second" grep -qF "now: $T/d1:$BUILTIN" "$T/out"
expect_exit 0 "a relative data directory" env POPC_DATA_PATH=../d1 "$POPC" scene show paper
check "  made absolute" test "$(from)" = "$T/d1/scenes/paper.ini"

# ---- maps
expect_exit 0 "--set axis.map=generic" env POPC_DATA_PATH="$DATA" "$POPC" scene show --set axis.map=generic
check "  the installed map, absolute" has_line "map = $DATA/drives/generic.ini"
expect_exit 0 "a map name in a scene file" env POPC_DATA_PATH="$T/d1" "$POPC" scene show withmap
check "  the data directory's map" has_line "map = $T/d1/drives/mymap.ini"
expect_exit 0 "a map beside the scene wins" env POPC_DATA_PATH="$T/d1" "$POPC" scene show beside-map
check "  the scene directory's file" has_line "map = $T/d1/scenes/beside.ini"
expect_exit 0 "a map name found nowhere stays a relative path" env POPC_DATA_PATH="$DATA" "$POPC" scene show --set axis.map=nomap
check "  from the working directory" has_line "map = $T/wd/nomap"
expect_exit 0 "the log header records the map found" env POPC_DATA_PATH="$DATA" "$POPC" run paper --set axis.map=generic --set run.duration=0.01 --log "$T/l.csv" -q
check "  absolute" grep -qxF "# map = $DATA/drives/generic.ini" "$T/l.csv"

# ---- popc scene list, sweeps, popc-servo-sim
expect_exit 0 "popc scene list" env POPC_DATA_PATH="$T/d1:$DATA" "$POPC" scene list
check "  the first directory's paper" has_line "paper	$T/d1/scenes/paper.ini"
check "  once" test "$(grep -c '^paper	' "$T/out")" -eq 1
check "  the second's fig3" has_line "fig3	$DATA/scenes/fig3.ini"
check "  only .ini files, named without .ini" test "$(grep -c '^both	' "$T/out")" -eq 1
# a name with a tab or a newline would break the NAME<TAB>PATH lines (issue
# 28: printed raw): not listed, a note names it escaped; the others are
mkdir -p "$T/ctl/scenes"
cp "$DATA/scenes/paper.ini" "$T/ctl/scenes/ok.ini"
cp "$DATA/scenes/paper.ini" "$T/ctl/scenes/tab"$'\t'"name.ini"
cp "$DATA/scenes/paper.ini" "$T/ctl/scenes/new"$'\n'"line.ini"
expect_exit 0 "popc scene list with control characters in names" env POPC_DATA_PATH="$T/ctl" "$POPC" scene list
check "  only the plain name is listed" test "$(cat "$T/out")" = "ok	$T/ctl/scenes/ok.ini"
check "  a note names the tab" err_has "popc scene list: note: not listed: $T/ctl/scenes/tab\\tname.ini: a name or path with a tab, a newline or another control character cannot be one NAME<TAB>PATH line (rename it)"
check "  and the newline" err_has "popc scene list: note: not listed: $T/ctl/scenes/new\\nline.ini"
expect_exit 0 "popc scene list --maps" env POPC_DATA_PATH="$DATA" "$POPC" scene list --maps
check "  generic" has_line "generic	$DATA/drives/generic.ini"
expect_exit 0 "popc sweep paper" env POPC_DATA_PATH="$DATA" "$POPC" sweep paper --vary controller.variant=none,improved --set run.duration=0.1 -o "$T/sw" -q --no-log
check "  the plan names the installed scene" grep -qxF "scene = $DATA/scenes/paper.ini" "$T/sw/sweep.plan"
# the programs read POPC_DATA_PATH and pass it to the library layers, which
# read no environment (docs/LIBRARY.md); a value longer than a scene holds
# is bad input, named, before any work
LONG=$(printf '/x%.0s' $(seq 600))
expect_exit 2 "a POPC_DATA_PATH of 1200 characters" env POPC_DATA_PATH="$LONG" "$POPC" run paper -q --set run.duration=0.1
check "  named, with the limit" err_has "POPC_DATA_PATH: the data path is 1200 characters long; at most 1023"
expect_exit 2 "  popc sweep too" env POPC_DATA_PATH="$LONG" "$POPC" sweep paper --vary controller.variant=none,improved -o "$T/swlong" -q --no-log
check "  named" err_has "POPC_DATA_PATH: the data path is 1200 characters long"
check "  nothing made" test ! -e "$T/swlong"
SIM=$BUILD/src/servo_sim/popc-servo-sim
if [ -x "$SIM" ]; then
  # a bad --listen is refused after the map and the scene are read
  expect_exit 2 "popc-servo-sim --map generic --scene paper" env POPC_DATA_PATH="$DATA" "$SIM" --map generic --scene paper --listen bogus
  check "  both found (it goes on to the URI)" err_has "bogus"
  check "  ... not 'no such file'" test -z "$(grep -F 'no such file' "$T/err")"
  expect_exit 2 "popc-servo-sim --map nosuch" env POPC_DATA_PATH="$DATA" "$SIM" --map nosuch --scene paper --listen bogus
  check "  names where it looked" err_has "nor drives/nosuch or drives/nosuch.ini in the data directory $DATA"
fi
check_summary
