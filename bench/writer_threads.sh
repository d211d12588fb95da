#!/usr/bin/env bash
# Writer threads A/B on one machine: a GPU run's default writers (all cores
# but two) against YV_WRITER_THREADS=K (8: the old default on 16 cores), two
# rounds with the order swapped in the second, on the draped garment (2048 to
# 8192, and its 41 M slices at 2048) and the sweater (4096 and 8192, with
# BASELINE_BINARY's run of the sweater at 8192 beside them). Prints a JSON
# line a run: side, writer threads, garment, resolution, options, wall
# seconds, active voxels, bytes and --stats stage seconds.
#
#   bench/writer_threads.sh NEW_BINARY BASELINE_BINARY SWEATER.bcc [K]
set -euo pipefail
new=$1 base=$2 sweater=$3 fixed=${4:-8}
scratch=${YV_SCRATCH:-$(mktemp -d)}
trap 'rm -f "$scratch"/o.vdb' EXIT
draped=$scratch/draped.bcc
"$new" gen --pattern twill --shape cylinder --crossings 410000 -o "$draped" --quiet
for bin in "$base" "$new"; do # the shaders compiled once for each (the driver caches them)
    "$bin" gen --pattern plain --crossings 16 -o "$scratch/w.bcc" --quiet
    "$bin" voxelize "$scratch/w.bcc" -o "$scratch/w.vdb" --resolution 64 --quiet
done
one() { # SIDE BINARY THREADS GARMENT RADIUS RESOLUTION [OPTIONS...]
    local side=$1 bin=$2 threads=$3 garment=$4 radius=$5 res=$6
    shift 6
    local start end env=()
    [ "$threads" = default ] || env=(YV_WRITER_THREADS="$threads")
    start=$(date +%s.%N)
    env "${env[@]}" "$bin" voxelize "$garment" -o "$scratch/o.vdb" --yarn-radius "$radius" --resolution "$res" \
        --quiet --stats "$scratch/s.json" "$@"
    end=$(date +%s.%N)
    python3 -c 'import json, os, sys
s = json.load(open(sys.argv[1]))
print(json.dumps({"side": sys.argv[2], "writer_threads": sys.argv[3], "garment": os.path.basename(sys.argv[4]),
                  "resolution": int(sys.argv[5]), "options": sys.argv[6],
                  "wall_seconds": round(float(sys.argv[8]) - float(sys.argv[7]), 3), "active_voxels": s["active_voxels"],
                  "file_bytes": os.path.getsize(sys.argv[9]), "seconds": {k: round(v, 3) for k, v in s["seconds"].items()}}))' \
        "$scratch/s.json" "$side" "$threads" "$garment" "$res" "$*" "$start" "$end" "$scratch/o.vdb"
    rm -f "$scratch/o.vdb"
}
for round in 1 2; do
    if [ "$round" = 1 ]; then order="$fixed default"; else order="default $fixed"; fi
    for t in $order; do one new "$new" "$t" "$draped" 0.3 8192; done
    [ "$round" = 1 ] && one base "$base" default "$sweater" 0.1 8192 --cross-section disk
    for t in $order; do one new "$new" "$t" "$sweater" 0.1 8192 --cross-section disk; done
    [ "$round" = 2 ] && one base "$base" default "$sweater" 0.1 8192 --cross-section disk
    for res in 2048 4096; do for t in $order; do one new "$new" "$t" "$draped" 0.3 "$res"; done; done
    for t in $order; do one new "$new" "$t" "$draped" 0.3 2048 --slices-per-segment 50; done
    for t in $order; do one new "$new" "$t" "$sweater" 0.1 4096 --cross-section disk; done
done
