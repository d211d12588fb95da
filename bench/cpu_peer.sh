#!/usr/bin/env bash
# yarnvox's CPU backend against its peer on the same cores: OpenVDB's
# ParticlesToLevelSet and sdfToFogVolume (yv_openvdb_baseline, density only),
# same garment, same grid, one after the other. The garment is issue 31's:
# a plain cylinder of 300 crossings, seed 3, --cross-section disk. For each
# resolution, JSON lines: yarnvox in the regions it plans itself, yarnvox in
# many small regions (--fragment-budget 200000: what a region's fixed costs
# add), and the peer; each with the process's wall, user and system seconds
# and CPU share (/usr/bin/time), yarnvox's with its --stats stage seconds and
# backend stats. The header line says where and when (bench/header.sh).
#
#   bench/cpu_peer.sh ["512 1024 2048"]
#     YV_DEVICE: the machine in words, for the header (e.g. "dev machine, 2 cores, shared")
#     YV_MANY_REGIONS=0: no many-regions runs
#     YV_BUILD_DIR (build), YV_SCRATCH (a temporary folder)
set -euo pipefail
resolutions=${1:-512 1024 2048}
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
scratch=${YV_SCRATCH:-$(mktemp -d)}
mkdir -p "$scratch"
trap 'rm -f "$scratch"/cpu-peer-*' EXIT

. "$root/bench/header.sh"
bench_header cpu_peer "$0 $*" ", \"device\": \"${YV_DEVICE:-unnamed}\""

input="$scratch/cpu-peer-plain-cylinder-300.bcc"
"$build/yarnvox" gen --pattern plain --crossings 300 --shape cylinder --seed 3 -o "$input" --quiet

# One JSON line of a finished run: its /usr/bin/time numbers, and what else it left.
report() { # TOOL RESOLUTION LABEL TIME_FILE [STATS_JSON | PEER_JSON_LINE]
    python3 - "$@" <<'PY'
import json, sys
tool, res, label, timing = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
wall, user, system, cpu = open(timing).read().split()[-4:]
line = {"tool": tool, "run": label, "resolution": res, "wall_seconds": float(wall), "user_seconds": float(user),
        "system_seconds": float(system), "cpu_percent": int(cpu.rstrip("%"))}
if tool == "yarnvox":
    s = json.load(open(sys.argv[5]))
    line.update({"seconds": s["seconds"], "slices": s["slices"], "samples": s["samples"],
                 "active_voxels": s["active_voxels"], "fiber_volume": s["fiber_volume"], "backend_stats": s["backend_stats"]})
else:
    line["peer"] = json.loads(sys.argv[5])
print(json.dumps(line))
PY
}

for res in $resolutions; do
    runs=(default)
    [ "${YV_MANY_REGIONS:-1}" = 0 ] || runs+=(many-regions)
    for run in "${runs[@]}"; do
        budget=()
        [ "$run" = default ] || budget=(--fragment-budget 200000)
        /usr/bin/time -f '%e %U %S %P' -o "$scratch/cpu-peer-time" \
            "$build/yarnvox" voxelize "$input" -o "$scratch/cpu-peer-yv.vdb" --backend cpu --cross-section disk \
            --resolution "$res" "${budget[@]}" --quiet --stats "$scratch/cpu-peer-stats.json"
        report yarnvox "$res" "$run" "$scratch/cpu-peer-time" "$scratch/cpu-peer-stats.json"
        rm -f "$scratch/cpu-peer-yv.vdb"
    done
    line=$(/usr/bin/time -f '%e %U %S %P' -o "$scratch/cpu-peer-time" \
        "$build/bench/yv_openvdb_baseline" --input "$input" --resolution "$res" -o "$scratch/cpu-peer-base.vdb")
    report peer "$res" default "$scratch/cpu-peer-time" "$line"
    rm -f "$scratch/cpu-peer-base.vdb"
done
