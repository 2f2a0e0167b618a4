"""What the Python layer costs (docs/python.md): the 1 ha quickstart grown from Python against the
program, and the numpy views against copies.

    PYTHONPATH=build/python python3 bench/bench_python.py [--years 30] [--repeats 3] [--busy]

Prints medians of --repeats runs: the program (`ecoterra run`, which also writes its run file),
ecoterra.run() (the same, in this process), a Run stepped year by year and day by day from
Python; then the time to take soil_moisture (a view) against a copy of it on a 1024 x 1024 grid.
--busy runs the figures beside one busy process (a second Python spinning on the other core).
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import ecoterra

ap = argparse.ArgumentParser()
ap.add_argument("--years", type=int, default=30)
ap.add_argument("--repeats", type=int, default=3)
ap.add_argument("--busy", action="store_true")
args = ap.parse_args()
root = Path(__file__).resolve().parent.parent
program = Path(os.environ.get("ECOTERRA_PROGRAM", root / "build/apps/ecoterra/ecoterra"))
scene_file = Path(ecoterra.data_dir()) / "scenes/quickstart.json"
years = args.years
busy = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if args.busy else None


def median_time(fn):
    times = []
    for _ in range(args.repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


tmp = Path(tempfile.mkdtemp())
scene = ecoterra.Scene(scene_file, set={"simulation.years": years})


def cli():
    subprocess.run([str(program), "run", str(scene_file), "-o", str(tmp / "c.h5"), "--years",
                    str(years), "--no-pictures", "--force"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def in_process():
    ecoterra.run(scene, tmp / "p.h5", force=True)


def by_year():
    r = ecoterra.Run(scene)
    for _ in range(years):
        r.step_year()


def by_day():
    r = ecoterra.Run(scene)
    for _ in range(years * 365):
        r.step_day()


try:
    rows = [("ecoterra run (the program)", median_time(cli)),
            ("ecoterra.run() from Python", median_time(in_process)),
            ("Run.step_year() x years", median_time(by_year)),
            ("Run.step_day() x days", median_time(by_day))]
    base = rows[0][1]
    print(f"1 ha quickstart, {years} years, median of {args.repeats}"
          f"{', beside one busy process' if busy else ', quiet'}:")
    for name, t in rows:
        print(f"  {name:32s} {t:7.2f} s   {t / base:5.3f} x the program")
    # Views against copies on a large grid: a 1024 x 1024 terrain's run.
    big = ecoterra.Scene(scene_file, set={"terrain.generate.size": 1024,
                                          "terrain.generate.cell_size_m": 1.0,
                                          "vegetation.initial": "bare"})
    r = ecoterra.Run(big)
    r.step_day()
    n = 2000
    t = time.perf_counter()
    for _ in range(n):
        v = r.soil_moisture
    view_us = (time.perf_counter() - t) / n * 1e6
    t = time.perf_counter()
    for _ in range(20):
        c = np.array(r.soil_moisture)
    copy_us = (time.perf_counter() - t) / 20 * 1e6
    print(f"soil_moisture on {v.shape[0]} x {v.shape[1]} cells: the view {view_us:.1f} us "
          f"(shares the engine's memory: {np.shares_memory(v, r.soil_moisture)}), a copy "
          f"{copy_us:.0f} us ({copy_us / view_us:.0f} x)")
    del c
finally:
    if busy:
        busy.kill()
