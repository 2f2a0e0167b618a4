"""Grow a forest from Python, thin it, read it into pandas, drive through it and export it.

    PYTHONPATH=build/python python3 docs/examples/python_forest.py OUT_FOLDER

(docs/python.md; the test suite runs this file as it is.)
"""
import sys
from pathlib import Path

import ecoterra

out = Path(sys.argv[1] if len(sys.argv) > 1 else "python_forest")
out.mkdir(parents=True, exist_ok=True)
data = Path(ecoterra.data_dir())

# The 1 ha quickstart scene, grown for 25 years, one year at a time.
scene = ecoterra.Scene(data / "scenes/quickstart.json", set={"simulation.years": 25})
run = ecoterra.Run(scene)
for year in range(25):
    run.step_year()
theta = run.soil_moisture  # the engine's own memory: no copy, read-only
print(f"year {run.years_done}: root-zone water {theta.mean():.3f} m3/m3 on {theta.shape} cells")

# The stand into pandas; a thinning from below: every tree under 10 cm goes.
plants = ecoterra.plants_frame(run)
trees = plants[plants.life_form == 0]
small = trees[trees.dbh_m < 0.10]
print(f"{len(trees)} trees, basal area {run.stand()['basal_area_m2_per_ha']:.1f} m2/ha; "
      f"cutting {len(small)} under 10 cm")
run.remove_plants(small.id.tolist())
print(f"after the thinning: {len(ecoterra.plants_frame(run))} plants, "
      f"basal area {run.stand()['basal_area_m2_per_ha']:.1f} m2/ha")
run.step_year()  # one more year after the cut

by_species = ecoterra.plants_frame(run).groupby("species_name").dbh_m.agg(["count", "mean"])
print(by_species)

# A run file of the stand as it stands, then a mobility figure and a glTF scene from it.
run.write(out / "thinned.h5", force=True)
smg = ecoterra.mobility(out / "thinned.h5", vehicle=str(data / "vehicles/mrzr4.json"), lines=50)
print(f"MRZR speed made good: {smg['smg_mean_m_per_s']:.2f} m/s over 50 lines")
folders = ecoterra.export_scene(out / "thinned.h5", out / "scene", formats=["gltf"], force=True)
print("glTF scene in", folders[0])
