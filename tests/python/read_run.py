"""A run file as a Python user reads it: h5py and pandas from Debian (python3-h5py,
python3-pandas), the two-line readers of docs/formats.md, checked against ecoterra's own stand
report. Usage: python3 read_run.py RUN.h5 STAND.json
Life forms (docs/formats.md): trees, shrubs and objects are rows of the plant table, grasses the
ground_cover rasters; pandas and numpy recompute the stand report's undergrowth from them."""
import json
import math
import sys

import h5py
import numpy as np
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
    forms = list(f["species/life_form"].asstr()[()])
    last_snapshot = f["snapshots"][sorted(f["snapshots"])[-1]]
    # Float rasters are float32 (docs/formats.md): averaged here in float64.
    ground = last_snapshot["ground_cover"][()].astype(np.float64)
    by_species_cover = {int(k): v[()].astype(np.float64)
                        for k, v in last_snapshot.get("ground_cover_by_species", {}).items()}

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


# Strings are str, integers are integers.
check(all(isinstance(s, str) for s in species) and len(species) >= 1, f"species names {species}")
check(len(forms) == len(species) and set(forms) <= {"tree", "shrub", "grass", "object"},
      f"species life forms {forms}")
check(isinstance(ecosystem, str), f"ecosystem attribute is {type(ecosystem)}")
check(isinstance(units, str) and units == "m2/ha", f"units attribute {units!r}")
check(int(count) == count and count >= 1, f"snapshot count {count!r}")
check(isinstance(snapshot_year, (int,)) or getattr(snapshot_year, "dtype", None) is not None and snapshot_year.dtype.kind == "i",
      f"snapshot year {snapshot_year!r}")
for col in ("id", "species", "life_form"):
    check(plants[col].dtype.kind == "i", f"plants.{col} is {plants[col].dtype}")
for col in ("year", "live_plants", "births", "deaths_age", "seeds_dispersed"):
    check(yearly[col].dtype.kind == "i", f"yearly.{col} is {yearly[col].dtype}")
for col in ("day", "year", "day_of_year"):
    check(daily[col].dtype.kind == "i", f"daily.{col} is {daily[col].dtype}")
check(plants["id"].is_unique, "plant ids repeat")
check(plants["species"].between(0, len(species) - 1).all(), "species index out of range")

# Each plant's life form is its species' (0 tree, 1 shrub, 3 object); grasses are never plants.
code = {"tree": 0, "shrub": 1, "grass": 2, "object": 3}
check((plants["life_form"] == plants["species"].map(lambda k: code[forms[k]])).all(),
      "plant life forms against their species'")
check((plants["life_form"] != 2).all(), "a grass in the plant table")
check((plants.loc[plants["life_form"] != 0, "dbh_m"] == 0).all(), "a shrub or object with a DBH")
check((plants.loc[plants["life_form"] == 0, "stem_diameter_m"] == plants.loc[plants["life_form"] == 0, "dbh_m"]).all(),
      "a tree's stem diameter is not its DBH")

# pandas recomputes the stand from the plant table: ecoterra's stand report must agree.
trees = plants[(plants["life_form"] == 0) & (plants["dbh_m"] > 0)]
ba = (math.pi / 4 * trees["dbh_m"] ** 2).sum() / (area_m2 / 1e4)
check(abs(ba - stand["basal_area_m2_per_ha"]) <= 1e-9 * max(1.0, ba),
      f"basal area {ba} (pandas) against {stand['basal_area_m2_per_ha']} (ecoterra stand)")
check(len(trees) == stand["stems"], f"stems {len(trees)} against {stand['stems']}")
by_species = trees.groupby("species")["dbh_m"].count()
for k, name in enumerate(species):
    if forms[k] == "tree":
        check(by_species.get(k, 0) == stand["species"][name]["stems"], f"stems of {name}")
    else:
        check(name not in stand["species"], f"{forms[k]} {name} among the stand's species")

# The undergrowth block: shrubs and objects counted by pandas, ground cover averaged by numpy.
under = stand["undergrowth"]
area_ha = area_m2 / 1e4
shrubs = plants[plants["life_form"] == 1]
check(abs(len(shrubs) / area_ha - under["shrubs_per_ha"]) <= 1e-9 * max(1.0, under["shrubs_per_ha"]),
      f"shrubs per ha {len(shrubs) / area_ha} against {under['shrubs_per_ha']}")
crown = (math.pi * shrubs["crown_radius_m"] ** 2).sum() / area_m2
check(abs(crown - under["shrub_crown_cover_fraction"]) <= 1e-9 * max(1.0, crown), "shrub crown cover")
objects = int((plants["life_form"] == 3).sum())
check(abs(objects / area_ha - under["objects_per_ha"]) <= 1e-9 * max(1.0, objects), "objects per ha")
# The stored covers are float32 (relative rounding 6e-8 each), the summary's mean is of doubles.
check(abs(ground.mean() - under["ground_cover_fraction"]) <= 1e-7, f"ground cover {ground.mean()} against {under['ground_cover_fraction']}")
check(((ground >= 0) & (ground <= 1 + 1e-12)).all(), "ground cover outside 0..1")
check(sorted(by_species_cover) == [k for k, form in enumerate(forms) if form == "grass"],
      "one ground-cover raster per grass species")
if by_species_cover:
    # Each stored cover is rounded to float32 (relative 6e-8) on its own.
    check(np.allclose(sum(by_species_cover.values()), ground, rtol=0, atol=1e-6),
          "the species' covers do not add up to ground_cover")
for entry in under["ground_cover_by_species"]:
    k = species.index(entry["species"])
    check(abs(by_species_cover[k].mean() - entry["cover_fraction"]) <= 1e-9, f"cover of {entry['species']}")
# The yearly series ends at the snapshot's year with the same basal area.
last = yearly.iloc[-1]
check(int(last["year"]) == int(snapshot_year), f"last year {last['year']} against snapshot {snapshot_year}")
check(abs(last["basal_area_m2_per_ha"] - ba) <= 1e-9 * max(1.0, ba), "yearly basal area at the end")
check(abs(last["shrubs_per_ha"] - under["shrubs_per_ha"]) <= 1e-9 * max(1.0, under["shrubs_per_ha"]),
      "yearly shrubs per ha at the end")
# The yearly value is the engine's (double), the stand's the stored float32 rasters' mean.
check(abs(last["ground_cover_fraction"] - under["ground_cover_fraction"]) <= 1e-6, "yearly ground cover at the end")

if failures:
    print("\n".join("FAILED: " + f for f in failures))
    sys.exit(1)
print(f"ok: {len(plants)} plants ({len(shrubs)} shrubs, {objects} objects) of {len(species)} species, {len(yearly)} years, {len(daily)} days; "
      f"basal area {ba:.4f} m2/ha as ecoterra's stand report")
