#!/usr/bin/env bash
# The bash completion (data/bash-completion/popc) as bash calls it: COMP_LINE
# and COMP_POINT set, the completion function run, COMPREPLY read. Verbs,
# options (read from each verb's option table, `PROGRAM --complete`), variant
# names, scene keys and an enum key's names for --set and --vary, installed
# scene and map names. That the tables, --help and the man pages agree:
# test_options_agree.sh.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
BUILD=${POPC_BUILD_ROOT:?}
T=$(mktemp -d /tmp/popc-completion-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
# the programs side by side on PATH, as installed: popc-analyze's completion
# asks the popc beside it for the variant names
mkdir -p "$T/bin" "$T/wd"
ln -s "$POPC" "$T/bin/popc"
ln -s "$BUILD/analysis/popc-analyze" "$T/bin/popc-analyze"
[ -x "$BUILD/src/servo_sim/popc-servo-sim" ] && ln -s "$BUILD/src/servo_sim/popc-servo-sim" "$T/bin/popc-servo-sim"
export PATH="$T/bin:$PATH" POPC_DATA_PATH="$SRC/data"
cd "$T/wd" || exit 1
. "$SRC/data/bash-completion/popc"

# complete FUNCTION PROGRAM LINE: COMPREPLY, sorted, space-separated, in $got
complete_line() {
	local fn=$1 prog=$2
	COMP_LINE="$prog $3"
	COMP_POINT=${#COMP_LINE}
	COMP_WORDS=("$prog")
	COMPREPLY=()
	"$fn" 2>/dev/null
	got=$(printf '%s\n' "${COMPREPLY[@]}" | sort | tr '\n' ' ')
	got=${got% }
}
# offers DESC FUNCTION PROGRAM LINE EXPECTED: the completions are exactly EXPECTED
offers() {
	complete_line "$2" "$3" "$4"
	if [ "$got" = "$5" ]; then ok "$1"; else bad "$1: '$4' gave '$got', expected '$5'"; fi
}
# includes DESC FUNCTION PROGRAM LINE WORD...: the completions hold each WORD
includes() {
	local what=$1 fn=$2 prog=$3 line=$4 w missing=
	shift 4
	complete_line "$fn" "$prog" "$line"
	for w in "$@"; do [[ " $got " == *" $w "* ]] || missing+=" $w"; done
	if [ -z "$missing" ]; then ok "$what"; else bad "$what: '$line' lacks$missing (gave '$got')"; fi
}

offers "verbs" _popc popc "" "--help --version bench map run scene sweep"
offers "a verb's start" _popc popc "sw" "sweep"
includes "popc map's options, from its --help" _popc popc "map --" --variant --vary --stiffness --tol --scan --criterion --port-tol --shard
offers "map --criterion: the criteria" _popc popc "map paper --criterion " "chatter device-passive diverged limit-cycle passive stable"
offers "  after a comma" _popc popc "map paper --criterion passive,d" "passive,device-passive passive,diverged"
includes "popc run's options, from its table" _popc popc "run --" --set --variant --log --summary --axis --map --connect --free-run --rt --channel-log --quiet --help
complete_line _popc popc "run --"
# each option line's first long option, once (a continuation line may start
# with an option it names)
n_help=$("$POPC" run --help | sed -nE 's/^ +(-[a-z], )?(--[a-z][a-z-]*).*/\2/p' | sort -u | wc -l)
n_got=$(wc -w <<<"$got")
check "  every option of the help ($n_help), no more ($n_got)" test "$n_got" -eq "$n_help"
offers "--variant: the variant names" _popc popc "run paper --variant i" "ignore improved"
complete_line _popc popc "run paper --variant "
check "  all ten" test "$(wc -w <<<"$got")" -eq 10
offers "map --variant: the admittance variants too" _popc popc "map zwidth-admittance --variant parallel-" "parallel-hold parallel-ignore parallel-improved parallel-pc"
offers "installed scene names" _popc popc "run fig1" "fig10 fig14 fig16"
printf '[run]\n' > fig1-local.ini
offers "  and files" _popc popc "run fig1" "fig1-local.ini fig10 fig14 fig16"
rm fig1-local.ini
offers "--map: installed map names" _popc popc "run paper --map ge" "generic"
offers "--axis" _popc popc "run paper --axis " "modbus sim"
complete_line _popc popc "run paper --set "
n_keys=$("$POPC" scene keys | grep -c '^  [^ ]')
check "--set: every scene key ($n_keys), with its '='" test "$(wc -w <<<"$got")" -eq "$n_keys" -a -z "$(tr ' ' '\n' <<<"$got" | grep -v '=$')"
offers "  a key's start" _popc popc "run paper --set controller.v" "controller.variant="
offers "  an enum key's names, after the '=' (bash keeps the word's head)" _popc popc "run paper --set controller.variant=f" "filtered-velocity"
offers "  integrator.method" _popc popc "run paper --set integrator.method=e" "euler exact"
offers "--vary: names after the last comma" _popc popc "sweep paper --vary controller.variant=none,i" "none,ignore none,improved"
offers "sweep: --shard" _popc popc "sweep paper --sh" "--shard"
offers "sweep merge's options" _popc popc "sweep merge --a" "--allow-other-build"
offers "scene actions" _popc popc "scene " "keys list show"
offers "scene list --maps" _popc popc "scene list --m" "--maps"
offers "bench kinds" _popc popc "bench " "integrators log loop"
offers "popc-analyze verbs" _popc_analyze popc-analyze "" "--help --version chatter compare energy events replay report teleop"
offers "  events --format" _popc_analyze popc-analyze "events x.csv --format " "csv json text"
offers "sweep's sub-verbs and scenes" _popc popc "sweep st" "stats"
offers "  sweep stats' options" _popc popc "sweep stats DIR --f" "--format"
offers "  sweep stats --format" _popc popc "sweep stats DIR --format " "csv json markdown text"
offers "  replay --variant: names and all (an admittance log's and a teleoperation log's too)" _popc_analyze popc-analyze "replay x.csv --variant " "all energy-bounding filtered-velocity hold ignore improved none parallel-hold parallel-ignore parallel-improved parallel-pc pc-off-reversals po-pc ref-energy tdpa-off tdpa-on windowed-po"
includes "  a verb's options, from its table" _popc_analyze popc-analyze "energy --" --observer --check --output --column --set
offers "  --format" _popc_analyze popc-analyze "compare x.csv --format m" "markdown"
if [ -e "$T/bin/popc-servo-sim" ]; then
  offers "popc-servo-sim --map" _popc_servo_sim popc-servo-sim "--map c" "cia402-lohi"
  offers "  --scene" _popc_servo_sim popc-servo-sim "--map generic --scene no" "no-pc"
  includes "  options, from its table" _popc_servo_sim popc-servo-sim "--" --map --listen --scene --lockstep --map-keys
fi
check_summary
