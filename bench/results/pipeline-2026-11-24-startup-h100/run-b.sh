#!/usr/bin/env bash
# The flat 410k-crossing garment against OpenVDB's tools at 2048 and 4096,
# with the disk's write speed measured in the same call.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=bf682c2
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2> $OUT/flat.err
tail -n +1 $OUT/disk.txt
