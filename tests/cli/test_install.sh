#!/usr/bin/env bash
# `meson install` as a user does it, into a scratch prefix: a second build of
# this source configured with --prefix=$T/prefix (so the installed programs'
# built-in data directory is the scratch one, as /usr/share/popc is for
# Debian's), only the installed targets built (at -O0: a few seconds), then
# the installed programs run from an empty directory without POPC_DATA_PATH:
# `popc run paper` finds the installed scene, `--set axis.map=generic` the
# installed map, `man -M $T/prefix/share/man popc` shows the page, the
# installed bash completion completes installed names.
# Arguments: enabled|disabled (this build's Modbus family, for the second
# build) and man|no-man (whether this build found scdoc).
# Exit 77 (skipped) when meson or ninja is missing, or, after every other
# check passed, when the man pages could not be checked (no scdoc, no man).
set -u
SRC=${POPC_SOURCE_ROOT:?}
MODBUS=${1:?enabled or disabled}
MAN=${2:?man or no-man}
T=$(mktemp -d /tmp/popc-install-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
for tool in meson ninja python3; do
  command -v "$tool" >/dev/null || { echo "skipped: $tool is not installed (tools/install-deps.sh test)"; exit 77; }
done
unset POPC_DATA_PATH DESTDIR
P=$T/prefix
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", b - a }'; }

# ---- configure, build the installed targets, install
t0=$(now)
man_opt=disabled
[ "$MAN" = man ] && man_opt=enabled
# a bash-completion.pc as Debian's (package bash-completion, on most
# installs): its datadir is a literal /usr/share, so a completionsdir taken
# from it ignores --prefix (issue 27). Put first on pkg-config's path, so
# this test sees that case whether or not the package is installed here.
mkdir -p "$T/pc"
cat >"$T/pc/bash-completion.pc" <<'EOF'
prefix=/usr
datadir=/usr/share
sysconfdir=/etc

compatdir=${sysconfdir}/bash_completion.d
completionsdir=${datadir}/bash-completion/completions
helpersdir=${datadir}/bash-completion/helpers

Name: bash-completion
Description: programmable completion for the bash shell
Version: 2.11
EOF
export PKG_CONFIG_PATH=$T/pc${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}
if ! meson setup "$T/build" "$SRC" --prefix="$P" -Dbuildtype=debug -Dmodbus="$MODBUS" \
     -Dman="$man_opt" >"$T/setup.log" 2>&1; then
  tail -20 "$T/setup.log"
  bad "meson setup --prefix=$P"
  check_summary
  exit 1
fi
t1=$(now)
# the targets meson install installs, as build-relative paths (ninja's names)
meson introspect "$T/build" --targets > "$T/targets.json"
mapfile -t targets < <(python3 -c '
import json, os, sys
build = sys.argv[1]
for t in json.load(open(sys.argv[2])):
    if t.get("installed"):
        for f in t["filename"]:
            print(os.path.relpath(f, build))' "$T/build" "$T/targets.json")
check "the installed targets listed (${#targets[@]}: ${targets[*]})" test "${#targets[@]}" -ge 3
ninja -C "$T/build" "${targets[@]}" >"$T/build.log" 2>&1
check "  built" test $? -eq 0 || tail -20 "$T/build.log"
t2=$(now)
# every file meson install would write goes under the prefix (nothing into
# /usr/share, with or without bash-completion's pkg-config file)
meson introspect "$T/build" --installed > "$T/installed.json"
outside=$(python3 -c '
import json, sys
p = sys.argv[1].rstrip("/") + "/"
print(" ".join(sorted(d for d in json.load(open(sys.argv[2])).values() if not d.startswith(p))))' "$P" "$T/installed.json")
check "every installed file is under $P${outside:+ (not: $outside)}" test -z "$outside"
meson install -C "$T/build" --no-rebuild --quiet >"$T/install.log" 2>&1
check "meson install into $P" test $? -eq 0 || tail -20 "$T/install.log"
t3=$(now)
echo "# times: setup $(secs "$t0" "$t1") s, build $(secs "$t1" "$t2") s, install $(secs "$t2" "$t3") s"

# ---- what is where
for f in bin/popc bin/popc-analyze share/popc/slurm/popc-sweep.sbatch share/doc/popc/LICENSE \
         share/doc/popc/README.md share/doc/popc/SWEEPS.md share/doc/popc/MAPS.md \
         share/doc/popc/figures/map-zwidth-spring.png share/bash-completion/completions/popc \
         share/bash-completion/completions/popc-analyze; do
  check "installed: $f" test -s "$P/$f"
done
for f in "$SRC"/data/scenes/*.ini "$SRC"/data/drives/*.ini; do
  rel=share/popc/${f#"$SRC"/data/}
  check "installed: $rel, as shipped" cmp -s "$f" "$P/$rel"
done
check "popc and popc-analyze are executable" test -x "$P/bin/popc" -a -x "$P/bin/popc-analyze"
[ "$MODBUS" = enabled ] && check "popc-servo-sim installed (Modbus build)" test -x "$P/bin/popc-servo-sim"
check "the LICENSE is MIT, the popc developers'" grep -q "Copyright (c) the popc developers" "$P/share/doc/popc/LICENSE"

# ---- the installed programs find the installed data, from any directory
mkdir -p "$T/wd"
cd "$T/wd" || exit 1
expect_exit 0 "installed popc run paper" "$P/bin/popc" run paper -q --set run.duration=0.2 --log run.csv
check "  wrote the log" test -s run.csv
expect_exit 0 "installed popc run paper.ini" "$P/bin/popc" run paper.ini -q --set run.duration=0.01
expect_exit 0 "installed popc scene show fig3" "$P/bin/popc" scene show fig3
check "  read the installed fig3.ini" grep -qxF "; resolved scene from $P/share/popc/scenes/fig3.ini" "$T/out"
expect_exit 0 "  --set axis.map=generic" "$P/bin/popc" scene show paper --set axis.map=generic
check "  the installed map, absolute" grep -qxF "map = $P/share/popc/drives/generic.ini" "$T/out"
expect_exit 0 "installed popc scene list" "$P/bin/popc" scene list
check "  every installed scene ($(ls "$SRC"/data/scenes/*.ini | wc -l))" test "$(grep -c "	$P/share/popc/scenes/" "$T/out")" -eq "$(ls "$SRC"/data/scenes/*.ini | wc -l)"
expect_exit 2 "an unknown name names the installed directory" "$P/bin/popc" run nosuch -q
check "  $P/share/popc" err_has "in the data directory $P/share/popc"
expect_exit 0 "installed popc-analyze reads the installed popc's log" "$P/bin/popc-analyze" energy run.csv --check
if [ -x "$P/bin/popc-servo-sim" ]; then
  expect_exit 2 "installed popc-servo-sim --map generic --scene paper (bad --listen, read after both)" \
    "$P/bin/popc-servo-sim" --map generic --scene paper --listen bogus
  check "  found both" test -z "$(grep -F 'no such file' "$T/err")"
fi

# ---- the installed bash completion, with the installed programs on PATH
comp=$(PATH="$P/bin:$PATH" bash -c '
  . "$1/share/bash-completion/completions/popc"
  COMP_LINE="popc run pa"; COMP_POINT=${#COMP_LINE}; COMP_WORDS=(popc); _popc 2>/dev/null
  echo "${COMPREPLY[*]}"
  COMP_LINE="popc run paper --map gen"; COMP_POINT=${#COMP_LINE}; COMPREPLY=(); _popc 2>/dev/null
  echo "${COMPREPLY[*]}"
  COMP_LINE="popc-analyze replay run.csv --variant im"; COMP_POINT=${#COMP_LINE}; COMP_WORDS=(popc-analyze); COMPREPLY=(); _popc_analyze 2>/dev/null
  echo "${COMPREPLY[*]}"' bash "$P")
check "installed completion: an installed scene name" test "$(sed -n 1p <<<"$comp")" = paper
check "  an installed map name" test "$(sed -n 2p <<<"$comp")" = generic
check "  popc-analyze's variant names, from the popc beside it" test "$(sed -n 3p <<<"$comp")" = improved

# ---- the library: the public header alone, libpopc shared and static, its
# pkg-config file, a program built out of the tree with it, import popc
check "installed: include/popc/popc.h, the public header" test -s "$P/include/popc/popc.h"
internal=$(cd "$P/include" && find . -name '*.h' ! -path ./popc/popc.h | head -3)
check "  and no internal header${internal:+ (installed: $internal)}" test -z "$internal"
pc=$(find "$P" -name popc.pc | head -1)
check "installed: popc.pc (pkg-config)" test -n "$pc"
libdir=$(PKG_CONFIG_PATH=${pc%/*} pkg-config --variable=libdir popc 2>/dev/null)
check "  its libdir holds libpopc.so.1 and libpopc.a" test -e "$libdir/libpopc.so.1" -a -e "$libdir/libpopc.a"
export PKG_CONFIG_PATH=${pc%/*}
cc_=${CC:-cc}
if command -v pkg-config >/dev/null && command -v "$cc_" >/dev/null; then
  # shared: the loader finds the scratch prefix's library by the rpath
  # shellcheck disable=SC2046
  "$cc_" -std=c11 -Wall -Werror "$SRC/examples/device_loop.c" -o "$T/dl-shared" \
    $(pkg-config --cflags --libs popc) -Wl,-rpath,"$libdir" 2>"$T/cc.err"
  check "an out-of-tree program: cc device_loop.c \$(pkg-config --cflags --libs popc)" test $? -eq 0 || cat "$T/cc.err"
  check "  needs libpopc.so.1" grep -q 'libpopc\.so\.1' <(readelf -d "$T/dl-shared" 2>/dev/null)
  # static: libpopc.a by name, then what --static adds (libmodbus, inih, m, pthread)
  static_libs=$(pkg-config --static --libs popc)
  # shellcheck disable=SC2046,SC2086
  "$cc_" -std=c11 -Wall -Werror "$SRC/examples/device_loop.c" -o "$T/dl-static" \
    $(pkg-config --cflags popc) ${static_libs/-lpopc/-l:libpopc.a} 2>"$T/cc.err"
  check "  and with pkg-config --static, against libpopc.a" test $? -eq 0 || cat "$T/cc.err"
  check "  which needs no libpopc.so" test -z "$(readelf -d "$T/dl-static" 2>/dev/null | grep libpopc)"
  "$P/bin/popc" run paper -q --set run.duration=1 --set controller.variant=improved --log lib-ref.csv
  for kind in shared static; do
    "$T/dl-$kind" paper "lib-$kind.csv" run.duration=1 controller.variant=improved
    check "  the $kind program's rows equal the installed popc run's" \
      cmp -s <(grep -v '^#' "lib-$kind.csv") <(grep -v '^#' lib-ref.csv)
  done
else
  bad "pkg-config or $cc_ missing: the library was not built against (tools/install-deps.sh paper)"
fi
# import popc from the prefix: the module loads the prefix's libpopc.so.1
py=${POPC_PYTHON:-}
pkg=$(find "$P" -path '*/popc/__init__.py' | head -1)
if [ -n "$py" ]; then
  check "installed: the Python module popc (${pkg#"$P"/})" test -n "$pkg"
  pyp=${pkg%/popc/__init__.py}
  (unset POPC_LIBRARY; PYTHONPATH=$pyp "$py" "$SRC/examples/python/step_controller.py" paper improved) > "$T/py.out" 2>&1
  check "  examples/python/step_controller.py against the prefix: $(tail -1 "$T/py.out")" test $? -eq 0
  (unset POPC_LIBRARY; PYTHONPATH=$pyp "$py" "$SRC/examples/python/read_log.py" lib-ref.csv) > "$T/py.out" 2>&1
  check "  examples/python/read_log.py: $(grep -m1 recomputed "$T/py.out")" test $? -eq 0
  (unset POPC_LIBRARY; PYTHONPATH=$pyp "$py" -c 'import popc, sys; sys.exit(popc._lib._name != sys.argv[1])' "$libdir/libpopc.so.1")
  check "  it loaded $libdir/libpopc.so.1" test $? -eq 0
fi

# ---- man pages
man_skip=
if [ "$MAN" != man ]; then
  man_skip="this build found no scdoc, so no man pages were built (apt-get install scdoc, or tools/install-deps.sh test)"
elif ! command -v man >/dev/null; then
  man_skip="man is not installed (apt-get install man-db, or tools/install-deps.sh test)"
fi
if [ -z "$man_skip" ]; then
  pages=("1 popc" "1 popc-analyze" "5 popc-scene")
  [ "$MODBUS" = enabled ] && pages+=("1 popc-servo-sim")
  for pg in "${pages[@]}"; do
    read -r sec name <<<"$pg"
    check "installed: share/man/man$sec/$name.$sec" test -s "$P/share/man/man$sec/$name.$sec"
    MANPAGER=cat MANWIDTH=100 man -M "$P/share/man" "$sec" "$name" >"$T/man-$name.txt" 2>"$T/man-$name.err"
    check "  man -M $P/share/man $sec $name" test -s "$T/man-$name.txt"
    # man-db's formatter marks bold and underline by overstriking
    sed -i 's/.\x08//g' "$T/man-$name.txt"
    check "  its NAME section" grep -q "^ *$name - " "$T/man-$name.txt"
  done
  check "man popc states the lookup rule" grep -q "FINDING SCENES AND MAPS" "$T/man-popc.txt"
  check "  with the installed data directory" grep -qF "$P/share/popc" "$T/man-popc.txt"
  missing=
  while read -r key; do
    grep -qF -- "$key" "$T/man-popc-scene.txt" || missing+=" $key"
  done < <("$P/bin/popc" scene keys | awk '/^  [^ ]/ { print $1 }')
  check "man 5 popc-scene lists every key of 'popc scene keys'${missing:+ (missing:$missing)}" test -z "$missing"
fi
check_summary || exit 1
if [ -n "$man_skip" ]; then
  echo "skipped: the man pages were not checked: $man_skip (the other $passes checks passed)"
  exit 77
fi
