#!/usr/bin/env bash
# A/B, three times each, alternating: build-dev/yarnvox-a (the pass before's
# packed bricks taken in while the GPU rasterizes) against build-dev/yarnvox
# (taken in while it builds and resolves the bricks), with the waits summed
# from YV_TRACE.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
$b/yarnvox-a voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o2.vdb --yarn-radius 0.1 --resolution 1024 --quiet
rm -f /tmp/yvb/o.vdb /tmp/yvb/o2.vdb
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/d.bcc 0.3 4096 d4096"; do
  for run in 1 2 3; do
    for bin in yarnvox-a yarnvox; do
      set -- $g
      t0=$(date +%s.%N)
      YV_TRACE=/tmp/yvb/t.json $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 - /tmp/yvb/s.json /tmp/yvb/t.json "$4 $bin" $t0 $t1 <<'PY' | tee -a $OUT/overlap-ab.txt
import json, sys
d = json.load(open(sys.argv[1])); s = d['seconds']
ev = [e for e in json.load(open(sys.argv[2]))['traceEvents'] if e.get('ph') == 'X']
main = min(e['tid'] for e in ev)
def total(name, tid=None):
    return round(sum(e['dur'] for e in ev if e['name'] == name and (tid is None or e['tid'] == tid)) / 1000, 1)
print(sys.argv[3], 'wall', round(float(sys.argv[5]) - float(sys.argv[4]), 3), 'voxelize', round(s['voxelize'], 3),
      'take-in ms', total('take in the pass before', main), 'append ms', total('append the packed bricks'),
      'resolve-wait ms', total("wait for the resolve's totals", main), 'active', d['active_voxels'])
PY
      rm -f /tmp/yvb/o.vdb
    done
  done
done
