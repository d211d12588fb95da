#!/usr/bin/env bash
# The sweater against OpenVDB's tools at 2048 and 4096 (the call before
# returned at most eight files, and this one was left out), with the disk's
# write speed, and the bare append rate.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=f13a55d
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh .data/sweater_flame_ribbing.bcc 0.1 "2048 4096" > $OUT/sweater.jsonl 2> $OUT/sweater.err
build-dev/bench/yv_bench_append --fragments 268435456 --sides 1,2,4,8 > $OUT/append.jsonl 2>&1
tail -n +1 $OUT/disk.txt
