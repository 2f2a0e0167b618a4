#!/usr/bin/env bash
# Grows short runs, then reads each from Python with h5py and pandas (tests/python/read_run.py).
# Usage: test_read_run.sh BUILD_DIR ROOT
set -euo pipefail
build="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
cd "$dir"
# The quickstart (trees), its undergrowth variant (shrubs, two grass species) and a MAVS file
# with roadblocks and grass.
e="$build/apps/ecoterra/ecoterra"
"$e" run "$root/data/scenes/quickstart.json" -o run.h5 --years 10 --no-pictures >/dev/null
"$e" run "$root/data/scenes/quickstart_undergrowth.json" -o under.h5 --years 15 --no-pictures >/dev/null
"$e" run "$root/data/scenes/quickstart.json" -o mavs.h5 --years 15 --no-pictures \
  --set terrain.generate.size=25 \
  --set "vegetation.ecosystem=$root/tests/data/mavs_ecosystem_files/american_southeast_forest_obstacles.json" >/dev/null
for r in run under mavs; do
  "$e" stand "$r.h5" --json "$r.stand.json" >/dev/null
  /usr/bin/python3 "$root/tests/python/read_run.py" "$r.h5" "$r.stand.json"
done
