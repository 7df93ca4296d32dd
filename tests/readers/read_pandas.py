#!/usr/bin/env python3
"""Reads popc logs with pandas as docs/READING.md says, and checks every cell
against the log bit for bit (check_cells.py).

    read_pandas.py LOG ENERGY_CSV [LOG ENERGY_CSV]...
"""
import sys

import pandas as pd

from check_cells import check


def read(log):
    # docs/READING.md's recipe, as written there
    return pd.read_csv(log, comment="#", float_precision="round_trip")


def main():
    status = 0
    args = sys.argv[1:]
    for log, energy_csv in zip(args[0::2], args[1::2]):
        d = read(log)
        kinds = {c: "float" if d[c].dtype == "float64" else
                 "int" if d[c].dtype == "int64" else str(d[c].dtype) for c in d.columns}
        columns = {c: [None if (kinds[c] == "float" and v != v) else
                       (float(v) if kinds[c] == "float" else int(v)) for v in d[c].tolist()]
                   for c in d.columns}
        fails = check(log, energy_csv, list(d.columns), kinds, columns)
        for f in fails:
            print(f"FAIL: pandas {pd.__version__}: {log}: {f}")
        if fails:
            status = 1
        else:
            print(f"pandas {pd.__version__}: {log}: {len(d)} rows x {len(d.columns)} columns "
                  f"equal the log bit for bit")
    return status


if __name__ == "__main__":
    sys.exit(main())
