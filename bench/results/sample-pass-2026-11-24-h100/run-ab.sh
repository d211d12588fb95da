#!/usr/bin/env bash
# A/B: build-dev/yarnvox-a (sampling in the fragment shader) against
# build-dev/yarnvox (slices placed and sampled in compute passes, the raster
# only appends sample items), each garment alternately.
set -u
mkdir -p /tmp/yvb
b=build-dev
nvidia-smi --query-gpu=name --format=csv,noheader
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
rm -f /tmp/yvb/o.vdb
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096" \
         "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/d.bcc 0.3 4096 d4096" "/tmp/yvb/f.bcc 0.3 2048 f2048" \
         "/tmp/yvb/d.bcc 0.3 8192 d8192"; do
  set -- $g
  bins="yarnvox-a yarnvox yarnvox-a yarnvox"; [ $4 = d8192 ] && bins="yarnvox-a yarnvox"
  for bin in $bins; do
    t0=$(date +%s.%N)
    $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
    t1=$(date +%s.%N)
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); s=d['seconds']; b=d['backend_stats']
print('$4 $bin wall', round($t1-$t0,3), ' '.join(f'{k}={v:.3f}' for k,v in s.items()),
      'raster', round(b['gpu_raster_seconds'],3), 'sample', round(b.get('gpu_sample_seconds',0),3),
      'items', b.get('sample_items',0), 'fragments', b['fragments'], 'passes', b['raster_passes'],
      'active', d['active_voxels'], 'peak', round(d['peak_host_bytes']/1e9,2), 'file', $(stat -c %s /tmp/yvb/o.vdb))" | tee -a $OUT/ab.txt
    rm -f /tmp/yvb/o.vdb
  done
done
