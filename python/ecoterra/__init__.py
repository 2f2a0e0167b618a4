"""ecoterra from Python: terrains, scenes, runs stepped day by day, their fields as numpy arrays
and their plants as columns (docs/python.md).

    import ecoterra
    run = ecoterra.Run(ecoterra.Scene("data/scenes/quickstart.json"))
    run.step_year(10)
    theta = run.soil_moisture          # a read-only view over the engine's memory
    plants = ecoterra.plants_frame(run)  # a pandas DataFrame
"""
import os as _os
from pathlib import Path as _Path


def _find_data():
    # The data folder (climates, ecosystems, scenes): ECOTERRA_DATA if set, else the nearest
    # share/ecoterra/data above this package (the build tree's link, or the installed prefix's).
    here = _Path(_os.path.abspath(__file__)).parent  # not resolved: the build tree links this file
    for up in [here, *here.parents][:6]:
        d = up / "share" / "ecoterra" / "data"
        if d.is_dir():
            return str(d)
    return None


if not _os.environ.get("ECOTERRA_DATA"):
    _d = _find_data()
    if _d:
        _os.environ["ECOTERRA_DATA"] = _d

from ._ecoterra import (  # noqa: E402
    Bmi,
    CheckpointError,
    Error,
    InputError,
    IoError,
    Run,
    Scene,
    Terrain,
    __version__,
    ensemble_members,
    ensemble_summary,
    run_ensemble_member,
    export_scene,
    generate_terrain,
    mobility,
    mobility_map,
    read_terrain,
    run,
)


def data_dir():
    """The data folder ecoterra reads its climates, ecosystems and scenes from."""
    return _os.environ.get("ECOTERRA_DATA")


def plants_frame(run_):
    """The live plants of a Run as a pandas DataFrame, with the species' names."""
    import pandas as pd

    df = pd.DataFrame(run_.plants())
    names = run_.species
    df.insert(2, "species_name", [names[i] for i in df["species"]])
    return df


def table_frame(columns):
    """A run's yearly() or daily() table as a pandas DataFrame."""
    import pandas as pd

    return pd.DataFrame(columns)


__all__ = [
    "Bmi", "CheckpointError", "Error", "InputError", "IoError", "Run", "Scene", "Terrain",
    "data_dir", "ensemble_members", "ensemble_summary", "export_scene", "run_ensemble_member", "generate_terrain", "mobility", "mobility_map", "plants_frame", "read_terrain", "run", "table_frame",
]
