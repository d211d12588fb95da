#!/usr/bin/env bash
# A/B, alternating, one binary (71e8f40): slice.vert as built in against
# shaders-lean/ (only the outputs append.frag reads: the ten that only
# dense.frag reads left out), and what a slice costs apart from its pixels:
# shaders-tiny/ (one-pixel sprites), shaders-tiny-lean/ (the same, lean),
# shaders-tiny-lean-cull-half/ (the same, every odd slice clipped away
# before the raster). The tiny variants lose items: a diagnosis only.
# Raster time, items, and whether default and lean .vdb files hold the
# same bytes but the header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/varyings-2026-11-25-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096"; do
  set -- $g
  for run in 1 2; do
    for v in default lean tiny tiny-lean tiny-lean-cull-half; do
      dir=""; [ $v != default ] && dir=$r/shaders-$v
      YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$v.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 $v raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'drawn', b['slices_drawn'], 'fragments', b['fragments'])" | tee -a $OUT/varyings.txt
    done
    python3 - <<'PY' | tee -a $OUT/varyings.txt
a = bytearray(open("/tmp/yvb/default.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/lean.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  default and lean, same bytes but the UUID:", a == b)
PY
    rm -f /tmp/yvb/*.vdb
  done
done
