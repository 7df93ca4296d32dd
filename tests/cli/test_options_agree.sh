#!/usr/bin/env bash
# --help, the man pages and the bash completion against the programs' own
# option tables (`PROGRAM --complete`: the tables getopt_long parses the
# command line with, include/popc/programs/options.h), for popc, popc-analyze
# and popc-servo-sim, verb by verb. Fails when one of them lists an option
# the table has not, or misses one it has (issue 27: `events` was missing
# from the completion, `--criterion device-passive`, `sweep stats`, and the
# man pages missed options of bench, compare, report, energy and the servo
# simulator).
#
# For each verb (and sub-verb: "sweep merge") of the table:
# - --help: names every option of the table (and its short form), and every
#   option line of the help ("  -q, --quiet ...") is one of the table's; an
#   argument "a|b|c" (the words an option takes) has each word in the help;
# - the man page: names every option of the table as *--NAME* in the verb's
#   own text (its SYNOPSIS lines and its entry under VERBS; popc-analyze's
#   input options, which every verb takes, anywhere in its page), and the
#   verb's SYNOPSIS lines name no option that is not the verb's;
# - the completion offers exactly the table's long options, the verbs
#   exactly the table's verbs (and --help --version), as --help lists them.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
BUILD=${POPC_BUILD_ROOT:?}
T=$(mktemp -d /tmp/popc-options-agree-XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$SRC/tests/check.sh"
mkdir -p "$T/bin" "$T/wd"
ln -s "$POPC" "$T/bin/popc"
ln -s "$BUILD/analysis/popc-analyze" "$T/bin/popc-analyze"
progs="popc popc-analyze"
if [ -x "$BUILD/src/servo_sim/popc-servo-sim" ]; then
  ln -s "$BUILD/src/servo_sim/popc-servo-sim" "$T/bin/popc-servo-sim"
  progs+=" popc-servo-sim"
fi
export PATH="$T/bin:$PATH" POPC_DATA_PATH="$SRC/data"
cd "$T/wd" || exit 1
. "$SRC/data/bash-completion/popc"

# the words of a list, sorted and unique, one line
words() { tr ' ' '\n' | sed '/^$/d' | sort -u | tr '\n' ' ' | sed 's/ $//'; }
# same DESC A B: two word lists equal as sets, the difference shown if not
same() {
  local a b
  a=$(words <<<"$2")
  b=$(words <<<"$3")
  if [ "$a" = "$b" ]; then ok "$1"; else
    bad "$1: only in the table: '$(comm -23 <(tr ' ' '\n' <<<"$a") <(tr ' ' '\n' <<<"$b") | tr '\n' ' ')'; only in the other: '$(comm -13 <(tr ' ' '\n' <<<"$a") <(tr ' ' '\n' <<<"$b") | tr '\n' ' ')'"
  fi
}
# completion PROGRAM LINE: COMPREPLY as words
completion() {
  local fn=_popc
  case $1 in popc-analyze) fn=_popc_analyze ;; popc-servo-sim) fn=_popc_servo_sim ;; esac
  COMP_LINE="$1 $2"
  COMP_POINT=${#COMP_LINE}
  COMP_WORDS=("$1")
  COMPREPLY=()
  "$fn" 2>/dev/null
  printf '%s ' "${COMPREPLY[@]}"
}
# the man page's lines of one verb: its SYNOPSIS lines (from "*PROG VERB*" to
# the next line that starts another synopsis, "++" joins) and its entry
# under VERBS ("*VERB*" at the start of a line, to the next such entry)
man_synopsis() { # PAGE PROG PATH SUBS: SUBS, the path's sub-verbs, are not the path's
  local verb=${3%% *} sub=
  [[ $3 == *" "* ]] && sub=${3#* }
  awk -v verb="*$2 $verb*" -v sub_="$sub" -v subs=" $4 " -v prog="*$2" '
    /^# / { in_syn = ($0 == "# SYNOPSIS"); on = 0; next }
    !in_syn { next }
    /^$/ { on = 0; next }
    index($0, prog " ") == 1 || index($0, prog "*") == 1 {
      on = 0
      rest = ""
      if (index($0, verb) == 1) rest = substr($0, length(verb) + 1)
      else if (sub_ != "" && index($0, substr(verb, 1, length(verb) - 1) " " sub_ "*") == 1) { on = 1 }
      if (!on && index($0, verb) == 1) {
        split(rest, w, /[ *]+/)
        first = w[1] == "" ? w[2] : w[1]
        if (sub_ == "") on = index(subs, " " first " ") == 0
        else on = (first == sub_)
      }
    }
    on { print }' "$1"
}
man_entry() { # PAGE PATH
  awk -v want="*$2*" -v want_sub="*$2 " '
    /^# / { in_verbs = ($0 == "# VERBS" || $0 == "# OPTIONS"); on = 0; next }
    !in_verbs { next }
    /^\*/ { on = (index($0, want) == 1 || index($0, want_sub) == 1) }
    on { print }' "$1"
}
man_options() { grep -oE '\*--?[a-z][a-z0-9-]*\*' | tr -d '*' | sort -u | tr '\n' ' '; }

for prog in $progs; do
  page=$SRC/man/$prog.1.scd
  "$prog" --complete >"$T/table" 2>"$T/err"
  check "$prog --complete: exit 0, a table" test $? -eq 0 -a -s "$T/table"
  # the table in bash's own arrays (few processes: a loaded machine runs this)
  declare -A LONGS=() SHORTS=() LETTER=() VALUES=() FAMILY=()
  paths=() top=
  prev_path= prev_opt=
  while IFS= read -r line; do
    IFS=$'\x1f' read -r kind path opt arg <<<"${line//$'\t'/$'\x1f'}"
    if [ "$kind" = verb ]; then
      paths+=("$path")
      [[ $path != *" "* ]] && top+="$path "
      continue
    fi
    FAMILY[${path%% *}.]+="$opt "
    if [[ $opt == --* ]]; then
      LONGS[_$path]+="$opt "
      # a short form is listed just before its long name
      [[ $prev_path == "$path" && $prev_opt != --* ]] && LETTER[$path $opt]=$prev_opt
      [[ $arg =~ ^[a-z0-9-]+(\|[a-z0-9-]+)+$ ]] && VALUES[$path $opt]=$arg
    else
      SHORTS[_$path]+="$opt "
    fi
    prev_path=$path prev_opt=$opt
  done <"$T/table"
  # a program without verbs has its options under the empty path
  [ ${#paths[@]} -eq 0 ] && paths=("")
  if [ -n "$top" ]; then
    help_verbs=$("$prog" --help | awk '/^verbs:/ { on = 1; next } on && /^  [a-z]/ { print $1 } on && /^$/ { on = 0 }' | tr '\n' ' ')
    same "$prog --help lists the table's verbs" "$top" "$help_verbs"
    same "$prog: the completion offers the table's verbs" "$top --help --version" "$(completion "$prog" "")"
    missing=
    for v in $top; do grep -qE "^\*$v[* ]" "$page" || missing+=" $v"; done
    check "$prog(1) has an entry for every verb${missing:+ (missing:$missing)}" test -z "$missing"
  fi
  # options every verb has: popc-analyze's input options (documented once)
  shared=
  if [ -n "$top" ]; then
    shared=$(for v in $top; do tr ' ' '\n' <<<"${LONGS[_$v]}" | sed '/^$/d' | sort -u; done |
             sort | uniq -c | awk -v n="$(wc -w <<<"$top")" '$1 == n { print $2 }' | tr '\n' ' ')
  fi
  for path in "${paths[@]}"; do
    name="$prog${path:+ $path}"
    longs=${LONGS[_$path]-} shorts=${SHORTS[_$path]-}
    # --help
    # shellcheck disable=SC2086 # the path's words are the verb and sub-verb
    "$prog" $path --help >"$T/help" 2>&1
    check "$name --help: exit 0" test $? -eq 0
    help_text=$(<"$T/help")
    missing=
    for o in $longs $shorts; do
      [[ $help_text =~ (^|[^a-z-])$o([^a-z-]|$) ]] || missing+=" $o"
    done
    check "$name --help names every option of the table${missing:+ (missing:$missing)}" test -z "$missing"
    help_opts=$(sed -nE 's/^ +(-[a-zA-Z0-9], )?(--[a-z][a-z0-9-]*).*/\1 \2/p' "$T/help" | tr -d ',' | tr '\n' ' ')
    # a verb's help may be its sub-verbs' too (popc sweep merge --help is
    # popc sweep's): the options of the verb and its sub-verbs
    family=
    family=${FAMILY[${path%% *}.]-}
    extra=
    for o in $help_opts; do [[ " $family " == *" $o "* ]] || extra+=" $o"; done
    check "  every option line of the help is the table's${extra:+ (not in the table:$extra)}" test -z "$extra"
    for o in $longs; do
      values=${VALUES[$path $o]-}
      [ -n "$values" ] || continue
      missing=
      for w in ${values//|/ }; do [[ $help_text =~ (^|[^a-z-])$w([^a-z-]|$) ]] || missing+=" $w"; done
      check "  $o: the help names each of $values${missing:+ (missing:$missing)}" test -z "$missing"
    done
    # the man page
    if [ -n "$path" ]; then
      subs=
      for p in "${paths[@]}"; do [[ $p == "$path "* ]] && subs+="${p#"$path "} "; done
      man_text=$( { man_synopsis "$page" "$prog" "$path" "$subs"; man_entry "$page" "$path"; } )
      syn_opts=$(man_synopsis "$page" "$prog" "$path" "$subs" | man_options)
      # a sub-verb with its verb's options (bench integrators) is documented with the verb
      parent=${path% *}
      if [[ $parent != "$path" && ${LONGS[_$parent]-} == "$longs" ]]; then
        man_text+=$'\n'$( { man_synopsis "$page" "$prog" "$parent" ""; man_entry "$page" "$parent"; } )
      fi
    else
      man_text=$(<"$page")
      syn_opts=
    fi
    in_man=$(man_options <<<"$man_text")
    missing=
    for o in $longs; do
      case $o in --help | --version) continue ;; esac
      # an option with a short form may go by it (*-q*)
      letter=${LETTER[$path $o]-}
      if [[ " $shared " == *" $o "* ]]; then grep -qF -- "*$o*" "$page" && continue
      else
        [[ " $in_man " == *" $o "* ]] && continue
        [[ -n $letter && " $in_man " == *" $letter "* ]] && continue
      fi
      missing+=" $o"
    done
    check "$prog(1) names every option of '$name'${missing:+ (missing:$missing)}" test -z "$missing"
    extra=
    for o in $syn_opts; do [[ " $longs $shorts " == *" $o "* ]] || extra+=" $o"; done
    check "  its SYNOPSIS of '$name' names only the table's options${extra:+ (not in the table:$extra)}" test -z "$extra"
    # the completion: the words after the verb's
    same "the completion of '$name -' offers the table's long options" "$longs" "$(completion "$prog" "${path:+$path }x -")"
  done
  unset LONGS SHORTS LETTER VALUES FAMILY
done
check_summary
