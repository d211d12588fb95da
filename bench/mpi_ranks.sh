#!/usr/bin/env bash
# One garment voxelized by one plain process, then by `mpirun -np R` for each
# rank count (default "1 2"), all on the GL backend of the one machine: with
# one GPU the ranks share it, so this measures what a second process gains by
# overlapping one rank's host work (reading back, unpacking, writing region
# files) with the other's GPU passes, and what it costs (two contexts' worth
# of GPU memory, hence a smaller fragment budget: more regions). Every MPI
# output is checked against the plain run's, value for value (same bytes but
# OpenVDB's UUID). Prints JSON lines; the first says where and when it ran.
#
#   bench/mpi_ranks.sh GARMENT.bcc "RESOLUTIONS" [voxelize options...]
#   env: YV_RANKS (default "1 2"), YV_REPEAT (default 1; the best wall time is kept),
#        YV_MPIRUN (default: .mpi/bin/mpirun from tools/device-mpi-prep, else mpirun)
#
# e.g. bench/mpi_ranks.sh .data/sweater_flame_ribbing.bcc "2048 4096" --yarn-radius 0.1
set -euo pipefail
input=$1 resolutions=$2
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
yarnvox="$build/yarnvox"
ranks_list=${YV_RANKS:-1 2} repeat=${YV_REPEAT:-1}
# A relocated Open MPI (tools/device-mpi-prep) where the machine has none installed.
[ -f "$root/.mpi/env.sh" ] && . "$root/.mpi/env.sh"
mpirun=${YV_MPIRUN:-mpirun}
# Root in a container: see tests/test_mpi.cpp for why each option.
# YV_BIND (default none): Open MPI binds each rank to one core when there are
# two ranks or fewer, which leaves a rank's TBB threads (readback, region
# files, the merge) one core between them.
mpirun_flags=(--bind-to "${YV_BIND:-none}" --allow-run-as-root --oversubscribe --mca btl self,vader
              --mca btl_vader_single_copy_mechanism none --mca mpi_yield_when_idle 1)
scratch=$(mktemp -d "${YV_SCRATCH:-${TMPDIR:-/tmp}}/yv-mpi-bench.XXXXXX")
trap 'rm -rf "$scratch"' EXIT

. "$root/bench/header.sh"
bench_header mpi_ranks "$0 $input '$resolutions' $*" \
    "$(printf ', "mpirun": "%s", "env": "YV_RANKS=%s YV_REPEAT=%s"' "$("$mpirun" --version 2>/dev/null | head -1)" "'$ranks_list'" "$repeat")"

# One run: wall seconds (best of YV_REPEAT) and the run's --stats, as one JSON line.
measure() { # label resolution output stats command...
    local label=$1 res=$2 out=$3 stats=$4 best="" ms
    shift 4
    for _ in $(seq "$repeat"); do
        rm -rf "$out" "$out.work"
        local start
        start=$(date +%s%N)
        "$@" >"$scratch/log" 2>&1 || { cat "$scratch/log" >&2; exit 1; }
        ms=$(( ($(date +%s%N) - start) / 1000000 ))
        if [ -z "$best" ] || [ "$ms" -lt "$best" ]; then best=$ms; fi
    done
    python3 - "$label" "$res" "$best" "$stats" "$scratch/log" <<'PY'
import json, re, sys
label, res, ms, stats, log = sys.argv[1:]
s = json.load(open(stats))
b = s.get("backend_stats", {})
per_rank = {m.group(1): int(m.group(2)) for m in re.finditer(r"rank (\d+): (\d+) regions rasterized", open(log).read())}
print(json.dumps({"run": label, "resolution": int(res), "wall_seconds": int(ms) / 1000.0,
                  "seconds": s.get("seconds"), "ranks": b.get("ranks"), "zoom_regions": b.get("zoom_regions"),
                  "fragment_budget": b.get("fragment_budget"), "renderer": b.get("renderer"),
                  "regions_per_rank": per_rank, "active_voxels": s.get("active_voxels"),
                  "peak_host_bytes_rank0": s.get("peak_host_bytes")}))
PY
}

same_vdb() { # a b: equal but for the 36-byte UUID at offset 21
    python3 - "$1" "$2" <<'PY'
import sys
a, b = (bytearray(open(p, "rb").read()) for p in sys.argv[1:])
for x in (a, b): x[21:57] = bytes(36)
print("true" if a == b else "false")
PY
}

for res in $resolutions; do
    plain="$scratch/plain.vdb"
    measure plain "$res" "$plain" "$scratch/plain.json" \
        "$yarnvox" voxelize "$input" -o "$plain" --resolution "$res" --backend gl --stats "$scratch/plain.json" "$@"
    for r in $ranks_list; do
        out="$scratch/ranks$r.vdb"
        measure "mpirun -np $r" "$res" "$out" "$scratch/ranks$r.json" \
            "$mpirun" "${mpirun_flags[@]}" -np "$r" "$yarnvox" voxelize "$input" -o "$out" --resolution "$res" \
            --backend gl --verbose --work-dir "$scratch/work" --stats "$scratch/ranks$r.json" "$@"
        printf '{ "resolution": %s, "ranks": %s, "same_as_plain": %s }\n' "$res" "$r" "$(same_vdb "$plain" "$out")"
        rm -rf "$scratch/work" "$out"
    done
done
