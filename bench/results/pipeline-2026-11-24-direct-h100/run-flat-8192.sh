#!/usr/bin/env bash
# The same call's second half: the flat garment at 2048 and 4096 against
# OpenVDB's tools, and the draped garment at 8192 against both baselines.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=7b05bc7
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk-flat-8192.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh gen:plain:flat:410000 0.3 "2048 4096" > $OUT/flat.jsonl 2> $OUT/flat.err
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "8192" > $OUT/draped-8192.jsonl 2> $OUT/draped-8192.err
tail -n +1 $OUT/disk-flat-8192.txt; cut -c1-300 $OUT/*.jsonl
