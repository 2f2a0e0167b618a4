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
# The exported tables in both formats, and the diagnosis.
"$e" export vegetation run.h5 -o stems.csv >/dev/null
"$e" export vegetation run.h5 -o stems.json >/dev/null
# (dead wood from a stand of large trees and a storm, so that the table has rows)
"$e" run "$root/data/scenes/quickstart.json" -o dead.h5 --years 6 --no-pictures \
  --set terrain.generate.size=25 \
  --set 'vegetation.initial={"random":{"stems_per_ha":800,"max_dbh_m":0.5}}' \
  --set 'vegetation.windthrow={"storms":[{"year":3,"wind_m_per_s":30}]}' >/dev/null
"$e" export deadwood dead.h5 -o dead.csv >/dev/null
"$e" export deadwood dead.h5 -o dead.json >/dev/null
[ "$(wc -l <dead.csv)" -gt 10 ] || { echo "too few dead-wood rows"; exit 1; }
/usr/bin/python3 "$root/tests/python/read_exports.py" run.h5 stems.csv stems.json dead.csv dead.json
