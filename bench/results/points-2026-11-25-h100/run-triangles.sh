#!/usr/bin/env bash
# A/B, alternating, one binary with a temporary YV_SLICE_PRIMITIVE switch:
# each slice drawn as a point sprite (the default on a GPU) against one
# triangle (the default on llvmpipe), now that the fragment shader is lean
# and the bound tighter. Raster time, items, whether the .vdb files hold the
# same bytes but the header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for v in point triangle; do
  YV_SLICE_PRIMITIVE=$v $b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
done
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096"; do
  set -- $g
  for run in 1 2; do
    for v in point triangle; do
      YV_SLICE_PRIMITIVE=$v $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$v.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 $v', b['slice_primitive'], 'raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'fragments', b['fragments'], 'passes', b['raster_passes'])" | tee -a $OUT/triangles.txt
    done
    python3 - <<'PY' | tee -a $OUT/triangles.txt
a = bytearray(open("/tmp/yvb/point.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/triangle.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b)
PY
    rm -f /tmp/yvb/*.vdb
  done
done
