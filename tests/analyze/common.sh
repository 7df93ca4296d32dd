# Sourced by the popc-analyze CLI tests: $1 is popc-analyze, $2 this file.
# POPC and POPC_SOURCE_ROOT come from tests/meson.build's test_env.
set -u
A=$1
case $A in /*) ;; *) A=$PWD/$A ;; esac
SCENES=$POPC_SOURCE_ROOT/data/scenes
W=$(mktemp -d "${TMPDIR:-/tmp}/popc-analyze-test.XXXXXX") || exit 99
trap 'rm -rf "$W"' EXIT
FAILS=0
fail() { echo "FAIL: $*" >&2; FAILS=$((FAILS + 1)); }
ok() { echo "ok: $*"; }
# expect_rc WANT CMD...: runs CMD, stdout/stderr to $W/out $W/err
expect_rc() {
	want=$1; shift
	"$@" >"$W/out" 2>"$W/err"
	rc=$?
	if [ "$rc" -ne "$want" ]; then
		fail "exit $rc (want $want): $*"
		sed 's/^/  stderr: /' "$W/err" | head -5 >&2
		return 1
	fi
	return 0
}
# run_scene SCENE.ini OUT.csv [popc run options]
run_scene() {
	scene=$1; out=$2; shift 2
	"$POPC" run "$SCENES/$scene" --log "$out" -q "$@" || { echo "popc run $scene failed" >&2; exit 99; }
}
finish() {
	if [ "$FAILS" -ne 0 ]; then echo "$FAILS failure(s)" >&2; exit 1; fi
	exit 0
}
