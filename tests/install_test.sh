#!/bin/bash
# An installed ecoterra runs without the source tree: `cmake --install` into a fresh prefix, the
# program carries no path of the source or build tree, and it finds its data (climates, runoff
# table, ecosystems, scenes) beside itself. Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1 source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
bin="$work/prefix/bin/ecoterra"
data="$work/prefix/share/ecoterra/data"
test -x "$bin" || { echo "FAIL: no $bin"; exit 1; }
for d in climates hydro ecosystems scenes; do
  test -d "$data/$d" || { echo "FAIL: $data/$d not installed"; exit 1; }
done
for p in "$source" "$build"; do
  if strings "$bin" | grep -qF "$(realpath "$p")"; then
    echo "FAIL: the installed program carries the path $p"; exit 1
  fi
done
# Run from an unrelated folder with no data hint in the environment.
cd "$work"
unset ECOTERRA_DATA
env -u ECOTERRA_DATA "$bin" run "$data/scenes/quickstart.json" --years 1 --no-pictures -o "$work/run.h5" \
  >"$work/run.log" 2>&1 || { cat "$work/run.log"; echo "FAIL: installed run"; exit 1; }
env -u ECOTERRA_DATA "$bin" hydro run "$data/scenes/hydro_quickstart.json" --set simulation.years=1 \
  -o "$work/h.h5" >"$work/h.log" 2>&1 || { cat "$work/h.log"; echo "FAIL: installed hydro run"; exit 1; }
env -u ECOTERRA_DATA "$bin" describe scene >"$work/describe.txt"
grep -q "climate.latitude_deg" "$work/describe.txt" || { echo "FAIL: describe"; exit 1; }
# A program moved away from its data says where it looked and how to point it there.
mkdir "$work/alone" && cp "$bin" "$work/alone/ecoterra"
if env -u ECOTERRA_DATA "$work/alone/ecoterra" hydro run "$data/scenes/hydro_quickstart.json" \
     -o "$work/x.h5" >"$work/alone.log" 2>&1; then
  echo "FAIL: a program without its data folder ran"; exit 1
fi
grep -q "cannot find ecoterra's data folder" "$work/alone.log" || { cat "$work/alone.log"; exit 1; }
grep -q "ECOTERRA_DATA" "$work/alone.log" || { cat "$work/alone.log"; exit 1; }
# The Python module from the prefix alone: its package and its data are the prefix's.
pkg=$(find "$work/prefix" -type d -path "*dist-packages/ecoterra" | head -1)
if [ -n "$pkg" ]; then
  env -u ECOTERRA_DATA PYTHONPATH="$(dirname "$pkg")" /usr/bin/python3 -c "
import ecoterra, sys
prefix = sys.argv[1]
assert ecoterra.__file__.startswith(prefix), ecoterra.__file__
assert ecoterra.data_dir().startswith(prefix), ecoterra.data_dir()
run = ecoterra.Run(ecoterra.Scene(ecoterra.data_dir() + '/scenes/quickstart.json'))
run.step_year()
assert run.years_done == 1
" "$work/prefix" || { echo "FAIL: the installed Python module"; exit 1; }
  for p in "$source" "$build"; do
    if grep -rqF "$(realpath "$p")" "$pkg"; then
      echo "FAIL: the installed Python package carries the path $p"; exit 1
    fi
  done
fi
echo "installed ecoterra ran from $work/prefix without the source tree"
