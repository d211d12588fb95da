#!/usr/bin/env bash
# The flat 410k-crossing garment against OpenVDB's tools (2048, 4096), and at 8192 alone.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb
mkdir -p /tmp/yvb
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2> $OUT/flat.err
t0=$(date +%s.%N)
build-dev/yarnvox voxelize /tmp/yvb/gen-plain-flat-410000.bcc -o /tmp/yvb/f8192.vdb --yarn-radius 0.3 --resolution 8192 --quiet --stats $OUT/flat-8192.json 2>> $OUT/flat.err
t1=$(date +%s.%N)
python3 -c "print('wall', $t1 - $t0)" > $OUT/flat-8192-wall.txt
rm -f /tmp/yvb/f8192.vdb
