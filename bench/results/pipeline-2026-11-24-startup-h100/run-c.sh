#!/usr/bin/env bash
# The draped 410k-crossing garment at 8192 against OpenVDB's tools, with the
# disk's write speed measured in the same call.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=bf682c2
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "8192" > $OUT/draped-8192-baseline.jsonl 2> $OUT/draped-8192.err
tail -n +1 $OUT/disk.txt
