#!/usr/bin/env bash
# Runs the example ensemble, then reads its summary from Python with pandas and h5py
# (tests/python/read_ensemble.py). Usage: test_read_ensemble.sh BUILD_DIR ROOT
set -euo pipefail
build="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
cd "$dir"
"$build/apps/ecoterra/ecoterra" ensemble "$root/data/studies/example.json" -o out >/dev/null 2>&1
/usr/bin/python3 "$root/tests/python/read_ensemble.py" out
