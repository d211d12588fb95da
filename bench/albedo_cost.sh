#!/usr/bin/env bash
# What --albedo costs, and that runs without it cost what they did before it
# existed: a generated knit voxelized by a yarnvox from before albedo and by
# this one (no --albedo), on each backend, alternating, best of REPEATS wall
# seconds of the voxelize stage (from --stats); then this one with a colour
# PNG, without and with --albedo, on each backend. Prints JSON lines; the first
# says where and when it ran (YV_COMMIT names the commit where the working
# tree's git history is not the one built).
#
#   bench/albedo_cost.sh BEFORE_YARNVOX [RESOLUTION] [CROSSINGS] [REPEATS] [BACKENDS]
set -euo pipefail
before=$1 res=${2:-256} crossings=${3:-2000} repeats=${4:-3} backends=${5:-"cpu gl"}
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
after="$build/yarnvox"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

. "$root/bench/header.sh"
bench_header albedo_cost "$0 $*"

"$after" gen --pattern knit --crossings "$crossings" --seed 1 -o "$scratch/knit.bcc" > /dev/null
# A colour cross-section for the --albedo run: the fibre plies' density, tinted.
python3 - "$scratch/tinted.png" <<'PY'
import struct, sys, zlib
size = 64
rows = b""
for y in range(size):
    row = b"\x00"
    for x in range(size):
        u, v = (x + 0.5) / size * 2 - 1, (size - 1 - y + 0.5) / size * 2 - 1
        row += bytes([200 if u < 0 else 40, 120, 60 if u < 0 else 210, 255 if u * u + v * v < 1 else 0])
    rows += row
chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
open(sys.argv[1], "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 6, 0, 0, 0))
                              + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
PY

run() { # label binary backend extra-args...
    local label=$1 bin=$2 backend=$3
    shift 3
    "$bin" voxelize "$scratch/knit.bcc" -o "$scratch/out.vdb" --resolution "$res" --backend "$backend" --quiet \
        --stats "$scratch/stats.json" "$@"
    python3 - "$label" "$backend" "$res" "$scratch/stats.json" <<'PY'
import json, sys
label, backend, res, path = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
s = json.load(open(path))
print(json.dumps({"version": label, "backend": backend, "resolution": res, "slices": s["slices"],
                  "samples": s["samples"], "active_voxels": s["active_voxels"],
                  "voxelize_seconds": s["seconds"]["voxelize"], "total_seconds": sum(s["seconds"].values()),
                  "peak_host_bytes": s["peak_host_bytes"]}))
PY
}

for backend in $backends; do
    for ((i = 0; i < repeats; ++i)); do
        run before "$before" "$backend"
        run after "$after" "$backend"
    done
done
for backend in $backends; do
    for ((i = 0; i < repeats; ++i)); do
        run after-plain-png "$after" "$backend" --cross-section "$scratch/tinted.png"
        run after-albedo "$after" "$backend" --cross-section "$scratch/tinted.png" --albedo
    done
done
