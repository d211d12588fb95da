#!/usr/bin/env bash
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
for v in base nofetch noz onefetch base; do
  for g in "/tmp/yvb/d.bcc 0.3 4096 d4096" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096"; do
    set -- $g
    YV_SHADER_DIR=$PWD/$b/sh-$v $b/yarnvox voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json 2>&1 | tail -2
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$v $4 raster', round(b['gpu_raster_seconds'],3), 'fragments', b['fragments'], 'active', d['active_voxels'])"
    rm -f /tmp/yvb/o.vdb /tmp/yvb/s.json
  done
done
