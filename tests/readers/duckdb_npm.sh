# Sourced: installs the pinned DuckDB package (package.json / package-lock.json
# beside this file) with `npm ci` into the directory NPM (set by the sourcing
# script, one per test: two tests that shared one would install over each
# other), once per lock file. Calls skip (exit 77, saying why) when node or
# npm is missing or the npm registry cannot be reached, die on any other npm
# failure; both are the sourcing script's, as is W (its scratch directory).
# (tests/readers/readers.sh has the same steps inline.) Another pinned npm
# package the same way: NPM_LOCK_DIR (the directory of its package.json and
# package-lock.json) and NPM_PACKAGE (the package whose directory in
# node_modules shows it is installed), e.g. tests/readers/polars and
# nodejs-polars (recipes.sh polars).
command -v node >/dev/null && command -v npm >/dev/null ||
	skip "node or npm missing (Debian: apt-get install nodejs npm; tools/install-deps.sh test)"
NPM_HERE=${NPM_LOCK_DIR:-${POPC_SOURCE_ROOT:?}/tests/readers}
NPM_PACKAGE=${NPM_PACKAGE:-@duckdb/node-api}
if ! cmp -s "$NPM_HERE/package-lock.json" "$NPM/package-lock.json" ||
	[ ! -d "$NPM/node_modules/$NPM_PACKAGE" ]; then
	rm -rf "$NPM" && mkdir -p "$NPM" || die "cannot make $NPM"
	cp "$NPM_HERE/package.json" "$NPM_HERE/package-lock.json" "$NPM/"
	if ! (cd "$NPM" && timeout 300 npm ci --no-audit --no-fund --loglevel=error) >"$W/npm.log" 2>&1; then
		rm -rf "$NPM"
		# unreachable registry, or one this machine cannot trust: skip
		if grep -qiE 'ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ECONNRESET|ETIMEDOUT|ENETUNREACH|network|proxy|SELF_SIGNED_CERT|UNABLE_TO_GET_ISSUER_CERT|UNABLE_TO_VERIFY_LEAF_SIGNATURE|CERT_UNTRUSTED' "$W/npm.log"; then
			skip "the npm registry is unreachable, $NPM_PACKAGE not installed: $(grep -m1 -iE 'err' "$W/npm.log")"
		fi
		cat "$W/npm.log" >&2
		die "npm ci of $NPM_HERE/package-lock.json failed"
	fi
fi
