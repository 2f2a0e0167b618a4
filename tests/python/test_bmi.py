"""ecoterra's BMI from Python, driven as the Basic Model Interface 2.0 specification describes it
(https://bmi.readthedocs.io), and coupled through BMI calls only to a small rainfall model that
is not ecoterra's. Usage: test_bmi.py WORK_FOLDER (PYTHONPATH at the build tree's package)."""
import json
import shutil
import sys
from pathlib import Path

import numpy as np

import ecoterra

work = Path(sys.argv[1])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
data = Path(ecoterra.data_dir())
scene = json.loads((data / "scenes/quickstart.json").read_text())
scene["terrain"]["generate"]["size"] = 24
scene["simulation"]["years"] = 1
scene["vegetation"]["ecosystem"] = str(data / "ecosystems/humid_subtropical_broadleaf.json")
config = work / "scene.json"
config.write_text(json.dumps(scene))
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def drive(model, config_file):
    """A generic BMI driver: only the specification's calls and what it promises."""
    model.initialize(str(config_file))
    check(model.get_start_time() <= model.get_current_time() <= model.get_end_time(),
          "start <= current <= end")
    names = model.get_output_var_names()
    check(len(names) == model.get_output_item_count(), "output count")
    check(len(model.get_input_var_names()) == model.get_input_item_count(), "input count")
    for name in names:
        grid = model.get_var_grid(name)
        size = model.get_grid_size(grid)
        dtype = np.dtype(model.get_var_type(name))
        check(model.get_var_nbytes(name) == size * model.get_var_itemsize(name) == size *
              dtype.itemsize, f"{name}: nbytes = size x itemsize")
        values = model.get_value(name, np.empty(size, dtype))
        inds = np.array([0, size - 1], dtype=np.int32)
        at = model.get_value_at_indices(name, np.empty(2, dtype), inds)
        check(np.array_equal(at, values[inds]), f"{name}: values at indices")
        rank = model.get_grid_rank(grid)
        if model.get_grid_type(grid) == "uniform_rectilinear":
            shape = model.get_grid_shape(grid, np.empty(rank, np.int32))
            spacing = model.get_grid_spacing(grid, np.empty(rank))
            origin = model.get_grid_origin(grid, np.empty(rank))
            check(int(np.prod(shape)) == size, f"{name}: prod(shape) == size")
            x = model.get_grid_x(grid, np.empty(shape[-1]))
            y = model.get_grid_y(grid, np.empty(shape[0]))
            check(np.allclose(np.diff(x), spacing[-1]) and np.allclose(np.diff(y), spacing[0])
                  and x[0] == origin[-1] and y[0] == origin[0], f"{name}: x, y from origin")
    t0 = model.get_current_time()
    model.update()
    check(model.get_current_time() == t0 + model.get_time_step(), "update: one time step")
    model.update_until(t0 + 5)
    check(model.get_current_time() == t0 + 5, "update_until")
    return names


m = ecoterra.Bmi()
names = drive(m, config)
check("soil_water__volume_fraction" in names and "land_surface__elevation" in names,
      "CSDMS standard names")
check(m.get_var_units("soil_water__volume_fraction") == "m3 m-3", "units")
ptr = m.get_value_ptr("soil_water__volume_fraction")
check(np.shares_memory(ptr, m.get_value_ptr("soil_water__volume_fraction"))
      and not ptr.flags.writeable, "get_value_ptr: a read-only view, no copy")
before = ptr.copy()
m.update()
check(not np.array_equal(before, ptr), "the view follows the model")

# The same days through ecoterra.Run: BMI updates are the engine's days bit for bit.
r = ecoterra.Run(ecoterra.Scene(config))
for _ in range(int(m.get_current_time())):
    r.step_day()
check(np.array_equal(r.soil_moisture.ravel(), ptr), "BMI days == Run days (BMI arrays are flat)")


class PulseRain:
    """A small rainfall model with BMI's calls: a storm of `depth_mm` every `every` days, dry
    otherwise; its output is the precipitation flux in m s-1."""
    name = "atmosphere_water__precipitation_leq-volume_flux"

    def initialize(self, every=10, depth_mm=40.0):
        self.t, self.every, self.depth = 0, every, depth_mm

    def update(self):
        self.t += 1

    def get_value(self, name, dest):
        assert name == self.name
        dest[0] = (self.depth if self.t % self.every == 0 else 0.0) / 1000 / 86400
        return dest

    def get_current_time(self):
        return self.t


rain = PulseRain()
rain.initialize()
eco = ecoterra.Bmi()
eco.initialize(str(config))
flux = np.zeros(1)
theta = eco.get_value_ptr("soil_water__volume_fraction")
means, rains = [], []
for day in range(60):
    rain.update()
    rain.get_value(rain.name, flux)
    eco.set_value(rain.name, flux)
    eco.update()
    got = eco.get_value(rain.name, np.zeros(1))
    rains.append((flux[0], got[0]))
    means.append(theta.mean())
check(all(abs(a - b) <= 1e-15 for a, b in rains), "ecoterra's rain is the rain model's, each day")
storms = [d for d in range(60) if rains[d][0] > 0]
check(len(storms) == 6 and all(means[d] > means[d - 1] for d in storms if d > 0),
      "every 40 mm storm wets the soil")
dry = [means[d] < means[d - 1] for d in range(1, 60) if rains[d][0] == 0 and d - 1 not in storms]
check(sum(dry) >= 0.9 * len(dry), "the soil dries between storms")
bad = ecoterra.Bmi()
try:
    bad.update()
    check(False, "update before initialize raises")
except ecoterra.Error as e:
    check("not initialized" in str(e), f"update before initialize: {e}")
try:
    eco.set_value("soil_water__volume_fraction", np.zeros(24 * 24))
    check(False, "setting an output raises")
except ecoterra.InputError as e:
    check("output only" in str(e), f"setting an output: {e}")
try:
    eco.get_value("soil_water__volume_fraction", np.empty(3))
    check(False, "a short destination raises")
except ecoterra.InputError as e:
    check("destination" in str(e), f"a short destination: {e}")
kept = theta.copy()
eco.finalize()
check(np.array_equal(theta, kept), "a get_value_ptr view outlives finalize()")
print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
