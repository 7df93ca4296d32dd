#!/usr/bin/env bash
# The exe_wrapper of `meson test --setup valgrind` (meson.build):
#
#   valgrind-wrapper.sh BUILD_ROOT VALGRIND [OPTION...] -- TEST [ARG...]
#
# runs TEST under VALGRIND when it is a program built in BUILD_ROOT. A test
# whose command is an interpreter or a script (bash, sh, python3: behaviour,
# layers-includes, the CLI drivers) is skipped (exit 77): valgrind would check
# bash or python, not popc, and bash itself leaks blocks memcheck counts as
# definitely lost. Those tests run under ASan/UBSan instead (--setup sanitize).
set -u
build_root=$1
shift
valgrind=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do
	valgrind+=("$1")
	shift
done
shift # the --
command -v "${valgrind[0]}" >/dev/null || {
	echo "valgrind setup: ${valgrind[0]} not found (apt-get install valgrind)" >&2
	exit 1
}
case $1 in
"$build_root"/*) exec "${valgrind[@]}" "$@" ;;
*)
	echo "valgrind setup: '$1' is not a program built in $build_root: skipped" >&2
	exit 77
	;;
esac
