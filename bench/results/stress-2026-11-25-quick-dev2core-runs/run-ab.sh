#!/usr/bin/env bash
# llvmpipe (this 2-core machine): the quick stress set's gl runs with the
# binary before (71e8f40) and this commit's, alternating, three rounds.
# llvmpipe draws triangles, whose raster shaders changed (the varyings
# packed four to a slot, the test in a loop of one slice).
set -u
out=${1:?output file}
for round in 1 2 3; do
  for bin in build-dev/yarnvox-71e8f40 build-cc/yarnvox; do
    python3 bench/stress.py --quick --methods gl --sizes 0.1M --yarnvox $bin --out /tmp/stress-ab > /dev/null 2>&1
    python3 - "$bin" <<'PY' | tee -a $out
import json, sys
rows = json.load(open("/tmp/stress-ab/results.json"))
rows = rows["runs"] if isinstance(rows, dict) else rows
print(sys.argv[1].split("/")[-1], " ".join(f'{r["size"]} {r["resolution"]} gl: {r["wall_seconds"]:.2f} s {r["active_voxels"]} voxels' for r in rows))
PY
  done
done
