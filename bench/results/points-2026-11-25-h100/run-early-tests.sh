#!/usr/bin/env bash
# A/B, alternating, one binary: append.frag as built in against
# shaders-early-tests/ (the same with layout(early_fragment_tests), which
# changes nothing where there is no depth or stencil buffer, but may let
# the hardware drop its ordering of fragments with side effects). Raster
# time, items, and whether the two .vdb files hold the same bytes but the
# header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
r=bench/results/points-2026-11-25-h100
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for v in default early-tests; do
  dir=""; [ $v = early-tests ] && dir=$r/shaders-early-tests
  YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
done
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096" "d 0.3 4096" "s 0.1 4096" ; do
  set -- $g
  for run in 1 2; do
    for v in default early-tests; do
      dir=""; [ $v = early-tests ] && dir=$r/shaders-early-tests
      t0=$(date +%s.%N)
      YV_SHADER_DIR=$dir $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$v.vdb --yarn-radius $2 --resolution $3 "${@:4}" --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 ${*:4} $v wall', round($t1-$t0,3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'fragments', b['fragments'], 'passes', b['raster_passes'])" | tee -a $OUT/early-tests.txt
    done
    python3 - <<'PY' | tee -a $OUT/early-tests.txt
a = bytearray(open("/tmp/yvb/default.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/early-tests.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b)
PY
    rm -f /tmp/yvb/default.vdb /tmp/yvb/early-tests.vdb
  done
done
