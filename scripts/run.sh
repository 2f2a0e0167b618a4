#!/usr/bin/env bash
# The main job on the embedded default scene: builds ecoterra and grows the 1 ha quickstart forest
# (data/scenes/quickstart.json: humid subtropical broadleaf forest on multifractal terrain, 40
# years, coupled model), then prints its stand table and writes its stem list and pictures into
# out/default/. Running it again replaces out/default/ (--force).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
bin="$root/build/apps/ecoterra/ecoterra"
out="$root/out/default"
mkdir -p "$out"
"$bin" run "$root/data/scenes/quickstart.json" -o "$out/run.h5" --force
"$bin" stand "$out/run.h5" --json "$out/stand.json" --force
"$bin" export vegetation "$out/run.h5" -o "$out/stems.csv" --force
echo "done: run file $out/run.h5, stand table $out/stand.json, stems $out/stems.csv,"
echo "      pictures in $out/run.pictures/ (stems, dbh_histogram, stand_history, soil_moisture, surface_water_depth)"
