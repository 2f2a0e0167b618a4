#!/usr/bin/env bash
# docs/python.md's example as written (docs/examples/python_forest.py), from an unrelated folder,
# then its glTF through the Khronos glTF validator. Usage: test_example.sh BUILD_DIR ROOT
set -euo pipefail
build="$1"
root="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
cd "$dir"
env -u ECOTERRA_DATA PYTHONPATH="$build/python" /usr/bin/python3 \
  "$root/docs/examples/python_forest.py" out | tee example.log
grep -q "MRZR speed made good" example.log
glb="out/scene/scene_gltf/scene.glb"
test -s "$glb" || { echo "FAIL: no $glb"; exit 1; }
NODE_PATH="$root/.tools/node_modules" node "$root/tests/tools/validate_gltf.js" "$glb" | tee v.log
grep -q "errors 0" v.log || { echo "FAIL: the glTF validator found errors"; exit 1; }
