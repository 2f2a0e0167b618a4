"""Tests of the Python module (docs/python.md), run by CTest with PYTHONPATH at the build tree's
package. Usage: test_module.py ECOTERRA_PROGRAM WORK_FOLDER

Each check compares the module with the program (bit for bit where the program writes the same
thing), or asserts behaviour: views that do not copy, errors with the program's messages, a cut
that keeps the budgets.
"""
import json
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

import ecoterra

program, work = sys.argv[1], Path(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)  # a fresh folder: nothing left from an earlier run
work.mkdir(parents=True)
data = Path(ecoterra.data_dir())
quickstart = data / "scenes/quickstart.json"
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def raises(exc, fn, *contains):
    try:
        fn()
    except exc as e:
        msg = str(e)
        return all(c in msg for c in contains), msg
    except Exception as e:  # a wrong class is a failure too
        return False, f"{type(e).__name__}: {e}"
    return False, "no exception"


def cli(*args):
    subprocess.run([program, *map(str, args)], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)


def checkpoint(path):
    """The whole state a run file holds, as one checkpoint: its /checkpoint/state keeps the series
    in /series, and Run.from_run_file(...).state() puts them back in."""
    return ecoterra.Run.from_run_file(path).state()


# 1. A run stepped from Python equals `ecoterra run` bit for bit, by days, by years, resumed.
cli("run", quickstart, "-o", work / "cli.h5", "--years", 4, "--no-pictures", "--force")
scene = ecoterra.Scene(quickstart, set={"simulation.years": 4})
check(any("physiology keys at their defaults" in n for n in scene.notes),
      "the scene's notes, as the program prints them")
by_years = ecoterra.Run(scene)
by_years.step_year(4)
check(by_years.state() == checkpoint(work / "cli.h5"), "4 years stepped by year == ecoterra run")
by_days = ecoterra.Run(scene)
closed = sum(by_days.step_day() for _ in range(4 * 365))
check(closed == 4 and by_days.state() == by_years.state(), "1460 days by day == 4 years")
half = ecoterra.Run.from_state(scene, ecoterra.Run(scene).state())
half.step_year(2)
resumed = ecoterra.Run.from_state(scene, half.state())
resumed.step_year(2)
check(resumed.state() == by_years.state(), "2 + 2 years through state() == 4 years")
from_file = ecoterra.Run.from_run_file(work / "cli.h5")
check(from_file.years_done == 4 and from_file.state() == by_years.state(),
      "Run.from_run_file reads the program's checkpoint")
summary = ecoterra.run(scene, work / "py.h5", years=4)
check(summary["years_run"] == 4 and checkpoint(work / "py.h5") == checkpoint(work / "cli.h5"),
      "ecoterra.run writes the program's run file")
cli("run", "--resume", work / "py.h5", "--years", 1, "--no-pictures")
by_years.step_year()
check(checkpoint(work / "py.h5") == by_years.state(), "the program resumes ecoterra.run's file")

# 2. Fields are views over the engine's memory: no copy, read-only, following the steps.
theta = by_years.soil_moisture
again = by_years.soil_moisture
check(np.shares_memory(theta, again) and not theta.flags.writeable,
      "soil_moisture is a read-only view, the same memory each time")
before = theta.copy()
by_years.step_day()
check(not np.array_equal(before, theta), "the view follows the engine's steps")
g = by_years.terrain_grid
check(theta.shape == (g["ny"], g["nx"]), "fields are (ny, nx)")
check(np.isnan(by_years.water_table_depth).all(), "no groundwater: the water table is NaN")
with h5py.File(work / "cli.h5") as f:
    dem = f["terrain/elevation"][()]
check(np.array_equal(ecoterra.Run(scene).elevation.astype(dem.dtype), dem),
      "elevation is the run file's terrain (stored as float32)")

# 3. Plants: the snapshot's columns; a cut as a thinning cuts, budgets kept.
plants = by_years.plants()
with h5py.File(work / "cli.h5") as f:
    snap = f["snapshots"][sorted(f["snapshots"].keys())[-1]]
    names = set(snap["plants"].keys())
check(set(plants) == names, "plants() has the snapshot's plant columns")
cut = ecoterra.Run(scene)
cut.step_year(3)
ids = cut.plants()["id"]
n0 = len(ids)
removed = cut.remove_plants(ids[::2].tolist())
check(removed == len(ids[::2]) and len(cut.plants()["id"]) == n0 - removed,
      "remove_plants removes exactly the ids given")
check(not set(ids[::2]) & set(cut.plants()["id"]), "none of the cut ids is left")
cut.step_year()
yearly = cut.yearly()
check(yearly["harvested_stems"][-1] == removed, "the cut counts in the year's harvest")
check(cut.water_residual_relative < 1e-9, "the water budget closes after the cut")
ok, msg = raises(ecoterra.InputError, lambda: cut.remove_plants([ids[0]]), "no living plant",
                 str(ids[0]))
check(ok, f"cutting a plant twice names its id ({msg})")

# 4. Errors are ecoterra's classes with the program's messages; nothing crashes.
ok, msg = raises(ecoterra.InputError,
                 lambda: ecoterra.Scene(quickstart, set={"simulation.yeers": 3}),
                 "simulation.yeers", "did you mean 'simulation.years'")
check(ok, f"an unknown key: InputError with a suggestion ({msg})")
ok, msg = raises(ecoterra.InputError,
                 lambda: ecoterra.Scene(quickstart, set={"simulation.years": -2}),
                 "simulation.years", "-2")
check(ok, f"a value out of range names key and value ({msg})")
ok, msg = raises(ecoterra.InputError, lambda: ecoterra.Scene(work / "none.json"), "none.json",
                 "cannot open")
check(ok, f"a missing scene file: InputError naming it, as the program says ({msg})")
ok, msg = raises(TypeError, lambda: ecoterra.Run("quickstart"))
check(ok, f"a wrong type: TypeError ({msg})")
ok, msg = raises(ecoterra.InputError, lambda: ecoterra.Scene({"terrain": 3}), "terrain")
check(ok, f"a bad dict names the key ({msg})")
closed_run = ecoterra.Run(scene)
closed_run.step_day()
kept_view = closed_run.soil_moisture
kept_values = kept_view.copy()
closed_run.close()
import gc  # noqa: E402

gc.collect()
check(np.array_equal(kept_view, kept_values), "a view outlives close() (it keeps the engine)")
ok, msg = raises(ecoterra.Error, lambda: closed_run.step_day(), "closed")
check(ok and closed_run.closed, f"a closed run raises ecoterra.Error ({msg})")
kept = checkpoint(work / "py.h5")
ok, msg = raises(ecoterra.InputError, lambda: ecoterra.run(scene, work / "py.h5", years=1),
                 "py.h5", "exists")
check(ok, f"ecoterra.run does not overwrite without force ({msg})")
check(checkpoint(work / "py.h5") == kept, "the earlier file is untouched")
ok, msg = raises(ecoterra.CheckpointError,
                 lambda: ecoterra.Run.from_state(scene, b"not a checkpoint"))
check(ok, f"bad state bytes: CheckpointError ({msg})")
check(issubclass(ecoterra.InputError, ecoterra.Error) and issubclass(ecoterra.Error,
                                                                     RuntimeError),
      "InputError < Error < RuntimeError")

# 5. Terrain: the generator and the analysis equal the program's.
spec = {"method": "fbm", "size": 65, "seed": 7, "cell_size_m": 0.5}
t = ecoterra.generate_terrain(spec)
cli("terrain", "generate", "--method", "fbm", "--size", 65, "--seed", 7, "--cell", 0.5, "-o",
    work / "t.h5", "--force")
with h5py.File(work / "t.h5") as f:
    z = f["elevation"][()]
check(np.array_equal(t.z.astype(z.dtype), z), "generate_terrain == ecoterra terrain generate")
t2 = ecoterra.generate_terrain(method="fbm", size=65, seed=7, cell_size_m=0.5)
check(np.array_equal(t.z, t2.z), "keywords == dict")
t.write(work / "t.asc")
back = ecoterra.read_terrain(work / "t.asc")
check(np.allclose(back.z, t.z, atol=1e-6) and back.grid == t.grid, "write and read a raster")
a = t.analyze()
cli("terrain", "analyze", work / "t.h5", "--json", work / "a.json", "--force")
b = json.loads((work / "a.json").read_text())
check(abs(a["rms_m"] - b["rms_m"]) < 1e-6 * max(1, abs(b["rms_m"])),
      "analyze() gives the program's RMS")
arr = np.add.outer(np.arange(20.0), np.zeros(30))
flat = ecoterra.Terrain.from_array(arr, cell_size_m=2)
check(flat.grid["nx"] == 30 and flat.grid["ny"] == 20 and flat.z[5, 3] == 5,
      "from_array keeps (ny, nx) and row order")
ok, msg = raises(ecoterra.InputError, lambda: ecoterra.generate_terrain(method="nope"), "nope")
check(ok, f"an unknown method names it ({msg})")

# 6. A run written from Python is read by the program; mobility and maps equal the program's.
w = ecoterra.Run(scene)
w.step_year(4)
w.write(work / "w.h5")
check(checkpoint(work / "w.h5") == w.state(), "Run.write stores the checkpoint")
cli("stand", work / "w.h5", "--json", work / "w_stand.json")
stand = json.loads((work / "w_stand.json").read_text())
check(stand["stems"] == w.stand()["stems"], "ecoterra stand reads a file Run.write wrote")
mrzr = str(data / "vehicles/mrzr4.json")
ours = ecoterra.mobility(work / "w.h5", vehicle=mrzr, lines=20, seed=5)
cli("mobility", work / "w.h5", "--vehicle", mrzr, "--lines", 20, "--seed", 5, "--json",
    work / "mob.json", "--no-pictures")
theirs = json.loads((work / "mob.json").read_text())
check(ours["smg_mean_m_per_s"] == theirs["smg_mean_m_per_s"], "mobility() == ecoterra mobility")
mp = ecoterra.mobility_map(work / "w.h5", vehicle=mrzr)
cli("mobility", "map", work / "w.h5", "--vehicle", mrzr, "-o", work / "map", "--no-pictures")
theirs = json.loads((work / "map/summary.json").read_text())
check(mp["mean_speed_m_per_s"] == theirs["mean_speed_m_per_s"]
      and mp["speed_mean_m_per_s"].shape == (g["ny"], g["nx"]),
      "mobility_map() == ecoterra mobility map")
ok, msg = raises(ecoterra.InputError, lambda: w.write(work / "w.h5"), "exists")
check(ok, f"Run.write does not overwrite without force ({msg})")

# 7. Ensembles: one member from Python is the program's member; the summary reads in pandas.
man = data / "studies/example.json"
check(ecoterra.ensemble_members(man) == 6, "ensemble_members")
for i in (0, 4):
    rec = ecoterra.run_ensemble_member(man, work / "ens_py", i)
    cli("ensemble", man, "-o", work / "ens_cli", "--member", i)
    theirs = json.loads(next((work / "ens_cli/members").glob(f"{i:06d}*/member.json")).read_text())
    check(rec["status"] == "ok" and rec["metrics"] == theirs["metrics"]
          and rec["seeds"] == theirs["seeds"], f"member {i} from Python == the program's")
summ = ecoterra.ensemble_summary(work / "ens_py")
check(summ["ok"] == 2 and summ["missing"] == 4, "the summary counts the members run")
import pandas as pd  # noqa: E402

members = pd.read_csv(work / "ens_py/summary/members.csv")
check(len(members) == 2 and list(members.member) == [0, 4], "members.csv in pandas: the members run")
ok, msg = raises(ecoterra.InputError, lambda: ecoterra.run_ensemble_member(man, work / "e", 6),
                 "member 6", "[0, 6)")
check(ok, f"a member outside the ensemble ({msg})")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
