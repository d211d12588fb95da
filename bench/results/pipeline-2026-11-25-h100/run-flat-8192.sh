#!/usr/bin/env bash
# The same machine's second call: the flat garment at 2048 and 4096 against
# OpenVDB's tools, the draped garment at 8192 against both baselines, and the
# flat garment at 8192 alone.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=${YV_COMMIT:?}
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk-flat-8192.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2> $OUT/flat.err
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "8192" > $OUT/draped-8192.jsonl 2> $OUT/draped-8192.err
t0=$(date +%s.%N)
build-dev/yarnvox voxelize /tmp/yvb/gen-plain-flat-410000.bcc -o /tmp/yvb/f8192.vdb --yarn-radius 0.3 --resolution 8192 --quiet --stats $OUT/flat-8192.json
t1=$(date +%s.%N)
python3 -c "print('wall', round($t1 - $t0, 3), 'file_bytes', $(stat -c %s /tmp/yvb/f8192.vdb))" > $OUT/flat-8192-wall.txt
rm -f /tmp/yvb/f8192.vdb
tail -n +1 $OUT/disk-flat-8192.txt $OUT/flat-8192-wall.txt $OUT/*.err; python3 bench/baseline_summary.py $OUT/flat.jsonl $OUT/draped-8192.jsonl
