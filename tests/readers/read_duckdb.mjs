// Reads a popc log with DuckDB (the @duckdb/node-api package, pinned in
// package.json) as docs/READING.md says, and dumps what it read as JSON for
// check_cells.py: the column names, 'float' (DOUBLE) or 'int' (an integer
// type) or the type's name per column, and every cell (a double as the 16
// hex digits of its bits, big-endian; an integer as a decimal string; an
// empty cell as null).
//   node read_duckdb.mjs LOG OUT.json
import { DuckDBInstance } from '@duckdb/node-api';
import { writeFileSync } from 'node:fs';

const [log, out] = process.argv.slice(2);
const instance = await DuckDBInstance.create(':memory:');
const con = await instance.connect();
const quoted = "'" + log.replaceAll("'", "''") + "'";
// docs/READING.md's recipe, as written there
const result = await con.runAndReadAll(`SELECT * FROM read_csv(${quoted}, comment = '#')`);
const names = result.columnNames();
const types = result.columnTypes().map((t) => t.toString());
const kinds = types.map((t) => (t === 'DOUBLE' ? 'float'
	: ['BIGINT', 'INTEGER', 'SMALLINT', 'TINYINT', 'UBIGINT', 'UINTEGER', 'HUGEINT'].includes(t)
		? 'int' : t));
const buf = new DataView(new ArrayBuffer(8));
const hex = (v) => {
	buf.setFloat64(0, v);
	return buf.getBigUint64(0).toString(16).padStart(16, '0');
};
const columns = result.getColumns();
const cells = columns.map((col, j) => col.map((v) => (v === null ? null
	: kinds[j] === 'float' ? hex(v) : String(v))));
writeFileSync(out, JSON.stringify({ names, types, kinds, cells }));
console.log(`duckdb: ${log}: ${columns[0]?.length ?? 0} rows, ${names.length} columns: ` +
	names.map((n, j) => `${n} ${types[j]}`).join(', '));
