#!/usr/bin/env bash
# Where the flat garment's raster time goes at 2048 (its slices take twice
# the draped garment's time for as many items): the same binary with
# YV_SHADER_DIR variants: sprites 0.8 and 1.25 times as wide (the items
# change: a diagnosis only), and a fragment shader that returns at once
# (the raster alone, no append).
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/flat-raster-2026-11-24-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "f 2048" "d 2048" "f 4096" "d 4096"; do
  set -- $g
  for run in 1 2; do
    for v in default scale08 scale125 empty; do
      dir=""; [ $v != default ] && dir=$r/shaders-$v
      YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution $2 --quiet --stats /tmp/yvb/s.json
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$2 $v raster', round(b['gpu_raster_seconds'],4), 'items', b['sample_items'], 'drawn', b['slices_drawn'], 'passes', b['raster_passes'])" | tee -a $OUT/variants.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
