#!/usr/bin/env bash
# A/B, alternating, one binary: the sprite and the append test bounded by
# what the sampling reads of the footprint (the shaders built in) against
# shaders-edges-sum/ (by half the sum of its edges, YV_SHADER_DIR). Raster
# and sampling time, sample items, wall time, and whether the two .vdb files
# hold the same bytes but the header UUID; the disk cross-section and
# supersampling as well.
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/points-2026-11-25-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for v in default edges-sum; do
  dir=""; [ $v = edges-sum ] && dir=$r/shaders-edges-sum
  YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
done
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096" "d 0.3 4096" "s 0.1 4096" "s 0.1 2048 --cross-section disk" "d 0.3 1024 --supersample 2"; do
  set -- $g
  for run in 1 2; do
    for v in default edges-sum; do
      dir=""; [ $v = edges-sum ] && dir=$r/shaders-edges-sum
      t0=$(date +%s.%N)
      YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$v.vdb --yarn-radius $2 --resolution $3 "${@:4}" --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 ${*:4} $v wall', round($t1-$t0,3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'fragments', b['fragments'], 'passes', b['raster_passes'])" | tee -a $OUT/footprint-reach.txt
    done
    python3 - <<'PY' | tee -a $OUT/footprint-reach.txt
a = bytearray(open("/tmp/yvb/default.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/edges-sum.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b)
PY
    rm -f /tmp/yvb/default.vdb /tmp/yvb/edges-sum.vdb
  done
done
