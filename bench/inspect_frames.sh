#!/usr/bin/env bash
# Frame time and samples per pixel of `yarnvox inspect --render`, with and
# without empty-space skipping, for one garment at each resolution (or for a
# volume already made). A .bcc is voxelized first (extra arguments go to
# `yarnvox voxelize`, e.g. --yarn-radius 0.1); a .vdb or a work directory is
# rendered as it is. Each frame is drawn --repeat times (median and best
# reported). Prints JSON lines; the first one says where and when it ran
# (YV_COMMIT names the commit where the working tree's git history is not
# the one built).
#
#   bench/inspect_frames.sh GARMENT.bcc|VOLUME.vdb|WORKDIR "RESOLUTIONS" [WIDTHxHEIGHT] [voxelize options...]
#   env: YV_GPU_BUDGET (default 2G), YV_REPEAT (default 5), YV_VIEW (default 30,20,4),
#        YV_MODES (default "raycast mip orientation"; "slices" draws the garment's
#        slices, with the sort and draw times; texture-slicing, half-angle,
#        splatting and volumetric-triangles (the garment the volume records)
#        have no empty-space skipping to turn off and are timed once; isosurface
#        is timed with and without), YV_SLICE_LOD (slices: --slice-lod PIXELS,
#        e.g. 0 for every slice; default: the command's), YV_SLICE_PRIMITIVE
#        (slices: --slice-primitive auto|tiles|points|boxes; default: the command's)
set -euo pipefail
input=$1 resolutions=$2 size=${3:-800x600}
shift $(( $# < 3 ? $# : 3 ))
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
yarnvox="$build/yarnvox"
budget=${YV_GPU_BUDGET:-2G} repeat=${YV_REPEAT:-5} view=${YV_VIEW:-30,20,4}
modes=${YV_MODES:-raycast mip orientation}
slice_lod=${YV_SLICE_LOD:-} slice_primitive=${YV_SLICE_PRIMITIVE:-}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

. "$root/bench/header.sh"
bench_header inspect_frames "$0 $input '$resolutions' $size $*" \
    "$(printf ', "env": "YV_GPU_BUDGET=%s YV_REPEAT=%s YV_VIEW=%s YV_MODES=%s YV_SLICE_LOD=%s YV_SLICE_PRIMITIVE=%s"' "$budget" "$repeat" "$view" "'$modes'" "$slice_lod" "$slice_primitive")"

case "$input" in
*.bcc) ;;
*) resolutions=given ;;
esac

for res in $resolutions; do
    volume=$input
    if [ "$res" != given ]; then
        volume="$scratch/volume-$res.vdb"
        start=$(date +%s%N)
        "$yarnvox" voxelize "$input" -o "$volume" --resolution "$res" --quiet "$@"
        ms=$(( ($(date +%s%N) - start) / 1000000 ))
        printf '{ "resolution": %s, "voxelize_seconds": %d.%03d, "vdb_bytes": %s }\n' "$res" \
            $((ms / 1000)) $((ms % 1000)) "$(stat -c %s "$volume")"
    fi
    for mode in $modes; do
        skips="on off"
        case "$mode" in slices | texture-slicing | half-angle | splatting | volumetric-triangles) skips=on ;; esac
        for skip in $skips; do
            flags=()
            [ "$skip" = off ] && flags+=(--no-skip)
            # The garment the volume was made from (a volume given records its own).
            [ "$mode" = slices ] && [ "$res" != given ] && flags+=(--garment "$input")
            [ "$mode" = slices ] && [ -n "$slice_lod" ] && flags+=(--slice-lod "$slice_lod")
            [ "$mode" = slices ] && [ -n "$slice_primitive" ] && flags+=(--slice-primitive "$slice_primitive")
            "$yarnvox" inspect "$volume" --render "$mode" --size "$size" --view "$view" --gpu-budget "$budget" \
                --repeat "$repeat" --json "${flags[@]}" -o "$scratch/frame.png" |
                python3 -c 'import json, sys
r = json.load(sys.stdin)
r.pop("output", None)
r["path"] = sys.argv[1]
r["resolution"] = int(sys.argv[2]) if sys.argv[2].isdigit() else sys.argv[2]
print(json.dumps(r))' "$input" "$res"
        done
    done
    if [ "$res" != given ]; then rm -f "$volume"; fi
done
