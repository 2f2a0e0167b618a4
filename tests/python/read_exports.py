"""The stem and dead-wood tables as a Python user reads them: pandas' read_csv and read_json of
`ecoterra export vegetation|deadwood -o X.csv|X.json` give the same frame, and the run's
/diagnosis (h5py) counts the same living plants per species as the plant table.
Usage: python3 read_exports.py RUN.h5 STEMS.csv STEMS.json DEAD.csv DEAD.json"""
import json
import sys

import h5py
import numpy as np
import pandas as pd

run, stems_csv, stems_json, dead_csv, dead_json = sys.argv[1:6]
failures = []


def same(csv, js, what):
    c = pd.read_csv(csv)
    j = pd.read_json(js)
    if len(c) == 0 and len(j) == 0:  # an empty table: the JSON is [] and has no columns
        return c
    if list(c.columns) != list(j.columns) or len(c) != len(j):
        failures.append(f"{what}: columns {list(c.columns)} / {list(j.columns)}, rows {len(c)} / {len(j)}")
        return c
    for col in c.columns:
        if c[col].dtype.kind == "f" or j[col].dtype.kind == "f":
            # the CSV holds 10 significant digits
            if not np.allclose(c[col].astype(float), j[col].astype(float), rtol=1e-9, atol=1e-12):
                failures.append(f"{what}.{col} differs")
        elif not (c[col].astype(str) == j[col].astype(str)).all():
            failures.append(f"{what}.{col} differs")
    return c


stems = same(stems_csv, stems_json, "stems")
same(dead_csv, dead_json, "dead wood")
if len(stems) == 0:
    failures.append("no stems")
with h5py.File(run, "r") as f:
    diag = json.loads(f["diagnosis"].attrs["json"])
    source = json.loads(f["terrain/elevation"].attrs["source_json"])
living = {s["species"]: s["living_at_end"] for s in diag["species"]}
counted = stems[stems["life_form"].isin(["tree", "shrub"])].groupby("species").size().to_dict()
for name, n in living.items():
    if n != counted.get(name, 0):
        failures.append(f"{name}: /diagnosis says {n} living, the stem table {counted.get(name, 0)}")
if diag["verdict"] not in ("ok", "empty", "sparse", "missed_target"):
    failures.append(f"verdict {diag['verdict']}")
if not isinstance(source, dict):
    failures.append(f"source_json is {source!r}")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"exports read by pandas: {len(stems)} stems, {len(living)} species; verdict {diag['verdict']}")
