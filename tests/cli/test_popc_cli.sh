#!/usr/bin/env bash
# popc run / popc scene as a user runs them: help, exit codes, error messages,
# the log's shape, summaries, the resolved scene, instability and SIGINT.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
FAIL_REALLOC=${1:-}   # tests/cli/fail_realloc.c, built as an LD_PRELOAD shim
T=$(mktemp -d /tmp/popc-cli-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"

expect_exit 0 "popc --help" "$POPC" --help
expect_exit 0 "popc run --help" "$POPC" run --help
check "run --help documents exit codes" grep -q "6 unstable: a" "$T/out"
expect_exit 0 "popc scene --help" "$POPC" scene --help
expect_exit 2 "popc without a verb" "$POPC"
expect_exit 2 "unknown verb" "$POPC" frobnicate
expect_exit 2 "run without a scene" "$POPC" run
expect_exit 2 "run with an unknown option" "$POPC" run "$SRC/data/scenes/paper.ini" --bogus
check "  names the program and verb" err_has "popc run: unrecognized option '--bogus'"
expect_exit 2 "scene show with an unknown option" "$POPC" scene show --bogus
check "  names the program and verb" err_has "popc scene show: unrecognized option '--bogus'"
expect_exit 2 "run with a missing scene file" "$POPC" run "$T/none.ini"
check "  names the missing file" err_has "$T/none.ini"

printf '[run]\nduration = 1\n[operator]\nmass = -3\n' > "$T/bad.ini"
expect_exit 2 "out-of-range key" "$POPC" run "$T/bad.ini" --log "$T/bad.csv"
check "  names file:line, key and range" err_has "$T/bad.ini:4: operator.mass = -3: out of range; allowed [0, 1000] kg"
check "  nothing ran: no log written" test ! -e "$T/bad.csv"
expect_exit 2 "bad --set" "$POPC" run "$SRC/data/scenes/paper.ini" --set encoder.resolution=0
check "  names the key and range" err_has "encoder.resolution = 0: out of range; allowed (0, 1] m"
expect_exit 2 "a run of no tick (0.4 ms at 1 kHz)" "$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=4e-4 --log "$T/notick.csv"
check "  names the keys and the shortest duration" err_has "run.duration = 0.0004 s at run.rate = 1000 Hz is 0.4 control periods, which rounds to no tick; allowed run.duration >= 0.0005 s"
check "  nothing ran: no log written" test ! -e "$T/notick.csv"
expect_exit 0 "half a period rounds to one tick" "$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=5e-4 -q
expect_exit 2 "bad --variant" "$POPC" run "$SRC/data/scenes/paper.ini" --variant fastest
check "  names the option typed and lists the variants" err_has "popc run: --variant 'fastest': unknown value; allowed one of none|po-pc|ref-energy|filtered-velocity|ignore|hold|improved"
expect_exit 2 "bad --axis" "$POPC" run "$SRC/data/scenes/paper.ini" --axis serial
check "  names --axis and the kinds" err_has "popc run: --axis 'serial': unknown value; allowed one of sim|modbus"
expect_exit 2 "the same through --set" "$POPC" run "$SRC/data/scenes/paper.ini" --set controller.variant=fastest
check "  names --set and the key" err_has "popc run: --set controller.variant = 'fastest': unknown value"
expect_exit 0 "--variant wins over --set controller.variant" env -C "$T" "$POPC" run "$SRC/data/scenes/paper.ini" --set controller.variant=improved --variant none --set run.duration=0.1 --summary - -q
check "  ran none" grep -q "^none," "$T/out"

# scene files as users write them: indented keys, CRLF, and errors that name
# their own line
printf '[run]\n  duration = 2\n  rate = 500\n' > "$T/indent.ini"
expect_exit 0 "indented keys are keys (not a continuation of the key above)" "$POPC" scene show "$T/indent.ini"
check "  both read" grep -qx "rate = 500" "$T/out"
printf '[run]\nduration = 2\n    5\n' > "$T/cont.ini"
expect_exit 2 "an indented line without '=' is malformed" "$POPC" scene show "$T/cont.ini"
check "  names the line" err_has "cont.ini:3: malformed line"
printf '[run\nduration = 1\n' > "$T/brk.ini"
expect_exit 2 "a section header without ']'" "$POPC" scene show "$T/brk.ini"
check "  line 1 is malformed (not a later key's error)" err_has "brk.ini:1: malformed line"
printf '[run]\nrate = 500\nduration = 2\nrate = 600\n' > "$T/dup.ini"
expect_exit 2 "a key given twice" "$POPC" scene show "$T/dup.ini"
check "  names both lines" err_has "dup.ini:4: run.rate given twice (first on line 2)"
# 199 characters is libinih's limit; CR LF is a line end, not a 200th character
long=$(printf 'duration = 2 ;%0185d' 0)
printf '[run]\r\n%s\r\nrate = 500\r\n' "$long" > "$T/crlf.ini"
expect_exit 0 "CRLF scene with a 199-character line" "$POPC" scene show "$T/crlf.ini"
check "  both keys read" bash -c "grep -qx 'duration = 2' '$T/out' && grep -qx 'rate = 500' '$T/out'"
printf '[run]\r\n%s0\r\nrate = 500\r\n' "$long" > "$T/crlf2.ini"
expect_exit 2 "CRLF scene with a 200-character line" "$POPC" scene show "$T/crlf2.ini"
check "  names the line and the limit" err_has "crlf2.ini:2: line longer than 199 characters"

# operator intent tables: relative to the scene file, CRLF; bad tables are bad
# input (exit 2) naming file:line, column and range; nothing runs
mkdir -p "$T/tab"
printf '[run]\nduration = 0.2\n[operator]\nintent = table\ntable = xd.csv\n' > "$T/tab/table.ini"
printf 't,x_d\r\n0,-0.01\r\n0.1,0.005\r\n' > "$T/tab/xd.csv"
expect_exit 0 "table intent, path relative to the scene file" "$POPC" run "$T/tab/table.ini" -q --log "$T/tab.csv"
check "  x_true follows the table past 0 m (contact)" awk -F, '/^[0-9]/ && $4 > 0 { e = 1 } END { exit !e }' "$T/tab.csv"
# a relative scene path: the resolved scene names the table absolutely, so
# that it runs from anywhere (here from another directory)
mkdir -p "$T/elsewhere"
(cd "$T" && "$POPC" scene show tab/table.ini > "$T/elsewhere/resolved.ini" 2>"$T/err")
check "resolved scene names the table by its absolute path" grep -qx "table = $T/tab/xd.csv" "$T/elsewhere/resolved.ini"
expect_exit 0 "  and runs from another directory" "$POPC" run "$T/elsewhere/resolved.ini" -q
# a relative path on the command line is from the working directory, and
# made absolute too (one rule: relative to where it is written)
(cd "$T/tab" && "$POPC" scene show --set operator.intent=table --set operator.table=xd.csv --set axis.map=drive.ini > "$T/elsewhere/set.ini" 2>"$T/err")
check "--set operator.table=xd.csv is named absolutely, from the working directory" grep -qx "table = $T/tab/xd.csv" "$T/elsewhere/set.ini"
check "  ... axis.map too" grep -qx "map = $T/tab/drive.ini" "$T/elsewhere/set.ini"
expect_exit 0 "  and the resolved scene runs from another directory" "$POPC" run "$T/elsewhere/set.ini" -q
check "  --help states the rule" bash -c "'$POPC' run --help | grep -q 'on the command line (--set, --map),'"
printf 't,x_d\n0,0\n1,0.01\n0.5,0.02\n' > "$T/tab/back.csv"
expect_exit 2 "times that go back" "$POPC" run "$T/tab/table.ini" --set "operator.table=$T/tab/back.csv" --log "$T/back.csv"
check "  names file:line and both times" err_has "back.csv:4: time 0.5 does not increase (previous 1)"
check "  nothing ran: no log written" test ! -e "$T/back.csv"
printf 't,x_d\n0,0\n1,1e308\n' > "$T/tab/far.csv"
expect_exit 2 "a position beyond operator.x0's range" "$POPC" run "$T/tab/table.ini" --set "operator.table=$T/tab/far.csv"
check "  names file:line, column and range" err_has "far.csv:3: column 2: 1e+308 m is out of range; allowed [-1000, 1000] m"
printf 't,f\n0,0\n1,-2e6\n' > "$T/tab/push.csv"
expect_exit 2 "a force beyond operator.force's range" "$POPC" run "$T/tab/table.ini" --set "operator.table=$T/tab/push.csv" --set operator.table_quantity=force
check "  names the force range" err_has "push.csv:3: column 2: -2e+06 N is out of range; allowed [-1e+06, 1e+06] N"
expect_exit 2 "scene show reads the table too" "$POPC" scene show "$T/tab/table.ini" --set "operator.table=$T/tab/back.csv"
check "  names file:line" err_has "back.csv:4: time 0.5 does not increase"
expect_exit 2 "a missing table" "$POPC" run "$T/tab/table.ini" --set "operator.table=$T/tab/none.csv"
check "  names it" err_has "none.csv: cannot open table: No such file or directory"
mkdir -p "$T/tab/dir.csv"
expect_exit 2 "a directory given as the table (bad input, as a missing one)" "$POPC" run "$T/tab/table.ini" --set "operator.table=$T/tab/dir.csv"
check "  names the path and why" err_has "popc run: $T/tab/dir.csv: cannot read table: Is a directory"

# the paper scene, logged
expect_exit 0 "run paper.ini" "$POPC" run "$SRC/data/scenes/paper.ini" --log "$T/paper.csv" --summary "$T/sum.csv"
check "  summary states the integrator" err_has "integrator: exact"
check "  summary states the speed" err_has "x real time"
check "  log has the provenance header" grep -qx "# source = sim" "$T/paper.csv"
check "  log names the variant" grep -qx "# variant = ref-energy" "$T/paper.csv"
# provenance (issue 27): the build popc --version names, the date (UTC,
# ISO 8601) and the command line, each argument as a shell reads it back
build=$("$POPC" --version | sed -n 's/.*(build \(.*\))$/\1/p')
check "  log names the build ($build)" grep -qxF "# popc_build = $build" "$T/paper.csv"
check "  log has the date" grep -qE '^# date = [0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}Z$' "$T/paper.csv"
check "  log has the command line" grep -qxF "# command = $POPC run $SRC/data/scenes/paper.ini --log $T/paper.csv --summary $T/sum.csv" "$T/paper.csv"
expect_exit 0 "run with arguments a shell must quote" "$POPC" run "$SRC/data/scenes/paper.ini" -q \
  --set run.duration=0.01 --set "operator.speed = 0.01" --log "$T/it's a log.csv"
check "  the command line quoted as a shell reads it" grep -qxF \
  "# command = $POPC run $SRC/data/scenes/paper.ini -q --set run.duration=0.01 --set 'operator.speed = 0.01' --log '$T/it'\''s a log.csv'" "$T/it's a log.csv"
cmd=$(sed -n 's/^# command = //p' "$T/it's a log.csv")
check "  ... and bash reads it back to the same words" \
  test "$(eval "printf '%s|' $cmd")" = "$POPC|run|$SRC/data/scenes/paper.ini|-q|--set|run.duration=0.01|--set|operator.speed = 0.01|--log|$T/it's a log.csv|"
check "  log holds the resolved scene" grep -qx "# \[encoder\]" "$T/paper.csv"
check "  log has the column names" grep -qx "t,x,count,x_true,v,f_e,f_pc,f_c,W,E_ref,flags,E_port" "$T/paper.csv"
rows=$(grep -c '^[0-9-]' "$T/paper.csv")
check "  log has 5001 rows (t = 0 .. 5 s), got $rows" test "$rows" -eq 5001
check "  log ends with the stop reason" test "$(tail -n 1 "$T/paper.csv")" = "# stop = completed"
check "  summary CSV has a header and one row" test "$(wc -l < "$T/sum.csv")" -eq 2
check "  summary CSV header" grep -q "^variant,integrator,substeps,status,ticks,sim_time_s,wall_time_s,realtime_factor" "$T/sum.csv"
expect_exit 0 "second run appends to the summary" "$POPC" run "$SRC/data/scenes/paper.ini" -q --variant improved --summary "$T/sum.csv"
check "  two rows, one header" test "$(wc -l < "$T/sum.csv")" -eq 3
# the scene of each row (issue 27): the file as given or found, and a digest
# of the resolved scene: equal for the same scene under another name
# (popc scene show LOG of the run's log), different for another scene
check "  the header ends with scene,scene_digest" grep -q ",rendered_stiffness,scene,scene_digest$" "$T/sum.csv"
scol() { awk -F, -v r="$2" -v n="$3" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } NR == r + 1 { print $c[n] }' "$1"; }
check "  scene: the file given" test "$(scol "$T/sum.csv" 1 scene)" = "$SRC/data/scenes/paper.ini"
check "  scene_digest: fnv1a- and 16 hex digits" grep -qE ',fnv1a-[0-9a-f]{16}$' "$T/sum.csv"
"$POPC" scene show "$T/paper.csv" >"$T/paper-again.ini" &&
  "$POPC" run "$T/paper-again.ini" -q --set run.duration=0.01 --summary "$T/sum2.csv" &&
  "$POPC" run "$SRC/data/scenes/paper.ini" -q --set run.duration=0.01 --summary "$T/sum2.csv" &&
  "$POPC" run "$SRC/data/scenes/paper.ini" -q --set run.duration=0.02 --summary "$T/sum2.csv" &&
  "$POPC" run "$SRC/data/scenes/paper.ini" -q --set run.duration=0.01 --summary "$T/sum2.json" --summary-format json
check "  the same resolved scene, another file: the same digest" test "$(scol "$T/sum2.csv" 1 scene_digest)" = "$(scol "$T/sum2.csv" 2 scene_digest)"
check "  ... and its own scene name" test "$(scol "$T/sum2.csv" 1 scene)" = "$T/paper-again.ini"
check "  another duration: another digest" test "$(scol "$T/sum2.csv" 2 scene_digest)" != "$(scol "$T/sum2.csv" 3 scene_digest)"
check "  JSON: scene and digest as strings" \
  grep -qF "\"scene\":\"$SRC/data/scenes/paper.ini\",\"scene_digest\":\"$(scol "$T/sum2.csv" 2 scene_digest)\"}" "$T/sum2.json"
check "  -q prints nothing" test ! -s "$T/err"

expect_exit 1 "a summary path that cannot be written" "$POPC" run "$SRC/data/scenes/paper.ini" --summary "$T/nodir/sum.csv" --log "$T/sumlog.csv"
check "  names it and why" err_has "nodir/sum.csv: cannot open the summary for appending: No such file or directory"
check "  refused before the run: no log written" test ! -e "$T/sumlog.csv"

# --summary -: standard output, as --log - (no file named '-')
(cd "$T" && "$POPC" run "$SRC/data/scenes/paper.ini" -q --summary - > "$T/sumout.csv" 2>"$T/err")
check "--summary - writes to standard output (exit $?)" test "$(wc -l < "$T/sumout.csv")" -eq 2
check "  header and row, as the file's" cmp -s <(head -1 "$T/sumout.csv") <(head -1 "$T/sum.csv")
check "  no file named '-'" test ! -e "$T/-"   # (each --summary - here runs in $T)
(cd "$T" && "$POPC" run "$SRC/data/scenes/paper.ini" -q --summary - | cat > "$T/sumpipe.csv")
check "  on a pipe: header and row" test "$(wc -l < "$T/sumpipe.csv")" -eq 2 -a "$(head -1 "$T/sumpipe.csv")" = "$(head -1 "$T/sum.csv")"
(cd "$T" && "$POPC" run "$SRC/data/scenes/paper.ini" -q --summary - >> "$T/sumout.csv")
check "  appended to a file that is not empty: the row only" test "$(wc -l < "$T/sumout.csv")" -eq 3 -a "$(grep -c '^variant,' "$T/sumout.csv")" -eq 1
expect_exit 2 "--log - with --summary -" env -C "$T" "$POPC" run "$SRC/data/scenes/paper.ini" --log - --summary -
check "  says both name standard output" err_has "popc run: --log - and --summary - both name standard output"
check "  nothing ran: nothing on standard output" test ! -s "$T/out"
check "  --help says '-' is standard output" grep -q "'-': standard output, with its header" <("$POPC" run --help)

# log to standard output equals the log file
"$POPC" run "$SRC/data/scenes/paper.ini" -q --log - > "$T/stdout.csv"
check "--log - writes the same log to stdout (but its provenance lines)" cmp -s <(sans_provenance "$T/stdout.csv") <(sans_provenance "$T/paper.csv")

# the resolved scene: every key, reloadable, and it reproduces the run
expect_exit 0 "scene show" "$POPC" scene show "$SRC/data/scenes/fig16.ini" --set run.duration=2
cp "$T/out" "$T/resolved.ini"
check "  every section present" test "$(grep -c '^\[' "$T/resolved.ini")" -eq 8
check "  override applied" grep -qx "duration = 2" "$T/resolved.ini"
check "  defaults explicit" grep -qx "ignore_mode = undo" "$T/resolved.ini"
"$POPC" run "$T/resolved.ini" -q --log "$T/a.csv"
"$POPC" run "$SRC/data/scenes/fig16.ini" -q --set run.duration=2 --log "$T/b.csv"
check "  the resolved scene reproduces the run's rows" cmp -s <(grep -v '^#' "$T/a.csv") <(grep -v '^#' "$T/b.csv")
# popc scene show LOG: the log's own scene, which reruns it bit for bit
# (every shipped scene, with overrides and a variant of its own)
for f in "$SRC"/data/scenes/*.ini; do
  n=$(basename "$f" .ini)
  "$POPC" run "$f" -q --set run.duration=0.5 --set encoder.resolution=2e-6 --variant improved \
    --log "$T/show-$n.csv" 2>/dev/null || { bad "scene show LOG: $n did not run"; continue; }
  expect_exit 0 "scene show LOG ($n)" "$POPC" scene show "$T/show-$n.csv"
  cp "$T/out" "$T/show-$n.ini"
  check "  names the log" grep -qxF "; resolved scene of the log $T/show-$n.csv" "$T/show-$n.ini"
  "$POPC" run "$T/show-$n.ini" -q --log "$T/show-$n.again.csv" 2>/dev/null
  check "  popc run of it makes the same log (but its provenance lines)" \
    cmp -s <(sans_provenance "$T/show-$n.csv") <(sans_provenance "$T/show-$n.again.csv")
done
expect_exit 0 "scene show LOG --set" "$POPC" scene show "$T/show-paper.csv" --set run.duration=2
check "  the override applied" grep -qx "duration = 2" "$T/out"
expect_exit 2 "scene show LOG --set out of range" "$POPC" scene show "$T/show-paper.csv" --set run.rate=1e9
check "  names the key" err_has "run.rate"
expect_exit 0 "scene keys" "$POPC" scene keys
check "  lists controller.pc_bound with its range" grep -q "controller.pc_bound .*allowed (0, 1e+06\] N" "$T/out"
expect_exit 0 "scene keys --help" "$POPC" scene keys --help
check "  prints the usage, not the keys" grep -q "^usage: popc scene" "$T/out"
expect_exit 2 "scene keys with an extra argument" "$POPC" scene keys paper.ini
check "  names the argument" err_has "unexpected argument 'paper.ini'"

# a fixed-step integrator reports its error against the exact discretization
expect_exit 0 "trapezoid run" "$POPC" run "$SRC/data/scenes/paper.ini" --set integrator.method=trapezoid --set integrator.substeps=100 --set run.duration=1
check "  reports its error against exact" err_has "max position error against exact"

# an unstable integrator stops the run with exit 6 and says why, in the log too
expect_exit 6 "explicit Euler on a stiff hand diverges" "$POPC" run "$SRC/data/scenes/paper.ini" \
  --set integrator.method=euler --set integrator.substeps=1 --set operator.stiffness=1e9 \
  --set operator.mass=1e-3 --set device.mass=0 --log "$T/unstable.csv"
check "  names the integrator and a stable alternative" err_has "integrator euler with 1 substeps"
check "  log ends with the reason" grep -q "^# stop = integrator unstable" "$T/unstable.csv"
check "  no non-finite number in the log" bash -c "! grep -qiE 'nan|inf' <(grep -v '^#' '$T/unstable.csv')"

# out of memory while collecting options (the shim makes every realloc fail):
# exit 1 saying so, not a run of the scene without its --set overrides
if [ -n "$FAIL_REALLOC" ] && [ -f "$FAIL_REALLOC" ]; then
  # a sanitizer build loads its runtime first unless told the shim may precede it
  oom_env=(env LD_PRELOAD="$FAIL_REALLOC" ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0")
  expect_exit 1 "popc run --set, out of memory" "${oom_env[@]}" "$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=0.1 --summary "$T/oom.csv" -q
  check "  says so" err_has "popc run: out of memory"
  check "  nothing ran" test ! -e "$T/oom.csv"
  expect_exit 1 "popc scene show --set, out of memory" "${oom_env[@]}" "$POPC" scene show --set run.duration=0.1
  check "  says so" err_has "popc scene show: out of memory"
  check "  no scene printed" test ! -s "$T/out"
  expect_exit 1 "popc sweep --vary, out of memory" "${oom_env[@]}" "$POPC" sweep "$SRC/data/scenes/paper.ini" --vary run.duration=0.1,0.2 -o "$T/oom"
  check "  says so" err_has "popc sweep: out of memory"
  check "  nothing ran" test ! -e "$T/oom"
  expect_exit 1 "popc bench --set, out of memory" "${oom_env[@]}" "$POPC" bench loop --set run.duration=0.1 --min-time 0 --repeat 1
  check "  says so" err_has "popc bench: out of memory"
  check "  nothing measured" test ! -s "$T/out"
else
  echo "# fail_realloc shim not given (argument 1): out-of-memory checks left out"
fi

# One number grammar (popc/util/parse.h) for every option, refused with exit 2
# naming the option: --set took strtod's hex float as a scene value would not,
# --vary ranges, -j and --min-time went through strtod/strtol of their own
P=$SRC/data/scenes/paper.ini
expect_exit 2 "--set run.duration=0x2: hex refused" "$POPC" run "$P" --set run.duration=0x2 -q
check "  names the key" err_has "run.duration = '0x2': not a finite number"
expect_exit 2 "--vary run.duration=0x1:0x2:2: hex range refused" "$POPC" sweep "$P" --vary run.duration=0x1:0x2:2 -o "$T/hexsweep"
check "  names --vary and the key" err_has "--vary run.duration: '0x1:0x2:2': range ends must be finite decimal numbers"
check "  nothing ran" test ! -e "$T/hexsweep"
expect_exit 2 "--vary run.duration=0x1,0x2: hex list refused" "$POPC" sweep "$P" --vary run.duration=0x1,0x2 -o "$T/hexlist"
check "  names the key" err_has "run.duration = '0x1': not a finite number"
expect_exit 2 "--vary with n = 0x2 points refused" "$POPC" sweep "$P" --vary run.duration=0.1:0.2:0x2 -o "$T/hexn"
check "  names n" err_has "the number of points n must be a whole number"
expect_exit 2 "--vary lo:hi:1 with lo != hi refused (hi was dropped)" "$POPC" sweep "$P" --vary run.duration=0.1:0.2:1 -o "$T/onepoint"
check "  says why" err_has "--vary run.duration: '0.1:0.2:1': a range of 1 point holds lo only, not hi"
check "  nothing ran" test ! -e "$T/onepoint"
expect_exit 0 "--vary lo:lo:1 is one value" "$POPC" sweep "$P" --vary run.duration=0.1:0.1:1 --list -o "$T/onevalue"
expect_exit 2 "sweep -j 0x2 refused" "$POPC" sweep "$P" --vary run.duration=0.1,0.2 -j 0x2 -o "$T/hexj"
check "  names -j" err_has "-j '0x2'"
expect_exit 2 "sweep --shard 0x0/2 refused" "$POPC" sweep "$P" --vary run.duration=0.1,0.2 --shard 0x0/2 -o "$T/hexshard"
check "  names --shard" err_has "--shard '0x0/2'"
expect_exit 0 "sweep --shard +1/2.0: a sign and 2.0 are whole numbers as in a scene" "$POPC" sweep "$P" --vary run.duration=0.1,0.2 --shard +1/2.0 --list -o "$T/signshard"
expect_exit 2 "bench --min-time 0x1p-3 refused" "$POPC" bench loop --min-time 0x1p-3 --repeat 1
check "  names --min-time" err_has "--min-time 0x1p-3"
expect_exit 2 "bench --repeat ' 2' refused (no blanks in a number)" "$POPC" bench loop --repeat " 2"
check "  names --repeat" err_has "--repeat  2"
expect_exit 2 "integer scene key 2.0000000000000001 is not whole (it is not 2)" "$POPC" scene show --set integrator.substeps=2.0000000000000001
check "  says so" err_has "integrator.substeps = 2.0000000000000001: not a whole number"
expect_exit 0 "integer scene key 2e0 is 2, as before" "$POPC" scene show --set integrator.substeps=2e0
check "  shows 2" grep -q "^substeps = 2$" "$T/out"

# SIGINT mid-run: the run stops, says so, keeps every completed tick, exits 5.
# The log goes through a pipe that the test reads: the signal is sent once
# 1000 rows have come (no polling of a file), and a 1e5 s run is still going
# then however slow the machine.
mkfifo "$T/int.fifo"
"$POPC" run "$SRC/data/scenes/paper.ini" --set run.duration=100000 --log - >"$T/int.fifo" 2>"$T/int.err" &
pid=$!
exec 3<"$T/int.fifo"
: > "$T/int.csv"
n=0
while IFS= read -r -u 3 line; do
  printf '%s\n' "$line" >> "$T/int.csv"
  case $line in [0-9]*) n=$((n + 1)); [ "$n" -gt 1000 ] && break ;; esac
done
check "SIGINT: sent after 1000 rows (read $n)" test "$n" -gt 1000
kill -INT "$pid"
cat <&3 >> "$T/int.csv"
exec 3<&-
wait "$pid"; rc=$?
check "SIGINT: exit 5 (got $rc)" test "$rc" -eq 5
check "  log ends with the signal stop line" grep -q "^# stop = signal" "$T/int.csv"
last=$(grep '^[0-9]' "$T/int.csv" | tail -n 1)
cells=$(echo "$last" | awk -F, '{print NF}')
check "  last row is complete ($cells cells)" test "$cells" -eq 12

check_summary
