#!/usr/bin/env bash
# Runs docs/READING.md's recipes as written there, with the reader they are
# for, on a real popc log and a real sweep summary, and compares every cell
# the recipe read with the file popc wrote: numbers bit for bit, text as text
# (check_dump.py).
#
#   recipes.sh READER   (pandas numpy duckdb polars r datatable readr octave jq gnuplot;
#                        POPC, POPC_SOURCE_ROOT, POPC_BUILD_ROOT from the environment)
#
# A recipe is the fenced block after a line `<!-- recipe: ID -->` in
# READING.md; the test takes the block's text as it is (awk, below), so the
# doc cannot drift from what is tested. The recipes read `improved.csv` and
# `out/sweep/summary.csv` (`.jsonl`) in the working directory: the test makes
# those files (a 2 s run of the paper scene, improved; a 6-run sweep whose
# first half is variant none, 0.0 in its PC and chatter columns) in a scratch
# directory and runs there. A log recipe leaves what it read in `d` (Octave:
# `names` and `d`), a summary recipe in `s` (Octave: `names`, `s` the text
# and `x` the numbers), DuckDB's node recipe in `rows`, polars' in a
# DataFrame `d` or `s`, jq prints, gnuplot
# plots; the test appends to each the few lines that write that back as CSV,
# a number as "%.17g" (17 digits read back to the same double), and
# check_dump.py compares.
#
# Exit 77 (skip), naming what is missing, when the reader is not installed:
# Debian's python3-pandas, python3-numpy, r-base-core, r-cran-data.table,
# r-cran-readr, octave, jq, gnuplot-nox; for DuckDB and polars (npm packages
# pinned in package-lock.json here and in polars/) node/npm or the npm
# registry (duckdb_npm.sh).
set -u
READER=${1:?reader}
POPC=${POPC:?}
SRC=${POPC_SOURCE_ROOT:?}
HERE=$SRC/tests/readers
DOC=$SRC/docs/READING.md
W=$(mktemp -d "${TMPDIR:-/tmp}/popc-recipes.XXXXXX")
trap 'rm -rf "$W"' EXIT
die() { echo "FAIL: $*" >&2; exit 1; }
skip() { echo "SKIP: $*" >&2; exit 77; }

# the recipe ID's block, as READING.md has it
recipe() {
	awk -v id="$1" '$0 == "<!-- recipe: " id " -->" { f = 1; next }
		f == 1 && /^```/ { f = 2; next } f == 2 && /^```/ { exit } f == 2 { print }' "$DOC" >"$W/$1.recipe"
	[ -s "$W/$1.recipe" ] || die "docs/READING.md has no recipe '$1' (a line <!-- recipe: $1 --> before a fenced block)"
}
# every code block of READING.md is a recipe a test runs, but MATLAB's (no
# licence here; the page says it is untested)
untagged=$(awk '/^```[a-z]/ && $0 != "```matlab" && prev !~ /^<!-- recipe: / { print NR ": " $0 }
	$0 != "" { prev = $0 }' "$DOC")
[ -z "$untagged" ] || die "docs/READING.md: a code block with no <!-- recipe: ID --> line before it, so no test runs it: $untagged"
# Debian's python3 (another python3 first in PATH, e.g. pyenv's, may lack the module)
python_with() {
	PY=
	for p in python3 /usr/bin/python3; do
		"$p" -c "import $1" 2>/dev/null && { PY=$p; return 0; }
	done
	skip "no python3 imports $1 (Debian: apt-get install $2; tools/install-deps.sh test)"
}
r_with() {
	command -v Rscript >/dev/null || skip "Rscript missing (Debian: apt-get install r-base-core; tools/install-deps.sh test)"
	[ -z "$1" ] || Rscript -e "library($1)" >/dev/null 2>&1 ||
		skip "R has no package $1 (Debian: apt-get install $2; tools/install-deps.sh test)"
}
# check_dump.py needs only the standard library: Debian's python3 where there
# is one (a pyenv shim first in PATH takes 2 s to start on a busy machine)
CHECKPY=python3
[ -x /usr/bin/python3 ] && CHECKPY=/usr/bin/python3
check() { "$CHECKPY" "$HERE/check_dump.py" "$@" || status=1; }
status=0

case $READER in
pandas) python_with pandas python3-pandas ;;
numpy) python_with numpy python3-numpy ;;
r) r_with "" "" ;;
datatable) r_with data.table r-cran-data.table ;;
readr) r_with readr r-cran-readr ;;
octave) command -v octave-cli >/dev/null || skip "octave-cli missing (Debian: apt-get install octave; tools/install-deps.sh test)" ;;
jq) command -v jq >/dev/null || skip "jq missing (Debian: apt-get install jq; tools/install-deps.sh test)" ;;
gnuplot) command -v gnuplot >/dev/null || skip "gnuplot missing (Debian: apt-get install gnuplot-nox)" ;;
duckdb)
	NPM=${POPC_BUILD_ROOT:?}/tests/recipes-npm
	. "$HERE/duckdb_npm.sh"
	cp "$HERE/dump_duckdb.mjs" "$NPM/" ;; # node finds node_modules beside the script
polars)
	NPM=${POPC_BUILD_ROOT:?}/tests/recipes-polars-npm NPM_LOCK_DIR=$HERE/polars NPM_PACKAGE=nodejs-polars
	. "$HERE/duckdb_npm.sh"
	;;
*) die "unknown reader $READER" ;;
esac

export POPC_DATA_PATH=$SRC/data
cd "$W" || die "cannot enter $W"
"$POPC" run paper -q --variant improved --set run.duration=2 --log improved.csv || die "run failed"
"$POPC" sweep paper --vary controller.variant=none,improved --vary environment.stiffness=1000:4000:3 \
	--set run.duration=1 -o out/sweep -j 1 -q || die "sweep failed"
grep -q '"pc_rms":0.0,' out/sweep/summary.jsonl || die "the sweep's first rows have no zero pc_rms"
LOG=improved.csv CSV=out/sweep/summary.csv JSONL=out/sweep/summary.jsonl

# Python (pandas, numpy) and R: the reader's recipes go into one script, each
# followed by the lines that write its VAR back to ID.dump (one start of the
# interpreter and its library, not one a recipe: on a busy machine each takes
# seconds); run() runs it and checks each dump against its SOURCE
checks=()
# Python: the recipe, then VAR written back
py_add() { # ID VAR SOURCE
	recipe "$1"
	checks+=("$1" "$3")
	{
		cat "$W/$1.recipe"
		if [ "$READER" = pandas ]; then
			echo "$2.to_csv('$1.dump', index=False, float_format='%.17g')"
		else # a structured array: its field names and rows
			cat <<-EOF
			with open('$1.dump', 'w') as _f:
			    _f.write(','.join($2.dtype.names) + '\n')
			    for _r in $2.tolist():
			        _f.write(','.join('' if isinstance(v, float) and v != v else
			                          '%.17g' % v if isinstance(v, float) else str(v) for v in _r) + '\n')
			EOF
		fi
	} >>recipes.py  # not $READER.py: numpy.py would shadow numpy
}
# R (base, data.table, readr): a data frame, doubles as %.17g, NA as ""
r_add() { # ID VAR SOURCE
	recipe "$1"
	checks+=("$1" "$3")
	{
		cat "$W/$1.recipe"
		cat <<-EOF
		local({
		  x <- as.data.frame($2)
		  cells <- lapply(x, function(c) ifelse(is.na(c), "", if (is.double(c)) sprintf("%.17g", c) else as.character(c)))
		  writeLines(paste(names(x), collapse = ","), "$1.dump")
		  write.table(as.data.frame(cells), "$1.dump", sep = ",", quote = FALSE, row.names = FALSE,
		              col.names = FALSE, append = TRUE)
		})
		EOF
	} >>recipes.R
}
run() { # the script's interpreter, then check_dump.py's options
	"$@" >"$READER.out" 2>&1 || { cat "$READER.out" >&2; die "$READER: the recipes failed (${*: -1}: each recipe, then the lines writing it back)"; }
}
py_run() { run "$PY" recipes.py; for ((i = 0; i < ${#checks[@]}; i += 2)); do check "$READER" "${checks[i + 1]}" "${checks[i]}.dump"; done; }
# R's parsers are 1 ulp off in about a cell in 100,000 (READING.md, "R")
r_run() { run Rscript --vanilla recipes.R; for ((i = 0; i < ${#checks[@]}; i += 2)); do check --max-ulp 1 "$READER" "${checks[i + 1]}" "${checks[i]}.dump"; done; }

case $READER in
pandas)
	py_add pandas-log d "$LOG"
	py_add pandas-summary-csv s "$CSV"
	py_add pandas-summary-json s "$JSONL"
	py_run ;;
numpy)
	py_add numpy-log d "$LOG"
	py_add numpy-summary s "$CSV"
	py_run ;;
r)
	r_add r-log d "$LOG"
	r_add r-summary s "$CSV"
	r_run ;;
datatable)
	r_add datatable-log d "$LOG"
	r_add datatable-summary s "$CSV"
	r_run ;;
readr)
	r_add readr-log d "$LOG"
	r_add readr-summary s "$CSV"
	r_run ;;
octave)
	for id in octave-log octave-summary; do
		recipe "$id"
		{
			cat "$W/$id.recipe"
			echo "f = fopen('$id.dump', 'w'); fprintf(f, '%s\n', strjoin(names, ','));"
			if [ "$id" = octave-log ]; then
				echo "fprintf(f, [strjoin(repmat({'%.17g'}, 1, numel(names)), ','), '\n'], d');"
			else # the text where a cell is no number (and the run ids), else the number
				cat <<-'EOF'
				for i = 1:rows(s)
				  c = s(i, :);
				  for j = 1:numel(names)
				    if !isnan(x(i, j)) && !strcmp(names{j}, 'run') c{j} = sprintf('%.17g', x(i, j)); end
				  end
				  fprintf(f, '%s\n', strjoin(c, ','));
				end
				EOF
			fi
			echo "fclose(f);"
		} >"$id.m"
		octave-cli --no-init-file --quiet "$id.m" >"$id.out" 2>&1 || { cat "$id.out" >&2; die "$id: the recipe failed"; }
		check octave "$([ $id = octave-log ] && echo "$LOG" || echo "$CSV")" "$id.dump"
	done ;;
jq)
	# each line of the block is one command; a line ending in @tsv prints the
	# columns it names ([.[]]: all of them), the max_by line a run id
	recipe jq-summary
	n=0
	while IFS= read -r line; do
		[ -n "$line" ] || continue
		n=$((n + 1))
		bash -c "$line" >"jq$n.dump" || die "jq recipe line $n failed: $line"
		case $line in
		*'[.[]] | @tsv'*)
			check jq "$JSONL" "jq$n.dump" $(head -n 1 "$JSONL" | jq -r 'keys_unsorted | .[]') ;;
		*'@tsv'*)
			cols=$(printf '%s\n' "$line" | sed -e 's/.*\[\(.*\)\].*/\1/' | tr ',' '\n' |
				sed -e 's/^ *\.//' -e 's/ *$//' -e 's/^"\(.*\)"$/\1/')
			check jq "$JSONL" "jq$n.dump" $cols ;;
		*max_by*)
			want=$("$CHECKPY" -c 'import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
print(json.dumps(max(rows, key=lambda r: r["pc_rms_late"])["run"]))' "$JSONL")
			[ "$(cat "jq$n.dump")" = "$want" ] || { echo "FAIL: jq: max_by printed $(cat "jq$n.dump"), want $want"; status=1; } ;;
		*) die "jq recipe line $n: the test knows no check for it: $line" ;;
		esac
	done <"$W/jq-summary.recipe"
	[ $n -ge 2 ] || die "jq recipe: $n lines" ;;
gnuplot)
	# the plot written as a table, 17 digits a number, instead of drawn
	recipe gnuplot-log
	{
		echo "set table 'gnuplot-log.table'; set format x '%.17g'; set format y '%.17g'"
		cat "$W/gnuplot-log.recipe"
		echo "unset table"
	} >gnuplot-log.gp
	gnuplot gnuplot-log.gp >gnuplot-log.out 2>&1 || { cat gnuplot-log.out >&2; die "gnuplot-log: the recipe failed"; }
	awk '!/^#/ && NF >= 2 { print $1 "\t" $2 }' gnuplot-log.table >gnuplot-log.dump
	cols=$(grep -o "using '[^']*':'[^']*'" "$W/gnuplot-log.recipe" | sed -e "s/using '\(.*\)':'\(.*\)'/\1 \2/")
	[ -n "$cols" ] || die "gnuplot-log: no using 'X':'Y' in the recipe"
	check gnuplot "$LOG" gnuplot-log.dump $cols ;;
duckdb)
	for id in duckdb-sql-log duckdb-sql-summary-csv duckdb-sql-summary-json; do
		recipe "$id"
		node "$NPM/dump_duckdb.mjs" "$W/$id.recipe" "$id.dump" || die "$id: the recipe failed"
	done
	check duckdb "$LOG" duckdb-sql-log.dump
	check duckdb "$CSV" duckdb-sql-summary-csv.dump
	check duckdb "$JSONL" duckdb-sql-summary-json.dump
	# the node recipe, a module beside node_modules, run here
	recipe duckdb-node-log
	{
		cat "$W/duckdb-node-log.recipe"
		cat <<-'EOF'
		import { writeFileSync as _write } from 'node:fs';
		import { cell as _cell } from './dump_duckdb.mjs';
		const _names = Object.keys(rows[0]);
		_write('duckdb-node-log.dump', [_names.join(','), ...rows.map((r) => _names.map((n) => _cell(r[n])).join(','))].join('\n') + '\n');
		EOF
	} >"$NPM/recipe-duckdb-node-log.mjs"
	node "$NPM/recipe-duckdb-node-log.mjs" || die "duckdb-node-log: the recipe failed"
	check duckdb-node "$LOG" duckdb-node-log.dump ;;
polars)
	# each recipe a module beside node_modules, run here; the DataFrame's
	# columns written back
	for spec in "polars-log d $LOG" "polars-summary-csv s $CSV" "polars-summary-json s $JSONL"; do
		set -- $spec
		recipe "$1"
		{
			cat "$W/$1.recipe"
			cat <<-EOF
			import { writeFileSync as _write } from 'node:fs';
			const _cell = (v) => (v === null || v === undefined ? ''
			  : typeof v === 'number' ? (Object.is(v, -0) ? '-0' : String(v)) : String(v));
			const _rows = $2.toRecords();
			_write('$1.dump', [$2.columns.join(','), ..._rows.map((r) => $2.columns.map((n) => _cell(r[n])).join(','))].join('\n') + '\n');
			EOF
		} >"$NPM/recipe-$1.mjs"
		node "$NPM/recipe-$1.mjs" || die "$1: the recipe failed"
		check polars "$3" "$1.dump"
	done ;;
esac
[ $status -eq 0 ] && echo "$READER: every recipe of docs/READING.md read every cell as popc wrote it"
exit $status
