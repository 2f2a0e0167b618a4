#!/usr/bin/env bash
# The main job on the embedded default: builds ecoterra, generates the default multifractal terrain
# (paper 000, majhor2023 preset), analyses it and writes its pictures into out/default/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
bin="$root/build/apps/ecoterra/ecoterra"
out="$root/out/default"
mkdir -p "$out"
"$bin" terrain generate --preset majhor2023 --d-high 2.45 --seed 7 -o "$out/terrain.h5"
"$bin" terrain analyze "$out/terrain.h5" --json "$out/report.json" --png "$out/pictures"
"$bin" terrain missions "$out/terrain.h5" --count 20 --length 35 --border 5 --seed 1 \
  -o "$out/missions.csv"
echo "done: terrain, report and pictures are in $out"
