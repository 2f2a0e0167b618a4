#!/usr/bin/env bash
# Installs what is missing (Debian 12, as root), then configures and builds ecoterra in ./build.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/install-deps.sh"
jobs="$(nproc 2>/dev/null || echo 2)"
# ECOTERRA_WERROR=ON in the environment (CI, .ci/run) turns warnings into errors.
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DECOTERRA_WERROR="${ECOTERRA_WERROR:-OFF}"
cmake --build "$root/build" -j "$jobs"
# As root, the build is installed into /usr/local: the program `ecoterra`, its data and the Python
# module (`python3 -c "import ecoterra"` then works anywhere; docs/python.md). ECOTERRA_NO_INSTALL=1
# skips this; without root the build tree serves (PYTHONPATH=build/python).
if [ "$(id -u)" -eq 0 ] && [ "${ECOTERRA_NO_INSTALL:-0}" != 1 ]; then
  cmake --install "$root/build" >/dev/null
  echo "build: installed ecoterra into /usr/local (program, data, Python module)"
fi
