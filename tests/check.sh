# Shared helpers of the shell tests that run popc's programs as a user would.
# Source it after setting T (a scratch directory the test owns):
#   . "$POPC_SOURCE_ROOT/tests/check.sh"
# then use check / expect_exit / err_has, and end with check_summary.
fails=0 passes=0
ok()   { passes=$((passes + 1)); echo "ok - $1"; }
bad()  { fails=$((fails + 1)); echo "not ok - $1"; }
# check DESC CMD...: passes when CMD succeeds
check() { local what=$1; shift; if "$@"; then ok "$what"; else bad "$what"; fi; }
# expect_exit CODE DESC CMD...: runs CMD with stdout in $T/out, stderr in $T/err
expect_exit() {
  local code=$1 what=$2; shift 2
  "$@" >"$T/out" 2>"$T/err"; local rc=$?
  if [ "$rc" -eq "$code" ]; then ok "$what (exit $rc)"; else bad "$what: exit $rc, expected $code: $(head -c 400 "$T/err")"; fi
}
# err_has TEXT: the last expect_exit's stderr holds TEXT (shown if not)
err_has() { grep -qF -- "$1" "$T/err" || { echo "   stderr lacks '$1':"; sed 's/^/   | /' "$T/err" | head -5; return 1; }; }
# check_summary: the closing count; the test fails if any check failed
check_summary() { echo "# $passes passed, $fails failed"; [ "$fails" -eq 0 ]; }
# sans_provenance LOG: the log without exactly its provenance lines (popc
# run's "# popc_build = ", "# date = ", "# command = ": they differ from run
# to run, README "The log"); every other line, header included, as written
sans_provenance() { grep -v -E '^# (popc_build|date|command) = ' "$1"; }
