#!/usr/bin/env bash
# A/B, alternating: each point sprite and its test's terms worked out with
# the slices' placement on every compute unit (build-dev/yarnvox) against
# the vertex shader working them out (build-dev/yarnvox-before, fb313e1);
# build-dev/yarnvox built at 902f1ef (reverted in the next commit).
# Raster and sampling time, items, wall time, and whether the two .vdb
# files hold the same bytes but the header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for v in yarnvox yarnvox-before; do
  $b/$v voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
done
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096" "d 0.3 4096" "s 0.1 4096" "s 0.1 2048 --cross-section disk"; do
  set -- $g
  for run in 1 2; do
    for v in yarnvox yarnvox-before; do
      t0=$(date +%s.%N)
      $b/$v voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$v.vdb --yarn-radius $2 --resolution $3 "${@:4}" --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 ${*:4} $v wall', round($t1-$t0,3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'fragments', b['fragments'], 'passes', b['raster_passes'])" | tee -a $OUT/sprites-in-compute.txt
    done
    python3 - <<'PY' | tee -a $OUT/sprites-in-compute.txt
a = bytearray(open("/tmp/yvb/yarnvox.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/yarnvox-before.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b)
PY
    rm -f /tmp/yvb/*.vdb
  done
done
