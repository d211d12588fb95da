#!/usr/bin/env bash
# What a first run on a machine with no shader cache costs: each yarnvox binary
# given runs the same voxelize (and an inspect render) with the NVIDIA driver's
# disk cache pointed at an empty folder (a fresh machine), then again with that
# folder filled (the next run). Prints JSON lines: the header, then one per run
# with its wall time and the run's own --stats seconds.
#
#   bench/first_run.sh GARMENT.bcc RESOLUTION BINARY... 
#   env: YV_SCRATCH (default a temporary folder), YV_ROUNDS (default 2)
set -euo pipefail
garment=$1 resolution=$2
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=${YV_SCRATCH:-$(mktemp -d)}
mkdir -p "$scratch"
. "$root/bench/header.sh"
bench_header first_run "$0 $garment $resolution $*" ""
for round in $(seq "${YV_ROUNDS:-2}"); do
    for bin in "$@"; do
        cache="$scratch/glcache-$round-$(basename "$(dirname "$bin")")-$(basename "$bin")"
        rm -rf "$cache"
        mkdir -p "$cache"
        for when in first next; do
            start=$(date +%s.%N)
            __GL_SHADER_DISK_CACHE_PATH="$cache" __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1 \
                "$bin" voxelize "$garment" -o "$scratch/out.vdb" --resolution "$resolution" --quiet \
                --stats "$scratch/stats.json"
            end=$(date +%s.%N)
            start2=$(date +%s.%N)
            __GL_SHADER_DISK_CACHE_PATH="$cache" "$bin" inspect "$scratch/out.vdb" --render raycast \
                --size 640x360 -o "$scratch/r.png" >/dev/null
            end2=$(date +%s.%N)
            python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(json.dumps({'binary': sys.argv[2], 'round': int(sys.argv[3]), 'cache': sys.argv[4], 'voxelize_wall_s': round(float(sys.argv[6]) - float(sys.argv[5]), 3), 'raycast_wall_s': round(float(sys.argv[8]) - float(sys.argv[7]), 3), 'seconds': s.get('seconds')}))" \
                "$scratch/stats.json" "$bin" "$round" "$when" "$start" "$end" "$start2" "$end2"
            rm -f "$scratch/out.vdb"
        done
    done
done
