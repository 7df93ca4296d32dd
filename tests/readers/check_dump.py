#!/usr/bin/env python3
"""Compares a reader's dump of what it read with the file popc wrote, every
cell: the numbers bit for bit, the text as text.

    check_dump.py [--max-ulp N] READER SOURCE DUMP [COLUMN...]

SOURCE is a popc log or summary CSV (`#` lines are comments; the first other
line names the columns), or a summary JSON Lines file (.jsonl: the first
object's keys name the columns, null is an empty cell). DUMP is what the
reader's recipe read, written back by the test (recipes.sh) as CSV: the
column names, then one line per row, a number as "%.17g" (or any text that
reads back to the same double), an empty or missing cell as "", NA, NaN or
null. With COLUMNs, the source's columns are those only (a recipe that
reads some columns: jq's), and the dump has no header line (tab-separated,
jq's @tsv).

The reference for a cell is its text in SOURCE read by Python's float()
(correctly rounded; popc writes the shortest text that reads back to its
double, so that is popc's value), or for JSON Python's json module (also
correctly rounded). A cell passes when the dump's text equals the source's,
or both read as numbers with the same 64 bits. The column `run` (a sweep's
run id, `0000`) is text: it must come back as written. On failure it prints
how many cells differ and by how many ulp at most, and the first few. --max-ulp N lets a number be up to N ulp off (R's parsers,
docs/READING.md says by how much) and says how many were.
"""
import json
import math
import struct
import sys

MISSING = ("", "NA", "NaN", "nan", "NAN", "null", "<NA>")


def bits(v):
    return struct.unpack("<q", struct.pack("<d", v))[0]


def ulps(a, b):
    """How many doubles apart a and b are (same sign assumed; else a large number)."""
    ia, ib = bits(a), bits(b)
    if (ia < 0) != (ib < 0):
        return abs(ia & 0x7FFFFFFFFFFFFFFF) + abs(ib & 0x7FFFFFFFFFFFFFFF)
    return abs(ia - ib)


def number(text):
    try:
        v = float(text)
    except ValueError:
        return None
    return v if math.isfinite(v) else None


def source_table(path):
    if path.endswith(".jsonl"):
        with open(path) as f:
            objs = [json.loads(l) for l in f if l.strip()]
        names = list(objs[0].keys())
        rows = []
        for o in objs:
            row = []
            for n in names:
                v = o.get(n)
                row.append("" if v is None else v if isinstance(v, str) else
                           repr(v) if isinstance(v, float) else str(v))
            rows.append(row)
        return names, rows
    with open(path) as f:
        lines = [l.rstrip("\n") for l in f if not l.startswith("#")]
    return lines[0].split(","), [l.split(",") for l in lines[1:]]


def main():
    args = sys.argv[1:]
    max_ulp = 0
    if args[0] == "--max-ulp":
        max_ulp, args = int(args[1]), args[2:]
    reader, source, dump = args[:3]
    only = args[3:]
    names, rows = source_table(source)
    with open(dump) as f:
        dlines = [l.rstrip("\r\n") for l in f]
    if only:
        missing = [c for c in only if c not in names]
        if missing:
            print(f"FAIL: {reader}: {source}: no column {', '.join(missing)} (it has {', '.join(names)})")
            return 1
        idx = [names.index(c) for c in only]
        names, rows = only, [[r[k] for k in idx] for r in rows]
        drows = [l.split("\t") for l in dlines]
    else:
        dnames = [c.strip('"') for c in dlines[0].split(",")]
        if dnames != names:
            print(f"FAIL: {reader}: {source}: column names {dnames}, want {names}")
            return 1
        drows = [[c.strip('"') for c in l.split(",")] for l in dlines[1:]]
    if len(drows) != len(rows):
        print(f"FAIL: {reader}: {source}: {len(drows)} rows, want {len(rows)}")
        return 1
    bad, worst, shown, cells, near = 0, 0, [], 0, 0
    for i, (row, drow) in enumerate(zip(rows, drows)):
        if len(drow) != len(names):
            print(f"FAIL: {reader}: {source}: row {i + 1}: {len(drow)} cells, want {len(names)}")
            return 1
        for name, want, got in zip(names, row, drow):
            cells += 1
            if got == want or (want == "" and got in MISSING):
                continue
            w, g = number(want), number(got)
            if name != "run" and w is not None and g is not None:
                if bits(w) == bits(g):
                    continue
                if ulps(w, g) <= max_ulp:
                    near += 1
                    continue
                worst = max(worst, ulps(w, g))
            bad += 1
            if len(shown) < 5:
                shown.append(f"row {i + 1} column {name}: read {got}, the file says {want}")
    if bad:
        print(f"FAIL: {reader}: {source}: {bad} of {cells} cells differ"
              + (f", numbers by up to {worst} ulp" if worst else ""))
        for s in shown:
            print(f"  {s}")
        return 1
    print(f"{reader}: {source}: {len(rows)} rows x {len(names)} columns, every cell as popc wrote it"
          + (f" (within {max_ulp} ulp: {near} cells off)" if max_ulp else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
