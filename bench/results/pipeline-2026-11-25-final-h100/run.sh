#!/usr/bin/env bash
# The whole run at the session's last code, one call: the disk's write
# speed (dd with fsync), yarnvox (median of three) against OpenVDB's tools
# on the sweater, the draped and the flat garment at 2048 and 4096, and the
# bare append rate.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=${YV_COMMIT:?}
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh .data/sweater_flame_ribbing.bcc 0.1 "2048 4096" > $OUT/sweater.jsonl 2> $OUT/errors.txt
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "2048 4096" > $OUT/draped.jsonl 2>> $OUT/errors.txt
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2>> $OUT/errors.txt
build-dev/bench/yv_bench_append --fragments 268435456 --sides 1,2,3,4,8 > $OUT/append.jsonl 2>&1
tail -n +1 $OUT/disk.txt $OUT/errors.txt; python3 bench/baseline_summary.py $OUT/sweater.jsonl $OUT/draped.jsonl $OUT/flat.jsonl; cut -c1-200 $OUT/append.jsonl
