#!/usr/bin/env bash
# popc sweep --dry-run and popc map --dry-run print the plan and write
# nothing (issue 27: there was no dry run, and `sweep --list` writes the plan
# and the run directories). The working directory's tree (names, sizes,
# modification times and contents) is the same before and after: for a new
# DIR (not made), a DIR that holds the same sweep (a resume: the runs done
# counted, nothing locked or touched) and a DIR that holds another sweep
# (exit 2, as the sweep itself would be refused).
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
T=$(mktemp -d /tmp/popc-dry-run-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
export POPC_DATA_PATH="$SRC/data"
mkdir -p "$T/wd"
cd "$T/wd" || exit 1

# the tree below the working directory: every entry, its size, mtime and digest
tree() { find . -printf '%p %y %s %T@\n' | sort; find . -type f -exec md5sum {} + | sort; }
VARY=(--vary controller.variant=none,improved --vary encoder.resolution=1e-5,2e-5)

tree >"$T/before"
expect_exit 0 "sweep --dry-run into a new DIR" "$POPC" sweep paper --set run.duration=0.5 "${VARY[@]}" -o new/sub --dry-run
check "  one line per run, id and values" test "$(grep -c $'^000[0-3]\t' "$T/out")" -eq 4
check "  run 0003's values" grep -q $'^0003\tcontroller.variant=improved encoder.resolution=2e-5$' "$T/out"
check "  says the DIR would be made and nothing is written" grep -q 'new/sub does not exist (it would be made); nothing written' "$T/out"
tree >"$T/after"
check "  the tree is unchanged (no DIR, plan, lock or run directory)" cmp -s "$T/before" "$T/after"

expect_exit 0 "  --shard 2/2: the shard's runs" "$POPC" sweep paper --set run.duration=0.5 "${VARY[@]}" -o new --dry-run --shard 2/2
check "  two of them, ids 1 and 3" test "$(cut -f1 "$T/out" | grep -v '^#' | tr '\n' ' ')" = "0001 0003 "

# a sweep made (two runs), then dry runs against it
"$POPC" sweep paper --set run.duration=0.5 --vary controller.variant=none,improved -o made -q -j 1 --no-log 2>"$T/sweep.err"
check "a real sweep for the resume case" test -s made/summary.csv
tree >"$T/before"
expect_exit 0 "sweep --dry-run on the same sweep" "$POPC" sweep paper --set run.duration=0.5 --vary controller.variant=none,improved -o made --dry-run
check "  says it would resume, with the runs done" grep -q 'made holds this sweep: 2 of 2 runs succeeded (it would resume)' "$T/out"
expect_exit 2 "sweep --dry-run on another sweep: exit 2" "$POPC" sweep paper --set run.duration=0.6 --vary controller.variant=none,improved -o made --dry-run
check "  says it would be refused" grep -q 'made holds another sweep (it would be refused)' "$T/out"
tree >"$T/after"
check "  the tree is unchanged (no lock, no plan note, no summary rewritten)" cmp -s "$T/before" "$T/after"

expect_exit 2 "--dry-run with --list refused (--list writes)" "$POPC" sweep paper "${VARY[@]}" -o x --dry-run --list
check "  names both" err_has "--dry-run and --list"

tree >"$T/before"
expect_exit 0 "map --dry-run" "$POPC" map paper --variant none,improved --vary environment.damping=0,0.5 -o map --dry-run --criterion passive,diverged
check "  its grid and scan" grep -q '4 lines x 467 stiffness points (100 to 1000000 N/m' "$T/out"
check "  its criteria" grep -q 'criteria diverged passive' "$T/out"
check "  one line per variant and damping" grep -q $'^3\tcontroller.variant=improved environment.damping=0.5$' "$T/out"
tree >"$T/after"
check "  the tree is unchanged" cmp -s "$T/before" "$T/after"
check_summary
