#!/usr/bin/env bash
# A/B: build-dev/yarnvox-a (octree split of every axis) against
# build-dev/yarnvox (hot boxes halved along their long axes only).
set -u
mkdir -p /tmp/yvb
b=build-dev
TIMEFORMAT="version wall %R"; { for i in 1 2 3 4 5; do time $b/yarnvox --version > /dev/null; done; } 2>&1 | tee $OUT/start.txt
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "/tmp/yvb/f.bcc 0.3 2048 f2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/f.bcc 0.3 4096 f4096" "/tmp/yvb/d.bcc 0.3 4096 d4096" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096"; do
  for run in 1 2; do
    for bin in yarnvox-a yarnvox; do
      set -- $g
      t0=$(date +%s.%N)
      $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']; s=d['seconds']
print('$4 $bin wall', round($t1-$t0,3), 'in', round(sum(s.values()),3), 'plan', round(s['plan'],3), 'voxelize', round(s['voxelize'],3), 'write', round(s['write'],3), 'regions', b['zoom_regions'], 'passes', b['raster_passes'], 'retries', b['overflow_retries'], 'raster', round(b['gpu_raster_seconds'],3), 'sample', round(b['gpu_sample_seconds'],3), 'drawn', b.get('slices_drawn'), 'items', b['sample_items'], 'fragments', b['fragments'], 'active', d['active_voxels'], 'fv', d['fiber_volume'], 'peak', round(d['peak_host_bytes']/1e9,2))" | tee -a $OUT/zoom-ab.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
