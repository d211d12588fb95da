#!/usr/bin/env bash
# A/B, alternating, one binary: the raster's item append through the atomic
# counter (built in), through an atomicAdd on the counter's word in its
# storage block (shaders-ssbo-atomic/), and one atomicAdd a subgroup
# (shaders-ballot/, GL_KHR_shader_subgroup). Raster time, items, and whether
# each .vdb holds the built-in's bytes but the header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/points-2026-11-25-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for v in default ssbo-atomic ballot; do
  dir=""; [ $v != default ] && dir=$r/shaders-$v
  YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet || echo "$v failed"; rm -f /tmp/yvb/o.vdb
done
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096" "d 0.3 4096" "s 0.1 4096"; do
  set -- $g
  for run in 1 2; do
    for v in default ssbo-atomic ballot; do
      dir=""; [ $v != default ] && dir=$r/shaders-$v
      YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$v.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 $v raster', round(b['gpu_raster_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'fragments', b['fragments'], 'passes', b['raster_passes'])" | tee -a $OUT/atomics.txt
    done
    python3 - <<'PY' | tee -a $OUT/atomics.txt
def load(n):
    a = bytearray(open("/tmp/yvb/%s.vdb" % n, "rb").read()); a[21:57] = bytes(36); return a
base = load("default")
print("  same bytes but the UUID:", [load(n) == base for n in ("ssbo-atomic", "ballot")])
PY
    rm -f /tmp/yvb/*.vdb
  done
done
