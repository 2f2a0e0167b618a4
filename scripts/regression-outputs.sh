#!/usr/bin/env bash
# Regression outputs for refactors that must not change a number: runs a fixed set of jobs into
# OUT (quickstart, undergrowth, a MAVS ecosystem file with objects, light-only, groundwater, a
# resumed run, ensemble members, exports). Compare two such folders with
#   bash scripts/regression-outputs.sh compare OLD NEW
# (both folders made at the same path in turn, since scene files name their own folder), which
# diffs every HDF5 file with h5diff (the provenance group's build and time attributes
# excepted) and every other file with cmp, and exits non-zero on any difference.
#   bash scripts/regression-outputs.sh run OUT [ECOTERRA_BINARY]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode="${1:-}"

run_jobs() {
    local out="$1" bin="$2"
    mkdir -p "$out"
    export ECOTERRA_DATA="$root/data"
    out="$(cd "$out" && pwd)"
    cd "$out"
    local q="$root/data/scenes/quickstart.json"
    local small=(--years 12 --no-pictures --set terrain.generate.size=24)
    "$bin" run "$q" -o quickstart.h5 --years 20 --no-pictures --force
    "$bin" run "$root/data/scenes/quickstart_undergrowth.json" -o undergrowth.h5 "${small[@]}" --force
    "$bin" run "$q" -o mavs_objects.h5 "${small[@]}" --force \
        --set "vegetation.ecosystem=$root/tests/data/mavs_ecosystem_files/american_southeast_forest_obstacles.json"
    "$bin" run "$q" -o light_only.h5 "${small[@]}" --set vegetation.competition=light_only --force
    "$bin" run "$q" -o groundwater.h5 --years 2 --no-pictures --set terrain.generate.size=16 \
        --set hydrology.groundwater=true --force
    "$bin" run "$q" -o resumed.h5 --years 7 --no-pictures --set terrain.generate.size=24 --force
    "$bin" run --resume resumed.h5 --years 5 --no-pictures
    "$bin" stand quickstart.h5 --json stand.json --force
    "$bin" export vegetation quickstart.h5 -o stems.csv --force
    "$bin" export scene quickstart.h5 --format gltf -o forest.glb --force
    "$bin" export scene mavs_objects.h5 --format mavs -o mavs_scene --force
    "$bin" export scene quickstart.h5 --format gazebo -o gazebo_scene --force
    "$bin" export layers undergrowth.h5 -o layers --force
    "$bin" mobility quickstart.h5 --vehicle "$root/data/vehicles/mrzr4.json" --lines 40 --seed 1 \
        --json mobility.json --force
    local manifest="$out/ensemble.json"
    cat >"$manifest" <<EOF
{"name": "regression", "base": {"run": "$q"}, "seed": 1, "replicates": 2,
 "set": {"simulation.years": 6, "terrain.generate.size": 36},
 "axes": [{"key": "vegetation.competition", "values": ["coupled", "light_only"]}],
 "analyses": {"stand": {}, "mobility": {"vehicle": "$root/data/vehicles/mrzr4.json", "lines": 20}}}
EOF
    "$bin" ensemble "$manifest" -o ensemble --jobs 2
}

# A members table without its wall-time column.
without_seconds() {
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "seconds") c = i }
             { out = ""; for (i = 1; i <= NF; ++i) if (i != c) out = out (out == "" ? "" : ",") $i; print out }' "$1"
}

compare() {
    local old="$1" new="$2" bad=0
    while IFS= read -r -d '' f; do
        local rel="${f#"$old"/}"
        if [[ ! -e "$new/$rel" ]]; then
            echo "missing in $new: $rel"
            bad=1
            continue
        fi
        case "$f" in
        *.h5)
            if ! h5diff --exclude-attribute /provenance --exclude-attribute /checkpoint \
                --exclude-path /members/seconds --exclude-path /checkpoint/state "$f" "$new/$rel" >/tmp/h5diff.$$ 2>&1; then
                echo "differs (h5diff): $rel"
                head -20 /tmp/h5diff.$$
                bad=1
            fi
            ;;
        */timing.json | */logs/*.log) ;; # wall times
        */members.csv)
            if ! cmp -s <(without_seconds "$f") <(without_seconds "$new/$rel"); then
                echo "differs (cmp, seconds column aside): $rel"
                bad=1
            fi
            ;;
        *)
            if ! cmp -s "$f" "$new/$rel"; then
                echo "differs (cmp): $rel"
                bad=1
            fi
            ;;
        esac
    done < <(find "$old" -type f -print0 | sort -z)
    rm -f /tmp/h5diff.$$
    if [[ $bad == 0 ]]; then echo "identical: $(find "$old" -type f | wc -l) files"; fi
    return $bad
}

case "$mode" in
run)
    # One path for the binary whatever build is tested: outputs quote their command line.
    fixed="${TMPDIR:-/tmp}/ecoterra-regression/ecoterra"
    mkdir -p "$(dirname "$fixed")"
    cp "${3:-$root/build/apps/ecoterra/ecoterra}" "$fixed"
    run_jobs "$2" "$fixed"
    ;;
compare) compare "$2" "$3" ;;
*)
    echo "usage: $0 run OUT [ECOTERRA_BINARY] | compare OLD NEW" >&2
    exit 2
    ;;
esac
