#!/usr/bin/env bash
# Does --precision half show in a picture? One garment voxelized with
# --precision float and --precision half, each .vdb rendered in Blender
# (tools/render-blender.py: Cycles on the CPU, the grid held at full precision
# while rendering so that the file's values are what is compared), and the
# pictures compared (bench/compare_pictures.py: PSNR, the largest per-channel
# difference 0-255, the pixels that differ by more than 1). The float file is
# rendered three times: again with the same seed (the same picture, bit for
# bit, or the renders are not repeatable) and with another seed: the
# float-vs-float difference across seeds is the noise floor that the
# half-vs-float difference (same seed) is read against. Prints JSON lines; the
# first says where and when it ran (YV_DEVICE describes the machine), one per
# file (bytes, active voxels from `yarnvox inspect --json`, bytes an active
# voxel), one per comparison. The float and half pictures (seed 0) are kept in
# PICTURES when given.
#
#   bench/half_vs_float.sh GARMENT.bcc RESOLUTION [PICTURES] [-- VOXELIZE OPTIONS]
#
# YV_SAMPLES (default 16), YV_SIZE (default 480x360), YV_THREADS (default 2)
# set the renders; YV_BACKEND (default auto) the voxelizations. Needs
# Blender (Debian: blender, 3.4) and python3 with numpy and PIL.
set -euo pipefail
garment=$1 res=$2
shift 2
pictures=""
if [[ $# -gt 0 && $1 != "--" ]]; then pictures=$1; shift; fi
[[ $# -gt 0 && $1 == "--" ]] && shift
root=$(cd "$(dirname "$0")/.." && pwd)
yarnvox="${YV_BUILD_DIR:-$root/build}/yarnvox"
samples=${YV_SAMPLES:-16} size=${YV_SIZE:-480x360} threads=${YV_THREADS:-2} backend=${YV_BACKEND:-auto}
py=/usr/bin/python3
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

. "$root/bench/header.sh"
bench_header half_vs_float "$0 $garment $res ${pictures:+$pictures }${*:+-- $*}" \
    ", \"device\": \"${YV_DEVICE:-unnamed}\", \"samples\": $samples, \"size\": \"$size\", \"render_threads\": $threads"

name=$(basename "$garment" .bcc)
for precision in float half; do
    out="$scratch/$name-$precision.vdb"
    start=$(date +%s.%N)
    "$yarnvox" voxelize "$garment" -o "$out" --resolution "$res" --precision "$precision" --backend "$backend" \
        --quiet "$@"
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    "$yarnvox" inspect "$out" --json > "$scratch/inspect.json"
    "$py" - "$name" "$res" "$precision" "$out" "$scratch/inspect.json" "$seconds" <<'PY'
import json, os, sys
name, res, precision, path, inspect, seconds = sys.argv[1:]
report = json.load(open(inspect))
active = report["voxels"]["active_voxels"]
size = os.path.getsize(path)
print(json.dumps({"garment": name, "resolution": int(res), "precision": precision, "vdb_bytes": size,
                  "active_voxels": active, "bytes_per_active_voxel": round(size / active, 2),
                  "half_float": [g["half_float"] for g in report["grids"]],
                  "voxelize_wall_seconds": round(float(seconds), 1)}))
PY
done

render() { # vdb png seed
    local start
    start=$(date +%s.%N)
    blender -b -noaudio -P "$root/tools/render-blender.py" -- "$1" "$2" --volume-precision full --seed "$3" \
        --samples "$samples" --size "$size" --threads "$threads" > "$scratch/blender.log" 2>&1 ||
        { tail -20 "$scratch/blender.log" >&2; exit 1; }
    printf '{ "render": "%s", "seed": %s, "wall_seconds": %.1f }\n' "$(basename "$2")" "$3" \
        "$(echo "$(date +%s.%N) - $start" | bc)"
}
render "$scratch/$name-float.vdb" "$scratch/$name-float.png" 0
render "$scratch/$name-float.vdb" "$scratch/$name-float-again.png" 0
render "$scratch/$name-float.vdb" "$scratch/$name-float-seed1.png" 1
render "$scratch/$name-half.vdb" "$scratch/$name-half.png" 0

compare() { "$py" "$root/bench/compare_pictures.py" "$scratch/$name-$1.png" "$scratch/$name-$2.png" "$name: $3"; }
compare float float-again "float vs float, same seed (repeatable)"
compare float float-seed1 "float vs float, seed 0 vs 1 (noise floor)"
compare float half "half vs float, same seed"

if [[ -n $pictures ]]; then
    mkdir -p "$pictures"
    cp "$scratch/$name-float.png" "$scratch/$name-half.png" "$pictures/"
fi
