// Reads popc summaries with DuckDB (the @duckdb/node-api package, pinned in
// package.json) as docs/READING.md says, with sample_size = 1 (the first row
// stands for the first 20480 of a big sweep), and checks each column's type:
// DOUBLE for every real column, an integer type for the counts, VARCHAR for
// the run ids and names (run "0000" stays "0000"). A --vary column (its name
// is a scene key, section.key) holds the values as written and is not checked.
//   node summary_types.mjs FILE...   (.csv or .jsonl, absolute paths)
import { DuckDBInstance } from '@duckdb/node-api';

const TEXT = new Set(['run', 'log', 'variant', 'integrator', 'scene', 'scene_digest']);
const INT = new Set(['ticks', 'substeps', 'status', 'exit_status', 'chatter_intervals', 'limit_cycle']);
const INTS = ['BIGINT', 'INTEGER', 'SMALLINT', 'TINYINT', 'UBIGINT', 'UINTEGER', 'HUGEINT'];
const instance = await DuckDBInstance.create(':memory:');
const con = await instance.connect();
let fails = 0;
for (const path of process.argv.slice(2)) {
	const quoted = "'" + path.replaceAll("'", "''") + "'";
	const reader = path.endsWith('.jsonl') ? 'read_json' : 'read_csv';
	const result = await con.runAndReadAll(`SELECT * FROM ${reader}(${quoted}, sample_size = 1)`);
	const names = result.columnNames();
	const types = result.columnTypes().map((t) => t.toString());
	const bad = [];
	names.forEach((name, j) => {
		if (name.includes('.'))
			return;
		const t = types[j];
		const ok = TEXT.has(name) ? t === 'VARCHAR' : INT.has(name) ? INTS.includes(t) : t === 'DOUBLE';
		if (!ok)
			bad.push(`${name} ${t} (want ${TEXT.has(name) ? 'VARCHAR' : INT.has(name) ? 'an integer' : 'DOUBLE'})`);
	});
	const j = names.indexOf('run');
	if (j >= 0) {
		const ids = result.getColumns()[j].map(String);
		if (!ids.every((r) => /^[0-9]{4}$/.test(r)))
			bad.push(`run ids ${ids.slice(0, 3)}... are not the 4-digit strings`);
	}
	console.log(`duckdb: ${path}: ${result.getColumns()[0]?.length ?? 0} rows, ${names.length} columns` +
		(bad.length ? ': ' + bad.join('; ') : ', every type right'));
	if (bad.length)
		fails++;
}
process.exit(fails ? 1 : 0);
