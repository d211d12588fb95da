#!/usr/bin/env bash
# Leaves streamed into the .vdb during the run (the default) against written
# after the last region (YV_STREAM_LEAVES=0), one build, alternating: what a
# large run saves where the disk is the limit. Prints JSON lines: the header,
# the disk's speed (dd of 4 GiB with fsync, before and after), then one per
# run with its wall time, the output's size and the run's own --stats.
#
#   bench/stream_leaves.sh YARNVOX RESOLUTION GARMENT [VOXELIZE ARGS...]
#   env: YV_SCRATCH (default a temporary folder on the disk measured),
#        YV_ROUNDS (default 2)
set -euo pipefail
yarnvox=$1 resolution=$2 garment=$3
shift 3
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=${YV_SCRATCH:-$(mktemp -d)}
mkdir -p "$scratch"
. "$root/bench/header.sh"
bench_header stream_leaves "$0 $yarnvox $resolution $garment $*" \
    ", \"file_system\": \"$(stat -f -c %T "$scratch")\", \"block\": $(stat -f -c %S "$scratch")"
disk() {
    local line
    line=$(dd if=/dev/zero of="$scratch/dd.bin" bs=1M count=4096 conv=fsync 2>&1 | tail -1)
    rm -f "$scratch/dd.bin"
    printf '{ "dd_%s": "%s" }\n' "$1" "$line"
}
disk before
for round in $(seq "${YV_ROUNDS:-2}"); do
    # Alternating which goes first, so neither always finds the disk after the other's write.
    if [ $((round % 2)) = 1 ]; then order="1 0"; else order="0 1"; fi
    for stream in $order; do
        start=$(date +%s.%N)
        YV_STREAM_LEAVES=$stream "$yarnvox" voxelize "$garment" -o "$scratch/out.vdb" --resolution "$resolution" \
            --quiet --stats "$scratch/stats.json" "$@"
        end=$(date +%s.%N)
        python3 - "$scratch/stats.json" "$stream" "$round" "$start" "$end" "$(stat -c %s "$scratch/out.vdb")" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
print(json.dumps({"stream": int(sys.argv[2]), "round": int(sys.argv[3]),
                  "wall_seconds": round(float(sys.argv[5]) - float(sys.argv[4]), 3), "file_bytes": int(sys.argv[6]),
                  "active_voxels": s["active_voxels"], "vdb_streamed_bytes": s.get("vdb_streamed_bytes"),
                  "vdb_streamed_before_end_bytes": s.get("vdb_streamed_before_end_bytes"),
                  "seconds": s["seconds"], "vdb_seconds": s["vdb_seconds"], "peak_host_bytes": s["peak_host_bytes"],
                  "zoom_regions": s["backend_stats"].get("zoom_regions")}))
EOF
        rm -f "$scratch/out.vdb"
    done
done
disk after
