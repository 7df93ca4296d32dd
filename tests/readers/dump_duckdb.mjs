// Runs a SQL recipe of docs/READING.md (recipes.sh takes it from there) with
// DuckDB (the @duckdb/node-api package, pinned in package.json) in the
// working directory, and writes what it read back as CSV for check_dump.py:
// the column names, then the rows, a double as JavaScript's shortest text
// that reads back to it (and -0 as "-0"), an integer in decimal, NULL as "".
//   node dump_duckdb.mjs RECIPE.sql OUT.csv
// Imported (recipes.sh's node recipe): exports cell(), nothing run.
import { DuckDBInstance } from '@duckdb/node-api';
import { readFileSync, writeFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';

export const cell = (v) => (v === null || v === undefined ? ''
	: typeof v === 'number' ? (Object.is(v, -0) ? '-0' : String(v)) : String(v));

if (process.argv[1] === fileURLToPath(import.meta.url)) {
	const [sqlFile, out] = process.argv.slice(2);
	const sql = readFileSync(sqlFile, 'utf8').trim().replace(/;$/, '');
	const con = await (await DuckDBInstance.create(':memory:')).connect();
	const result = await con.runAndReadAll(sql);
	const lines = [result.columnNames().join(',')];
	for (const row of result.getRows()) lines.push(row.map(cell).join(','));
	writeFileSync(out, lines.join('\n') + '\n');
}
