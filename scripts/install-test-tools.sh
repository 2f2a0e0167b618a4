#!/usr/bin/env bash
# Test-only tools: Debian's python3-h5py and python3-pandas (the Python readers of run files),
# hdf5-tools (h5ls), clang-format (the format check of CI), and
# from the npm registry, into .tools/ in the repository (git-ignored), the Khronos glTF validator
# that the export tests run on every .glb. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
version=2.0.0-dev.3.10
# Debian's Python readers the tests load run files with (tests/python/).
if ! /usr/bin/python3 -c "import h5py, pandas" 2>/dev/null; then
  echo "install-test-tools: installing python3-h5py and python3-pandas"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-h5py python3-pandas
fi
# HDF5's own tools (h5ls lists run files as users see them).
if ! command -v h5ls >/dev/null; then
  echo "install-test-tools: installing hdf5-tools"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends hdf5-tools
fi
# clang-format (Debian's, version 14): CI checks that the code is formatted (scripts/check-format.sh).
if ! command -v clang-format >/dev/null; then
  echo "install-test-tools: installing clang-format"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang-format
fi
if [ -f .tools/node_modules/gltf-validator/package.json ] &&
   grep -q "\"version\": \"$version\"" .tools/node_modules/gltf-validator/package.json; then
  echo "install-test-tools: gltf-validator $version present"
  exit 0
fi
if ! command -v npm >/dev/null; then
  echo "install-test-tools: npm is missing; installing Debian's nodejs and npm"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm
fi
mkdir -p .tools
npm install --silent --no-audit --no-fund --prefix .tools "gltf-validator@$version"
echo "install-test-tools: gltf-validator $version installed in .tools/"
