#!/usr/bin/env bash
# A/B: build-dev/yarnvox-a (before) against build-dev/yarnvox (after), each
# garment alternately, with YV_TRACE summaries of the after runs.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096" "/tmp/yvb/d.bcc 0.3 4096 d4096" "/tmp/yvb/d.bcc 0.3 8192 d8192"; do
  set -- $g
  bins="yarnvox-a yarnvox yarnvox-a yarnvox"; [ $4 = d8192 ] && bins="yarnvox-a yarnvox"
  for bin in $bins; do
    t0=$(date +%s.%N)
    YV_TRACE=$OUT/$4.$bin.trace.json $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
    t1=$(date +%s.%N)
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); s=d['seconds']
print('$4 $bin wall', round($t1-$t0,3), ' '.join(f'{k}={v:.3f}' for k,v in s.items()), 'peak', round(d['peak_host_bytes']/1e9,2), 'file', $(stat -c %s /tmp/yvb/o.vdb))"
    rm -f /tmp/yvb/o.vdb
  done
done
rm -f $OUT/*yarnvox-a.trace.json $OUT/s2048*.json $OUT/d4096*.json
