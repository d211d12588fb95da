#!/usr/bin/env bash
# Inspection at scale: wall time and peak host memory of each `yarnvox
# inspect` command on one large volume, for the yarnvox built here and,
# when YV_BASELINE names another yarnvox binary, for that one in the same
# run. The volume is the draped garment of the paper's size (410k crossings,
# twill, cylinder) voxelized at RESOLUTION; extra arguments go to
# `yarnvox voxelize` (e.g. --precision half). Prints JSON lines (the first
# says where and when; one per command from bench/peak_memory.py).
#
#   bench/inspect_scale.sh RESOLUTION [voxelize options...]
#   env: YV_BASELINE (a yarnvox binary to compare), YV_BUILD_DIR (default build),
#        YV_SCRATCH (default a temporary folder), YV_WORK_DIR=1 also keeps the
#        run's work directory and times --verify, --html and a region render on it,
#        YV_TIMEOUT (seconds per inspect command, default 300),
#        YV_BASELINE_SKIP (space-separated labels the baseline does not run, e.g.
#        one that needs more memory than the machine has)
set -euo pipefail
resolution=$1
shift
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
yarnvox="$build/yarnvox"
scratch=${YV_SCRATCH:-$(mktemp -d)}
timeout=${YV_TIMEOUT:-300}
mkdir -p "$scratch"
trap '[ -z "${YV_SCRATCH:-}" ] && rm -rf "$scratch"' EXIT
peak() { python3 "$root/bench/peak_memory.py" "$@"; }

. "$root/bench/header.sh"
bench_header inspect_scale "$0 $resolution $*" \
    "$(printf ', "env": "YV_BASELINE=%s YV_WORK_DIR=%s YV_TIMEOUT=%s"' "${YV_BASELINE:-}" "${YV_WORK_DIR:-}" "$timeout")"

garment="$scratch/draped.bcc"
[ -f "$garment" ] || "$yarnvox" gen --pattern twill --shape cylinder --crossings 410000 -o "$garment" --quiet
volume="$scratch/c$resolution.vdb"
work=()
[ "${YV_WORK_DIR:-}" = 1 ] && work=(--work-dir "$scratch/c$resolution.work")
rm -rf "$volume" "$scratch/c$resolution.work"
peak voxelize -- "$yarnvox" voxelize "$garment" -o "$volume" --resolution "$resolution" \
    --stats "$scratch/stats.json" --quiet "${work[@]}" "$@"
[ -f "$volume" ] || { echo "inspect_scale: voxelize wrote no $volume" >&2; exit 1; }
python3 -c "import json,os,sys; s=json.load(open(sys.argv[1])); print(json.dumps({'label': 'volume', 'active_voxels': s.get('active_voxels'), 'bricks': s.get('bricks'), 'vdb_bytes': os.path.getsize(sys.argv[2]), 'voxelize_seconds': s.get('seconds')}))" "$scratch/stats.json" "$volume" || true

run_inspect() { # BINARY NAME WORKDIR
    local bin=$1 name=$2 workdir=$3 skip=" ${YV_BASELINE_SKIP:-} "
    measure() { # LABEL ARGS...
        local label=$1
        shift
        if [ "$name" = baseline ] && [[ "$skip" == *" $label "* ]]; then
            echo "{\"label\": \"$name $label\", \"skipped\": \"YV_BASELINE_SKIP\"}"
            return
        fi
        peak "$name $label" --timeout "$timeout" -- "$bin" inspect "$@" || true
    }
    measure summary "$volume"
    # The .vdb was written around the page cache (O_DIRECT): the first read
    # comes from the disk, this one from the cache the first one filled.
    measure summary-cached "$volume"
    measure raycast "$volume" --render raycast --size 1280x720 -o "$scratch/$name-raycast.png"
    measure orientation "$volume" --render orientation --size 1280x720 -o "$scratch/$name-orientation.png"
    # The first render of a fresh machine compiles the shaders; this one finds them in the driver's cache.
    measure raycast-again "$volume" --render raycast --size 1280x720 -o "$scratch/$name-raycast.png"
    if [ "${YV_WORK_DIR:-}" = 1 ]; then
        measure verify "$workdir" --verify
        measure region-raycast "$workdir" --render raycast --region 5 -o "$scratch/$name-region.png"
        rm -rf "$scratch/$name-html"
        measure html "$workdir" --html "$scratch/$name-html" --html-renders 4
    fi
}
# The .vdb is read from the disk by the first command, from the page cache after.
run_inspect "$yarnvox" new "$scratch/c$resolution.work"
if [ -n "${YV_BASELINE:-}" ]; then
    # A work dir's format is the version's own: the baseline reads one it wrote
    # (same garment and options); its .vdb is not kept.
    if [ "${YV_WORK_DIR:-}" = 1 ]; then
        rm -rf "$scratch/c$resolution.work"
        peak "baseline voxelize" -- "$YV_BASELINE" voxelize "$garment" -o "$scratch/baseline.vdb" --resolution "$resolution" \
            --quiet --work-dir "$scratch/baseline.work" "$@"
        rm -f "$scratch/baseline.vdb"
    fi
    run_inspect "$YV_BASELINE" baseline "$scratch/baseline.work"
fi
if [ -n "${YV_OUT:-}" ]; then cp "$scratch"/new-raycast.png "$YV_OUT/raycast-$resolution.png" 2>/dev/null || true; fi
