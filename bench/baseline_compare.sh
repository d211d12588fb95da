#!/usr/bin/env bash
# yarnvox against the baseline a user already has (OpenVDB's own tools on the
# CPU, yv_openvdb_baseline: density only, and with an orientation grid), on
# the same garment and grid, one after the other on this machine. Prints JSON
# lines: a header (machine, date, commit, command), then for each garment and
# resolution the yarnvox --stats summary (the median of YV_REPEAT runs, 3
# unless set) and the two baseline runs.
#
#   bench/baseline_compare.sh GARMENT YARN_RADIUS "2048 4096"
#     GARMENT: a .bcc file, or gen:PATTERN:SHAPE:CROSSINGS (generated first)
#     YV_OPTIONS: more voxelize options (e.g. "--cross-section disk"); the
#       baselines take none (they draw spheres along the curves either way)
#     YV_BASELINES: "density orientation" (the default), "density", or "none"
#       (a row whose garment and grid another row's baselines measured)
set -euo pipefail
garment=$1 radius=$2 resolutions=$3
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
scratch=${YV_SCRATCH:-$(mktemp -d)}
mkdir -p "$scratch"
trap 'rm -rf "$scratch"/yv-* "$scratch"/base-*' EXIT

. "$root/bench/header.sh"
bench_header baseline_compare "$0 $*"

input=$garment
if [[ $garment == gen:* ]]; then
    IFS=: read -r _ pattern shape crossings <<<"$garment"
    input="$scratch/gen-$pattern-$shape-$crossings.bcc"
    [ -f "$input" ] || "$build/yarnvox" gen --pattern "$pattern" --shape "$shape" --crossings "$crossings" -o "$input" --quiet
fi

# The first GL run on a machine compiles yarnvox's shaders (0.7 to 0.9 s on
# the H100); the driver caches them, so every later run starts without. One
# untimed run of a tiny garment first, so that the timed runs are the runs a
# user makes from the second on (YV_COLD=1 skips it, to time a first run).
if [ "${YV_COLD:-0}" != 1 ]; then
    "$build/yarnvox" gen --pattern plain --crossings 16 -o "$scratch/yv-warm.bcc" --quiet
    "$build/yarnvox" voxelize "$scratch/yv-warm.bcc" -o "$scratch/yv-warm.vdb" --resolution 64 --quiet
fi

# yarnvox runs YV_REPEAT times (3 unless set) at each size: a run of a second
# varies by a tenth from one to the next on the same machine. Its line holds
# the median run's stats and every run's wall time.
repeat=${YV_REPEAT:-3}
for res in $resolutions; do
    runs=()
    for ((run = 0; run < repeat; ++run)); do
        start=$(date +%s.%N)
        # shellcheck disable=SC2086 # YV_OPTIONS is a list of words
        "$build/yarnvox" voxelize "$input" -o "$scratch/yv-$res.vdb" --yarn-radius "$radius" --resolution "$res" --quiet \
            --stats "$scratch/yv-stats-$run.json" ${YV_OPTIONS:-}
        end=$(date +%s.%N)
        runs+=("$start" "$end")
        size=$(stat -c %s "$scratch/yv-$res.vdb")
        rm -f "$scratch/yv-$res.vdb"
    done
    python3 - "$garment" "$res" "$scratch/yv-stats" "$size" "${runs[@]}" <<'PY'
import json, os, sys
garment, res, stats, size = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
times = [float(t) for t in sys.argv[5:]]
walls = [round(end - start, 3) for start, end in zip(times[0::2], times[1::2])]
median = sorted(range(len(walls)), key=lambda i: walls[i])[len(walls) // 2]
s = json.load(open(f"{stats}-{median}.json"))
print(json.dumps({"tool": "yarnvox", "garment": garment, "options": os.environ.get("YV_OPTIONS", ""),
                  "resolution": res, "wall_seconds": walls[median],
                  "wall_seconds_runs": walls, "seconds": s["seconds"], "slices": s["slices"], "fragments": s["samples"],
                  "active_voxels": s["active_voxels"], "file_bytes": size, "peak_host_bytes": s["peak_host_bytes"],
                  "backend_stats": s["backend_stats"]}))
PY
    # Each baseline line gains its process's wall time, measured as yarnvox's
    # is (its own "total" leaves out the process's start and exit).
    baselines=${YV_BASELINES:-density orientation}
    for orientation in "" --orientation; do
        kind=density
        [ -n "$orientation" ] && kind=orientation
        [[ " $baselines " == *" $kind "* ]] || continue
        start=$(date +%s.%N)
        line=$("$build/bench/yv_openvdb_baseline" --input "$input" --yarn-radius "$radius" --resolution "$res" $orientation \
            -o "$scratch/base-$res.vdb")
        end=$(date +%s.%N)
        python3 -c 'import json, sys; d = json.loads(sys.argv[1]); d["wall_seconds"] = round(float(sys.argv[3]) - float(sys.argv[2]), 3); print(json.dumps(d))' \
            "$line" "$start" "$end"
        rm -f "$scratch/base-$res.vdb"
    done
done
