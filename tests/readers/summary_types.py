"""Reads popc summaries with pandas as docs/READING.md says and checks each
column's dtype: float64 for every real column, int64 for the counts, the run
ids and names as strings (run "0000" stays "0000"). A --vary column (its
name is a scene key, section.key) holds the values as written and is not
checked.

    python3 summary_types.py FILE...   (.csv or .jsonl)
"""
import sys

import pandas as pd

TEXT = {"run", "log", "variant", "integrator", "scene", "scene_digest"}
INT = {"ticks", "substeps", "status", "exit_status", "chatter_intervals", "limit_cycle"}


def read(path):
    # docs/READING.md's recipes, as written there
    if path.endswith(".jsonl"):
        return pd.read_json(path, lines=True, dtype=False, precise_float=True)
    return pd.read_csv(path, dtype={"run": str})


fails = 0
for path in sys.argv[1:]:
    d = read(path)
    bad = []
    for name in d.columns:
        got = str(d[name].dtype)
        if "." in name:
            continue
        want = "object" if name in TEXT else "int64" if name in INT else "float64"
        if got != want:
            bad.append(f"{name} {got} (want {want})")
    if "run" in d.columns and not all(isinstance(r, str) and len(r) == 4 for r in d["run"]):
        bad.append(f"run ids {list(d['run'])[:3]}... are not the 4-digit strings")
    print(f"pandas: {path}: {len(d)} rows, {len(d.columns)} columns"
          + (": " + "; ".join(bad) if bad else ", every type right"))
    fails += bool(bad)
sys.exit(1 if fails else 0)
