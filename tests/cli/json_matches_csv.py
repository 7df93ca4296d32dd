#!/usr/bin/env python3
"""A JSON Lines summary equals its CSV twin cell for cell, as read by Python's
json module (strict: NaN, Infinity and -Infinity are refused, as RFC 8259
has no such numbers).

    json_matches_csv.py CSV JSONL [--skip NAME,...] [--want-null NAME,...] [--digits]

Each JSON line is one object whose keys are the CSV header's names, in its
order; each value is the row's cell: null for an empty cell, a string equal
to the cell's text, or a number whose double has the same 64 bits as the
cell's (an integer equal to an integer cell). --skip leaves out cells that
differ by nature between the two files (wall-clock times of two runs);
--want-null names columns that must be null somewhere (the test means it).
--digits: a number must have the very digits of its cell, as text (the
--format json of a table: the same digits as its CSV), not only its bits.
"""
import csv
import json
import struct
import sys


def refuse_constant(name):
    raise ValueError(f"{name} is not JSON")


def bits(v):
    return struct.pack("<d", float(v))


def main():
    args = sys.argv[1:]
    csv_path, jsonl_path = args[0], args[1]
    skip, want_null = set(), set()
    digits = "--digits" in args
    args = [a for a in args if a != "--digits"]
    for k in range(2, len(args), 2):
        (skip if args[k] == "--skip" else want_null).update(args[k + 1].split(","))
    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    with open(jsonl_path, "rb") as f:
        raw = f.read()
    raw.decode("utf-8")  # valid UTF-8, or this raises
    lines = raw.decode().splitlines()
    fails = []
    if len(lines) != len(rows):
        fails.append(f"{len(lines)} JSON lines, {len(rows)} CSV rows")
    nulls = set()
    for i, (line, row) in enumerate(zip(lines, rows)):
        obj = json.loads(line, parse_constant=refuse_constant)
        # the numbers' own text, to compare digits (a string stays a str:
        # parse_float and parse_int see numbers only)
        num_text = json.loads(line, parse_constant=refuse_constant,
                              parse_float=lambda t: ("number", t), parse_int=lambda t: ("number", t))
        if list(obj.keys()) != header:
            fails.append(f"line {i + 1}: keys {list(obj.keys())}, want {header}")
            continue
        for name, cell in zip(header, row):
            if name in skip:
                continue
            v = obj[name]
            if digits and isinstance(num_text[name], tuple):
                ok = num_text[name][1] == cell
            elif v is None:
                nulls.add(name)
                ok = cell == ""
            elif isinstance(v, str):
                ok = v == cell
            elif isinstance(v, bool):
                ok = False
            elif isinstance(v, int) and not any(c in cell for c in ".eE"):
                ok = cell != "" and v == int(cell)
            else:
                ok = cell != "" and bits(v) == bits(cell)
            if not ok:
                fails.append(f"line {i + 1} {name}: JSON {v!r}, CSV {cell!r}")
    for name in want_null - nulls:
        fails.append(f"column {name}: never null, the test wants an empty cell there")
    for f in fails[:20]:
        print(f"FAIL: {jsonl_path}: {f}")
    if not fails:
        print(f"{jsonl_path}: {len(lines)} objects equal {csv_path} cell for cell")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
