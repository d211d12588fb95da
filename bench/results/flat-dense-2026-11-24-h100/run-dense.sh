#!/usr/bin/env bash
# The flat 410k-crossing garment against OpenVDB's tools (2048, 4096), at
# 8192 alone; the paper's dense method on the draped and flat garments.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb
mkdir -p /tmp/yvb
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2> $OUT/flat.err
t0=$(date +%s.%N)
build-dev/yarnvox voxelize /tmp/yvb/gen-plain-flat-410000.bcc -o /tmp/yvb/f8192.vdb --yarn-radius 0.3 --resolution 8192 --quiet --stats $OUT/flat-8192.json 2>> $OUT/flat.err
t1=$(date +%s.%N)
python3 -c "print('wall', $t1 - $t0)" > $OUT/flat-8192-wall.txt
rm -f /tmp/yvb/f8192.vdb
build-dev/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/draped.bcc --quiet
for g in draped:/tmp/yvb/draped.bcc flat:/tmp/yvb/gen-plain-flat-410000.bcc; do
  for res in 2048 4096 8192; do
    name=${g%%:*}; file=${g#*:}
    t0=$(date +%s.%N)
    build-dev/yarnvox voxelize $file -o /tmp/yvb/d.vdb --yarn-radius 0.3 --resolution $res --method dense --quiet --stats $OUT/dense-$name-$res.json > $OUT/dense-$name-$res.log 2>&1
    rc=$?; t1=$(date +%s.%N)
    python3 -c "print('$name', $res, 'rc', $rc, 'wall', round($t1 - $t0, 3))" >> $OUT/dense-wall.txt
    rm -f /tmp/yvb/d.vdb
  done
done
cat $OUT/dense-wall.txt $OUT/flat-8192-wall.txt; tail -n 3 $OUT/dense-*.log | cut -c1-300
