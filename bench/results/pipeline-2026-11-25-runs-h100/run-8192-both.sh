#!/usr/bin/env bash
# The draped garment at 8192 against both baselines in one call (yarnvox the
# median of three, OpenVDB's tools density only and with the orientation
# grid), with the disk's write speed (dd with fsync).
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=${YV_COMMIT:?}
mkdir -p /tmp/yvb
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk-8192-both.txt; rm -f /tmp/yvb/dd.bin
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "8192" > $OUT/draped-8192-both.jsonl 2> $OUT/draped-8192-both.err
tail -n +1 $OUT/disk-8192-both.txt $OUT/draped-8192-both.err
python3 bench/baseline_summary.py $OUT/draped-8192-both.jsonl --append bench/results/pipeline-2026-11-25-runs-h100/append.jsonl
