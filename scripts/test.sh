#!/usr/bin/env bash
# Installs what is missing, builds ecoterra and runs the whole test suite under CTest.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh"
bash "$root/scripts/install-test-tools.sh"
cd "$root/build"
ctest --output-on-failure -j 2
