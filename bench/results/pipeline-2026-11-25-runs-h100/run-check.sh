#!/usr/bin/env bash
# 4925e61 (the runs' buffers moved to storage bindings 3 and 4, the rest
# unchanged but comments and checks) against 71e8f40, alternating, once:
# raster time, points drawn, and whether the .vdb files hold the same bytes
# but the header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for bin in yarnvox yarnvox-71e8f40; do $b/$bin voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; done; rm -f /tmp/yvb/o.vdb
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096"; do
  set -- $g
  for bin in yarnvox-71e8f40 yarnvox; do
    $b/$bin voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$bin.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
    python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 $bin raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'items', b['sample_items'], 'slices', b['slices_drawn'], 'points', b.get('primitives_drawn'), 'fragments', b['fragments'])" | tee -a $OUT/check.txt
  done
  python3 - <<'PY' | tee -a $OUT/check.txt
a = bytearray(open("/tmp/yvb/yarnvox.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/yarnvox-71e8f40.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b)
PY
  rm -f /tmp/yvb/*.vdb
done
