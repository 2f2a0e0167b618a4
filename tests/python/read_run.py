"""A run file as a Python user reads it: h5py and pandas from Debian (python3-h5py,
python3-pandas), the two-line readers of docs/formats.md, checked against ecoterra's own stand
report. Usage: python3 read_run.py RUN.h5 STAND.json"""
import json
import math
import sys

import h5py
import pandas as pd

run, stand_json = sys.argv[1], sys.argv[2]
stand = json.load(open(stand_json))

with h5py.File(run, "r") as f:
    # The two-line readers (docs/formats.md).
    species = list(f["species/name"].asstr()[()])
    plants = pd.DataFrame({k: v[()] for k, v in f["snapshots"][sorted(f["snapshots"])[-1]]["plants"].items()})
    yearly = pd.DataFrame({k: v[()] for k, v in f["series/yearly"].items()})
    daily = pd.DataFrame({k: v[()] for k, v in f["series/daily"].items()})
    area_m2 = float(f.attrs["area_m2"])
    count = f["snapshots"].attrs["count"]
    ecosystem = f["species"].attrs["ecosystem"]
    units = f["series/yearly/basal_area_m2_per_ha"].attrs["units"]
    snapshot_year = f["snapshots"][sorted(f["snapshots"])[-1]].attrs["year"]

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


# Strings are str, integers are integers.
check(all(isinstance(s, str) for s in species) and len(species) == 4, f"species names {species}")
check(isinstance(ecosystem, str), f"ecosystem attribute is {type(ecosystem)}")
check(isinstance(units, str) and units == "m2/ha", f"units attribute {units!r}")
check(int(count) == count and count >= 1, f"snapshot count {count!r}")
check(isinstance(snapshot_year, (int,)) or getattr(snapshot_year, "dtype", None) is not None and snapshot_year.dtype.kind == "i",
      f"snapshot year {snapshot_year!r}")
for col in ("id", "species"):
    check(plants[col].dtype.kind == "i", f"plants.{col} is {plants[col].dtype}")
for col in ("year", "live_plants", "births", "deaths_age", "seeds_dispersed"):
    check(yearly[col].dtype.kind == "i", f"yearly.{col} is {yearly[col].dtype}")
for col in ("day", "year", "day_of_year"):
    check(daily[col].dtype.kind == "i", f"daily.{col} is {daily[col].dtype}")
check(plants["id"].is_unique, "plant ids repeat")
check(plants["species"].between(0, len(species) - 1).all(), "species index out of range")

# pandas recomputes the stand from the plant table: ecoterra's stand report must agree.
trees = plants[plants["dbh_m"] > 0]
ba = (math.pi / 4 * trees["dbh_m"] ** 2).sum() / (area_m2 / 1e4)
check(abs(ba - stand["basal_area_m2_per_ha"]) <= 1e-9 * max(1.0, ba),
      f"basal area {ba} (pandas) against {stand['basal_area_m2_per_ha']} (ecoterra stand)")
check(len(trees) == stand["stems"], f"stems {len(trees)} against {stand['stems']}")
by_species = trees.groupby("species")["dbh_m"].count()
for k, name in enumerate(species):
    check(by_species.get(k, 0) == stand["species"][name]["stems"], f"stems of {name}")
# The yearly series ends at the snapshot's year with the same basal area.
last = yearly.iloc[-1]
check(int(last["year"]) == int(snapshot_year), f"last year {last['year']} against snapshot {snapshot_year}")
check(abs(last["basal_area_m2_per_ha"] - ba) <= 1e-9 * max(1.0, ba), "yearly basal area at the end")

if failures:
    print("\n".join("FAILED: " + f for f in failures))
    sys.exit(1)
print(f"ok: {len(plants)} plants of {len(species)} species, {len(yearly)} years, {len(daily)} days; "
      f"basal area {ba:.4f} m2/ha as ecoterra's stand report")
