#!/usr/bin/env bash
# Point sprites drawn one vertex a slice (glDrawArrays) against one
# instance a slice (glDrawArraysInstanced, YV_POINTS_INSTANCED=1), the same
# binary; the placement's GPU time now apart (gpu_place_seconds).
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "f 2048 0.3" "d 2048 0.3" "s 2048 0.1" "f 4096 0.3" "d 4096 0.3"; do
  set -- $g
  for run in 1 2; do
    for v in vertices instances; do
      inst=""; [ $v = instances ] && inst=1
      start=$(date +%s.%N)
      YV_POINTS_INSTANCED=$inst $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius $3 --resolution $2 --quiet --stats /tmp/yvb/s.json
      end=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$2 $v wall', round($end-$start,3), 'raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'fragments', b['fragments'], 'drawn', b['slices_drawn'], 'passes', b['raster_passes'], 'primitive', b.get('slice_primitive'))" | tee -a $OUT/variants.txt
      md5sum /tmp/yvb/o.vdb | cut -c1-12 >> $OUT/md5-$1$2-$v.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
