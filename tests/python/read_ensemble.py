"""An ensemble's summary as a Python user reads it (docs/ensembles.md): pandas on the CSV tables
and h5py on summary.h5, checked against each other and against the members' own records.
Usage: python3 read_ensemble.py OUT"""
import json
import math
import os
import sys

import h5py
import pandas as pd

out = sys.argv[1]
members = pd.read_csv(os.path.join(out, "summary/members.csv"), float_precision="round_trip")
agg = pd.read_csv(os.path.join(out, "summary/aggregate.csv"), float_precision="round_trip")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


check(len(members) == 6, f"6 members, got {len(members)}")
check(members["seed"].dtype.kind == "i", f"seeds read as integers, got {members['seed'].dtype}")
check((members["status"] == "ok").all(), "every member ok")
for _, row in members.iterrows():
    rec = json.load(open(os.path.join(out, "members", f"{int(row['member']):06d}", "member.json")))
    check(rec["seed"] == int(row["seed"]), f"member {row['member']}: seed {rec['seed']} != {row['seed']}")
    smg = rec["metrics"]["mobility.smg_mean_m_per_s"]
    check(smg == row["mobility.smg_mean_m_per_s"], f"member {row['member']}: SMG {smg} != {row['mobility.smg_mean_m_per_s']}")
# The aggregate is the members' mean, per competition model (pandas' groupby against ecoterra's).
mean = members.groupby("vegetation.competition")["stand.basal_area_m2_per_ha"].mean()
sd = members.groupby("vegetation.competition")["stand.basal_area_m2_per_ha"].std()
for _, row in agg.iterrows():
    c = row["vegetation.competition"]
    check(math.isclose(row["stand.basal_area_m2_per_ha.mean"], mean[c], rel_tol=1e-12), f"{c}: mean")
    check(math.isclose(row["stand.basal_area_m2_per_ha.sd"], sd[c], rel_tol=1e-9), f"{c}: sd")
    q = members[members["vegetation.competition"] == c]["stand.stems_per_ha"].quantile([0.1, 0.5, 0.9])
    for p, name in zip([0.1, 0.5, 0.9], ["p10", "p50", "p90"]):
        check(math.isclose(row[f"stand.stems_per_ha.{name}"], q[p], rel_tol=1e-12), f"{c}: {name}")
# Paired changes (replicate r shares its seeds across combinations): pandas' own differences.
paired = pd.read_csv(os.path.join(out, "summary/paired.csv"), float_precision="round_trip")
check(len(paired) > 0, "paired rows")
by = members.set_index(["combination", "replicate"])["stand.basal_area_m2_per_ha"]
for _, row in paired.iterrows():
    d = (by.loc[int(row["combination"])] - by.loc[int(row["from_combination"])]).dropna()
    check(int(row["pairs"]) == len(d), f"paired {row['combination']}: pairs")
    check(math.isclose(row["stand.basal_area_m2_per_ha.change_mean"], d.mean(), rel_tol=1e-9, abs_tol=1e-12),
          f"paired {row['combination']}: change mean")
    check(math.isclose(row["stand.basal_area_m2_per_ha.change_sd"], d.std(), rel_tol=1e-9, abs_tol=1e-12),
          f"paired {row['combination']}: change sd")
with h5py.File(os.path.join(out, "summary/summary.h5"), "r") as f:
    h5 = pd.DataFrame({k: v.asstr()[()] if v.dtype.kind == "O" else v[()] for k, v in f["members"].items()})
    check(f["members/mobility.smg_mean_m_per_s"].attrs["units"] == "m/s", "SMG units m/s")
    check(int(f.attrs["ok"]) == 6, "6 ok in the attributes")
h5 = h5.set_index("member").sort_index()
csv = members.set_index("member").sort_index()
for col in ["seed", "stand.basal_area_m2_per_ha", "mobility.smg_mean_m_per_s", "vegetation.competition"]:
    check((h5[col] == csv[col]).all(), f"column {col}: HDF5 and CSV differ")
if failures:
    print("FAILED:\n  " + "\n  ".join(failures))
    sys.exit(1)
print(f"ok: {len(members)} members read with pandas and h5py; aggregates match pandas' groupby")
