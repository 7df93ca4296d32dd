#!/usr/bin/env bash
# Behaviour digests: what popc and popc-analyze write for every scene in
# data/scenes/ and every controller variant, for each integrator, intent,
# environment and Table I reading, and for a small sweep, reduced to SHA-256
# digests and compared with tests/behaviour/digests.txt. A refactoring must
# leave every digest as it is; a change of behaviour updates the file in the
# same commit (--update), so the diff shows which outputs it changed.
#
#   behaviour.sh [--update]      (POPC, POPC_ANALYZE, POPC_SOURCE_ROOT from the environment)
#
# Digested: each log byte for byte but its provenance lines (popc_build,
# date, command: they differ from run to run; check.sh's sans_provenance);
# each run summary row without its scene and scene_digest cells (paths of
# this checkout: tests/cli/test_popc_cli.sh checks them); each run summary row without its three
# wall-clock cells (wall_time_s, realtime_factor, ns_per_tick); popc-analyze
# compare (CSV), energy -o and chatter on the logs; the sweep's summary.csv
# without its last cell (wall_time_s).
set -u
POPC=${POPC:?POPC must name the popc program}
ANALYZE=${POPC_ANALYZE:?POPC_ANALYZE must name popc-analyze}
SRC=${POPC_SOURCE_ROOT:?}
DIGESTS=$SRC/tests/behaviour/digests.txt
. "$SRC/tests/check.sh" # sans_provenance
update=0
[ "${1:-}" = --update ] && update=1
T=$(mktemp -d /tmp/popc-behaviour-XXXXXX)
trap 'rm -rf "$T"' EXIT
out=$T/digests.txt
: >"$out"
failed=0

digest() { # name, file
	printf '%s %s\n' "$1" "$(sha256sum <"$2" | cut -d' ' -f1)" >>"$out"
}
# the summary without the wall-clock cells, found by their header names
summary_nowall() {
	awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) drop[i] = ($i == "wall_time_s" || $i == "realtime_factor" || $i == "ns_per_tick" || $i == "scene" || $i == "scene_digest") }
		{ s = ""; for (i = 1; i <= NF; i++) if (!drop[i]) s = s (s == "" ? "" : ",") $i; print s }' "$1"
}
case_run() { # name, popc run arguments...
	local name=$1; shift
	local log=$T/$name.csv sum=$T/$name.summary.csv
	"$POPC" run "$@" --log "$log" --summary "$sum" -q 2>"$T/$name.err"
	local rc=$?
	printf '%s exit %s\n' "$name" "$rc" >>"$out"
	# the log without its provenance lines (build, date, command line)
	[ -f "$log" ] && { sans_provenance "$log" >"$log.fixed"; digest "$name.log" "$log.fixed"; }
	[ -f "$sum" ] && { summary_nowall "$sum" >"$sum.nowall"; digest "$name.summary" "$sum.nowall"; }
	return 0
}

variants="none po-pc ref-energy filtered-velocity ignore hold improved pc-off-reversals energy-bounding windowed-po"
adm_variants="none parallel-pc parallel-ignore parallel-hold parallel-improved"
for scene in "$SRC"/data/scenes/*.ini; do
	s=$(basename "$scene" .ini)
	if grep -q '^causality *= *admittance' "$scene"; then # docs/ADMITTANCE.md
		for v in $adm_variants; do
			case_run "$s.$v" "$scene" --set admittance.variant="$v"
		done
		continue
	fi
	if grep -qE '^architecture *= *position-(force|position)' "$scene"; then # docs/TELEOPERATION.md
		for pc in on off; do
			case_run "$s.tdpa-$pc" "$scene" --set teleop.tdpa=$pc
		done
		# the drift laws, and an excess (position-force: they correct a velocity command)
		grep -q '^architecture *= *position-force' "$scene" &&
			for law in artigas2010 coelho2018; do
				case_run "$s.drift-$law" "$scene" --set teleop.drift=$law --set teleop.excess=0.001
			done
		continue
	fi
	for v in $variants; do
		case_run "$s.$v" "$scene" --variant "$v"
	done
done
P=$SRC/data/scenes/paper.ini
for m in trapezoid rk4 semi-implicit-euler euler; do
	case_run "paper.$m" "$P" --set integrator.method=$m --set integrator.substeps=10 --set run.duration=2
done
case_run paper.literal "$P" --variant improved --set controller.ignore_mode=literal
case_run paper.sine "$P" --variant improved --set operator.intent=sine --set operator.amplitude=0.015 \
	--set operator.frequency=0.7 --set operator.x0=-0.005
case_run paper.force "$P" --variant hold --set operator.intent=force --set operator.force=2
case_run paper.spring "$P" --variant po-pc --set environment.kind=spring --set environment.damping=0.2
case_run paper.rate "$P" --variant ignore --set run.rate=2500 --set encoder.resolution=2e-6
case_run paper.delay1 "$P" --variant none --set run.delay_ticks=1 --set environment.stiffness=300
case_run paper.delay2 "$P" --variant improved --set run.delay_ticks=2
case_run paper.stiff.energy-bounding "$P" --variant energy-bounding --set environment.stiffness=1e6

# the analyser on the paper scene's logs
logs=()
for v in $variants; do logs+=("$T/paper.$v.csv"); done
"$ANALYZE" compare "${logs[@]}" --format csv >"$T/compare.csv" 2>/dev/null
echo "compare exit $?" >>"$out"
sed 's|^[^,]*/||' "$T/compare.csv" >"$T/compare.rel" # the log column without the temp dir
digest compare "$T/compare.rel"
"$ANALYZE" chatter "${logs[@]}" >"$T/chatter.txt" 2>/dev/null
echo "chatter exit $?" >>"$out"
sed "s|$T/||g" "$T/chatter.txt" >"$T/chatter.rel"
digest chatter "$T/chatter.rel"
"$ANALYZE" energy "$T/paper.filtered-velocity.csv" --observer eq2 -o "$T/energy.csv" >"$T/energy.txt" 2>/dev/null
echo "energy exit $?" >>"$out"
sed "s|$T/||g" "$T/energy.csv" >"$T/energy.rel"
digest energy "$T/energy.rel"
sed "s|$T/||g" "$T/energy.txt" >"$T/energy.txt.rel"
digest energy.text "$T/energy.txt.rel"

# a small sweep
"$POPC" sweep "$P" --vary controller.variant=none,ref-energy,improved,pc-off-reversals,energy-bounding,windowed-po \
	--vary environment.stiffness=500,2000 --set run.duration=2 -o "$T/sweep" -j 2 -q --no-log 2>/dev/null
echo "sweep exit $?" >>"$out"
sed 's/,[^,]*$//' "$T/sweep/summary.csv" >"$T/sweep.nowall"
digest sweep "$T/sweep.nowall"

if [ $update = 1 ]; then
	cp "$out" "$DIGESTS"
	echo "behaviour: wrote $(wc -l <"$DIGESTS") lines to $DIGESTS"
	exit 0
fi
if ! cmp -s "$out" "$DIGESTS"; then
	echo "behaviour: outputs differ from tests/behaviour/digests.txt (< expected, > now):"
	diff "$DIGESTS" "$out" | grep '^[<>]' | head -40
	failed=1
fi
n=$(wc -l <"$out")
[ $failed = 0 ] && echo "behaviour: all $n digests equal"
exit $failed
