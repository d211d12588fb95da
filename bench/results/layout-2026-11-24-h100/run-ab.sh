#!/usr/bin/env bash
# A/B: build-dev/yarnvox-a (7b05bc7) against build-dev/yarnvox (slices packed
# during the zoom plan, topology side by side), alternately.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096" "/tmp/yvb/d.bcc 0.3 8192 d8192"; do
  set -- $g
  bins="yarnvox-a yarnvox yarnvox-a yarnvox yarnvox-a yarnvox"; [ $4 = d8192 ] && bins="yarnvox-a yarnvox"
  for bin in $bins; do
    t0=$(date +%s.%N)
    YV_TRACE=/tmp/yvb/t.json $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
    t1=$(date +%s.%N)
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); s=d['seconds']
ev=json.load(open('/tmp/yvb/t.json'))['traceEvents']
lay=[e['dur']/1e6 for e in ev if e['name']=='sort and lay out the leaves']
print('$4 $bin wall', round($t1-$t0,3), ' '.join(f'{k}={v:.3f}' for k,v in s.items()), 'layout', round(sum(lay),3))"
    rm -f /tmp/yvb/o.vdb
  done
done
