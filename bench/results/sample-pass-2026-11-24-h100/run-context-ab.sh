#!/usr/bin/env bash
# A/B, alternating: build-dev/yarnvox-a (the GL context made on a thread of its own)
# against build-dev/yarnvox (made on the thread that runs the GL backend while
# another reads and slices the garment), at 2048.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
for bin in yarnvox yarnvox-a; do $b/$bin voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb; done
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/f.bcc 0.3 2048 f2048"; do
  runs="1 2 3"
  for run in $runs; do
    for bin in yarnvox-a yarnvox; do
      set -- $g
      t0=$(date +%s.%N)
      $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
s=d['seconds']; print('$4 $bin wall', round($t1-$t0,3), 'stages', round(sum(s.values()),3), ' '.join(f'{k}={v:.3f}' for k,v in s.items()), 'active', d['active_voxels'])" | tee -a $OUT/context-ab.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
