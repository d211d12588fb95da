#!/usr/bin/env bash
# The live view's stops, two builds A/B on one machine, alternating (A then B
# in odd rounds, B then A in even ones), with default slices and with the
# paper's 50 slices a segment (41 M slices): bench/view_bench.sh on the draped
# 410k-crossing garment beside its 512 ray cast, five stops a run. Appends
# each run's JSON lines to OUT/stops-{default,41M}-{a,b}.jsonl and prints a
# line a run: the final and first pictures and the run, from the request.
#
#   bench/view_stops_ab.sh BUILD_A BUILD_B OUT [ROUNDS]
#   BUILD_*: folders with yarnvox and bench/yv_view_bench; env YV_SCRATCH (default /tmp/yv)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
a=$1 b=$2 out=$3 rounds=${4:-2}
scratch=${YV_SCRATCH:-/tmp/yv}
mkdir -p "$scratch" "$out"
garment="$scratch/draped.bcc"
[ -f "$garment" ] || "$a/yarnvox" gen --pattern twill --shape cylinder --crossings 410000 -o "$garment" --quiet
for round in $(seq "$rounds"); do
  sides="a b"; [ $((round % 2)) = 0 ] && sides="b a"
  for side in $sides; do
    build=$a; [ "$side" = b ] && build=$b
    for slices in default 41M; do
      extra=(); [ "$slices" = 41M ] && extra=(--slices-per-segment 50)
      YV_BUILD_DIR="$build" bash "$root/bench/view_bench.sh" "$garment" --size 1280x720 --frames 4 --stops 5 -- \
        --resolution 512 --device 0 "${extra[@]}" > "$scratch/run.jsonl"
      cat "$scratch/run.jsonl" >> "$out/stops-$slices-$side.jsonl"
      python3 - "$scratch/run.jsonl" "$round" "$side" "$slices" <<'PY'
import json, sys
for line in open(sys.argv[1]):
    d = json.loads(line)
    if d.get("phase") == "stop-and-voxelize":
        print(*sys.argv[2:5], "final p50 %.0f max %.0f ms, first p50 %.0f ms, run p50 %.3f s" % (
            d["stopToDetailMs"]["p50"], d["stopToDetailMs"]["max"], d["stopToFirstPictureMs"]["p50"], d["runSeconds"]["p50"]))
PY
    done
  done
done
