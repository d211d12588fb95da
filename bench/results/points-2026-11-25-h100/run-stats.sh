#!/usr/bin/env bash
# The raster's pipeline statistics (a temporary YV_PIPELINE_STATS switch:
# vertex shader invocations, primitives into and out of clipping, fragment
# shader invocations, summed over the passes), and the raster's time with
# one slice in 1024 appending (shaders-sparse-append/: the others test and
# return), flat and draped garments at 2048 and 4096.
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/points-2026-11-25-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "f 2048" "d 2048" "f 4096" "d 4096"; do
  set -- $g
  YV_PIPELINE_STATS=1 $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution $2 --quiet 2> /tmp/yvb/ps.txt
  echo "$1$2 $(tail -1 /tmp/yvb/ps.txt)" | tee -a $OUT/stats.txt
  for v in default sparse-append; do
    dir=""; [ $v != default ] && dir=$r/shaders-$v
    YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution $2 --quiet --stats /tmp/yvb/s.json
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$2 $v raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'items', b['sample_items'], 'drawn', b['slices_drawn'], 'passes', b['raster_passes'])" | tee -a $OUT/stats.txt
    rm -f /tmp/yvb/o.vdb
  done
done
