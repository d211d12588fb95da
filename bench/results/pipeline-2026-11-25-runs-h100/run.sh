#!/usr/bin/env bash
# The whole run with runs of slices drawn as one point sprite, one call:
# the disk's write speed (dd with fsync); the raster against the binary
# before (71e8f40), alternating, two rounds, with whether the .vdb files
# hold the same bytes but the header UUID; then yarnvox (median of three)
# against OpenVDB's tools on the sweater, the draped and the flat garment
# at 2048 and 4096, and the bare append rate.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=${YV_COMMIT:?}
mkdir -p /tmp/yvb
b=build-dev
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk.txt; rm -f /tmp/yvb/dd.bin
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for bin in yarnvox yarnvox-71e8f40; do $b/$bin voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; done; rm -f /tmp/yvb/o.vdb
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096" "d 0.3 4096" "s 0.1 4096"; do
  set -- $g
  for round in 1 2; do
    for bin in yarnvox-71e8f40 yarnvox; do
      $b/$bin voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/$bin.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 $bin raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'slices', b['slices_drawn'], 'points', b.get('primitives_drawn'), 'fragments', b['fragments'])" | tee -a $OUT/raster.txt
    done
    python3 - <<'PY' | tee -a $OUT/raster.txt
a = bytearray(open("/tmp/yvb/yarnvox.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/yarnvox-71e8f40.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b)
PY
    rm -f /tmp/yvb/*.vdb
  done
done
bench/baseline_compare.sh .data/sweater_flame_ribbing.bcc 0.1 "2048 4096" > $OUT/sweater.jsonl 2> $OUT/errors.txt
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "2048 4096" > $OUT/draped.jsonl 2>> $OUT/errors.txt
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2>> $OUT/errors.txt
build-dev/bench/yv_bench_append --fragments 268435456 --sides 1,2,3,4,8 > $OUT/append.jsonl 2>&1
tail -n +1 $OUT/disk.txt $OUT/errors.txt
python3 bench/baseline_summary.py $OUT/sweater.jsonl $OUT/draped.jsonl $OUT/flat.jsonl --append $OUT/append.jsonl
