#!/usr/bin/env bash
# What the slice spacing that follows the voxel size costs, and what it buys:
# the same garment voxelized by a yarnvox from before the change (25 slices
# per segment, whole slab in one voxel) and by this one (default options),
# at each resolution: slices, fragments, seconds (from --stats) and the
# per-voxel density statistics of each output (yv_density_stats, through
# OpenVDB). Then GL against the CPU reference on the same garment.
# Prints JSON lines; the first one says where and when it ran (YV_COMMIT names
# the commit where the working tree's git history is not the one built).
#
#   bench/fidelity_cost.sh BEFORE_YARNVOX GARMENT.bcc YARN_RADIUS "2048 4096" [COMPARE_RESOLUTION]
set -euo pipefail
before=$1 input=$2 radius=$3 resolutions=$4 compare=${5:-0}
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
after="$build/yarnvox"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

. "$root/bench/header.sh"
bench_header fidelity_cost "$0 $*"

for res in $resolutions; do
    for which in before after; do
        bin=$before
        [ "$which" = after ] && bin=$after
        out="$scratch/$which-$res.vdb"
        "$bin" voxelize "$input" -o "$out" --yarn-radius "$radius" --resolution "$res" --quiet --stats "$scratch/stats.json"
        python3 - "$which" "$res" "$scratch/stats.json" "$("$build/bench/yv_density_stats" "$out")" <<'PY'
import json, sys
which, res, stats_path, density = sys.argv[1], int(sys.argv[2]), sys.argv[3], json.loads(sys.argv[4])
s = json.load(open(stats_path))
b = s.get("backend_stats", {})
row = {"version": which, "resolution": res, "slices": s["slices"], "fragments": s["samples"],
       "voxelize_seconds": s["seconds"]["voxelize"], "total_seconds": sum(s["seconds"].values()),
       "active_voxels": s["active_voxels"], "peak_host_bytes": s["peak_host_bytes"],
       "gpu_raster_seconds": b.get("gpu_raster_seconds"), "slice_spacing": s.get("slice_spacing"),
       "voxels_over_one": s.get("voxels_over_one"), "mass_share_over_one": s.get("mass_share_over_one"),
       "density": {k: density[k] for k in ("mass", "max", "p50", "p90", "p99", "p999", "share_above_1")}}
print(json.dumps(row))
PY
        rm -f "$out"
    done
done

if [ "$compare" != 0 ]; then
    for xs in fibers disk; do
        "$build/bench/yv_bench_voxelize" --backend compare --input "$input" --yarn-radius "$radius" \
            --resolution "$compare" --cross-section "$xs"
    done
fi
