#!/usr/bin/env bash
# The whole-run benchmark on the GPU machine after the point sprites: the
# disk's write speed (dd with fsync), yarnvox against OpenVDB's tools (the
# sweater, the draped and the flat garment at 2048 and 4096), the draped
# garment at 8192 alone, and the bare append rate.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=f13a55d
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh .data/sweater_flame_ribbing.bcc 0.1 "2048 4096" > $OUT/sweater.jsonl 2> $OUT/sweater.err
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "2048 4096" > $OUT/draped.jsonl 2> $OUT/draped.err
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2> $OUT/flat.err
t0=$(date +%s.%N)
build-dev/yarnvox voxelize /tmp/yvb/gen-twill-cylinder-410000.bcc -o /tmp/yvb/d8192.vdb --yarn-radius 0.3 --resolution 8192 --quiet --stats $OUT/draped-8192.json
t1=$(date +%s.%N)
python3 -c "print('wall', round($t1 - $t0, 3), 'file_bytes', $(stat -c %s /tmp/yvb/d8192.vdb))" > $OUT/draped-8192-wall.txt
rm -f /tmp/yvb/d8192.vdb
tail -n +1 $OUT/disk.txt $OUT/draped-8192-wall.txt
