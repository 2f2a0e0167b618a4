#!/usr/bin/env bash
# Test-only tools: Debian's python3-h5py and python3-pandas (the Python readers of run files),
# hdf5-tools (h5ls), clang-format (the format check of CI), and
# from the npm registry, into .tools/ in the repository (git-ignored), the Khronos glTF validator
# that the export tests run on every .glb. Idempotent.
set -euo pipefail
cd "$(dirname "$0")/.."
version=2.0.0-dev.3.10
# Debian packages, with the package lists refreshed once first (a fresh machine may have none).
updated=0
apt_install() {
  if [ "$updated" = 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    updated=1
  fi
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@"
}
# Debian's Python readers the tests load run files with (tests/python/).
if ! /usr/bin/python3 -c "import h5py, pandas" 2>/dev/null; then
  echo "install-test-tools: installing python3-h5py and python3-pandas"
  apt_install python3-h5py python3-pandas
fi
# HDF5's own tools (h5ls lists run files as users see them).
if ! command -v h5ls >/dev/null; then
  echo "install-test-tools: installing hdf5-tools"
  apt_install hdf5-tools
fi
# clang-format (Debian's, version 14): CI checks that the code is formatted (scripts/check-format.sh).
if ! command -v clang-format >/dev/null; then
  echo "install-test-tools: installing clang-format"
  apt_install clang-format
fi
if [ -f .tools/node_modules/gltf-validator/package.json ] &&
   grep -q "\"version\": \"$version\"" .tools/node_modules/gltf-validator/package.json; then
  echo "install-test-tools: gltf-validator $version present"
  exit 0
fi
if ! command -v npm >/dev/null; then
  echo "install-test-tools: npm is missing; installing Debian's nodejs and npm"
  apt_install nodejs npm
fi
mkdir -p .tools
npm install --silent --no-audit --no-fund --prefix .tools "gltf-validator@$version"
echo "install-test-tools: gltf-validator $version installed in .tools/"
