#!/usr/bin/env bash
# Installs the Debian 12 packages ecoterra builds against. Idempotent, non-interactive, needs root.
# --sanitize adds clang with its sanitizer and libFuzzer runtimes and OpenMP (scripts/sanitize.sh).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev libsundials-dev libsuitesparse-dev libboost-graph-dev
  libhdf5-dev zlib1g-dev nlohmann-json3-dev catch2
  libpng-dev libgdal-dev libfftw3-dev libcli11-dev libcairo2-dev
  libsdformat-dev gdal-bin
  libopenmpi-dev openmpi-bin
  pybind11-dev python3-dev python3-numpy
)
if [ "${1:-}" = "--sanitize" ]; then
  packages+=(clang libclang-rt-14-dev libomp-14-dev)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing packages (${missing[*]}) and not root; install them with apt-get" >&2
  exit 1
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
