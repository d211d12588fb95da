#!/usr/bin/env bash
# Diagnosis: the raster's time against the zoom regions' size (a temporary
# YV_SMALL_REGION switch over the least region target, 2^20 fragments), flat and
# draped garments at 2048 and 4096.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "f 2048" "d 2048" "f 4096"; do
  set -- $g
  for n in 1048576 262144 65536; do
    t0=$(date +%s.%N)
    YV_SMALL_REGION=$n $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution $2 --quiet --stats /tmp/yvb/s.json
    t1=$(date +%s.%N)
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$2 small-region $n wall', round($t1-$t0,3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'drawn', b['slices_drawn'], 'passes', b['raster_passes'])" | tee -a $OUT/regions.txt
    rm -f /tmp/yvb/o.vdb
  done
done
