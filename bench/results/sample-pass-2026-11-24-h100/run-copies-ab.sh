#!/usr/bin/env bash
# A/B, alternating: build-dev/yarnvox-a (each region's face drawn once)
# against build-dev/yarnvox (slices spread over 8 copies of the face side by
# side), the flat and the draped garment.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
for bin in yarnvox yarnvox-a; do $b/$bin voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb; done
for g in "/tmp/yvb/f.bcc 0.3 2048 f2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/f.bcc 0.3 4096 f4096" "/tmp/yvb/f.bcc 0.3 8192 f8192"; do
  runs="1 2"; [ ${g##* } = f8192 ] && runs=1
  for run in $runs; do
    for bin in yarnvox-a yarnvox; do
      set -- $g
      t0=$(date +%s.%N)
      $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$4 $bin wall', round($t1-$t0,3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],3), 'sample', round(b['gpu_sample_seconds'],3), 'items', b['sample_items'], 'fragments', b['fragments'], 'active', d['active_voxels'])" | tee -a $OUT/copies-ab.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
