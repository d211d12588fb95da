#!/usr/bin/env bash
# The flat garment at 2048 in smaller regions (--fragment-budget B: each
# region within B/2 fragments expected): does the raster's cost a slice
# follow the region's size?
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in f d; do
  for run in 1 2; do
    for budget in 0 16000000 8000000 4000000 2000000; do
      opt=""; [ $budget != 0 ] && opt="--fragment-budget $budget"
      t0=$(date +%s.%N)
      $b/yarnvox voxelize /tmp/yvb/$g.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 2048 --quiet --stats /tmp/yvb/s.json $opt
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('${g}2048 budget $budget wall', round($t1-$t0,3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],4), 'items', b['sample_items'], 'drawn', b['slices_drawn'], 'regions', b['zoom_regions'], 'passes', b['raster_passes'], 'retries', b['overflow_retries'])" | tee -a $OUT/budget.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
