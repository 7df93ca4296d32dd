#!/usr/bin/env python3
"""Compares what a reader (pandas, DuckDB) read of a popc log with the log's
own values, every cell bit for bit.

    check_cells.py LOG ENERGY_CSV READ_JSON     (READ_JSON: read_duckdb.mjs's dump)
    as a module: check(log, energy_csv, names, kinds, columns) -> failures

The references for each cell: the log's text read by Python's float() (an
independent correctly rounded parser), and for t, x, f_c, W and E_ref also
popc-analyze's values (popc's own reader), from `popc-analyze energy -o`
(t,x,f_c,W_logged,E_ref_logged). A reader's column is a list of doubles
(float columns), ints (count, flags) or None (an empty cell); a double is
compared by its 64 bits, a failure names the cell with its repr.
"""
import json
import struct
import sys

INT_COLUMNS = ("count", "flags")


def bits(v):
    return struct.pack("<d", v)


def data_lines(path):
    with open(path) as f:
        return [l.rstrip("\n") for l in f if not l.startswith("#")]


def check(log, energy_csv, names, kinds, columns):
    """names: the reader's column names; kinds: 'float' or 'int' per column;
    columns: name -> list of values. Returns a list of failure lines."""
    lines = data_lines(log)
    header = lines[0].split(",")
    rows = [l.split(",") for l in lines[1:]]
    fails = []
    if names != header:
        return [f"column names {names}, want {header}"]
    for name in header:
        want = "int" if name in INT_COLUMNS else "float"
        if kinds[name] != want:
            fails.append(f"column {name} typed {kinds[name]}, want {want}")
        if len(columns[name]) != len(rows):
            fails.append(f"column {name}: {len(columns[name])} rows, want {len(rows)}")
    if fails:
        return fails
    for j, name in enumerate(header):
        col = columns[name]
        for i, row in enumerate(rows):
            text, got = row[j], col[i]
            if text == "":
                ok = got is None
            elif name in INT_COLUMNS:
                ok = isinstance(got, int) and got == int(text)
            else:
                ok = isinstance(got, float) and bits(got) == bits(float(text))
            if not ok:
                fails.append(f"row {i + 1} column {name}: read {got!r}, the log says {text}")
                if len(fails) >= 10:
                    return fails
    # popc's own reader, through popc-analyze energy -o
    e_lines = data_lines(energy_csv)
    e_header = e_lines[0].split(",")
    e_rows = [l.split(",") for l in e_lines[1:]]
    if len(e_rows) != len(rows):
        return fails + [f"popc-analyze energy -o has {len(e_rows)} rows, the reader {len(rows)}"]
    for e_name, name in (("t", "t"), ("x", "x"), ("f_c", "f_c"), ("W_logged", "W"),
                         ("E_ref_logged", "E_ref")):
        k = e_header.index(e_name)
        col = columns[name]
        for i, row in enumerate(e_rows):
            if bits(col[i]) != bits(float(row[k])):
                fails.append(f"row {i + 1} column {name}: read {col[i]!r}, popc-analyze read {row[k]}")
                if len(fails) >= 10:
                    return fails
    return fails


def main():
    log, energy_csv, dump = sys.argv[1:4]
    with open(dump) as f:
        d = json.load(f)
    columns = {}
    for name, kind, cells in zip(d["names"], d["kinds"], d["cells"]):
        if kind == "float":  # 16 hex digits of the double's bits, big-endian
            columns[name] = [None if c is None else struct.unpack(">d", bytes.fromhex(c))[0]
                             for c in cells]
        else:
            columns[name] = [None if c is None else int(c) for c in cells]
    fails = check(log, energy_csv, d["names"], dict(zip(d["names"], d["kinds"])), columns)
    for f in fails:
        print(f"FAIL: {log}: {f}")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
