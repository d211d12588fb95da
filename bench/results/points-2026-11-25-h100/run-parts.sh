#!/usr/bin/env bash
# Diagnosis of the raster's parts (flat and draped garments, 2048 and
# 4096): the built-in shaders; shaders-noop/ (every pixel returns at once
# but those of one slice in 1024: the raster without the test and the
# append); shaders-tiny/ (one-pixel sprites: what each slice costs apart
# from its pixels). Both lose items: a diagnosis, not a result.
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/points-2026-11-25-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "f 2048" "d 2048" "f 4096" "d 4096"; do
  set -- $g
  for v in default noop tiny; do
    dir=""; [ $v != default ] && dir=$r/shaders-$v
    YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution $2 --quiet --stats /tmp/yvb/s.json
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$2 $v raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'items', b['sample_items'], 'drawn', b['slices_drawn'], 'passes', b['raster_passes'])" | tee -a $OUT/parts.txt
    rm -f /tmp/yvb/o.vdb
  done
done
