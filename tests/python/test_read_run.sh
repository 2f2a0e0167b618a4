#!/usr/bin/env bash
# Grows a short run, then reads it from Python with h5py and pandas (tests/python/read_run.py).
# Usage: test_read_run.sh BUILD_DIR ROOT
set -euo pipefail
build="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
cd "$dir"
"$build/apps/ecoterra/ecoterra" run "$root/data/scenes/quickstart.json" -o run.h5 --years 10 --no-pictures >/dev/null
"$build/apps/ecoterra/ecoterra" stand run.h5 --json stand.json >/dev/null
/usr/bin/python3 "$root/tests/python/read_run.py" run.h5 stand.json
