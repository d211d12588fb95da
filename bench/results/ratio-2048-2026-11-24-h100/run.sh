#!/usr/bin/env bash
# The 2048 ratios on another machine of the kind: the sweater and the draped
# garment against OpenVDB's tools, yarnvox five times each.
set -u
export YV_BUILD_DIR=build-dev YV_SCRATCH=/tmp/yvb YV_COMMIT=${YV_COMMIT:?} YV_REPEAT=5
mkdir -p /tmp/yvb
nproc > $OUT/cpu.txt; grep -m1 "model name" /proc/cpuinfo >> $OUT/cpu.txt
bench/baseline_compare.sh .data/sweater_flame_ribbing.bcc 0.1 "2048" > $OUT/sweater.jsonl 2> $OUT/sweater.err
bench/baseline_compare.sh gen:twill:cylinder:410000 0.3 "2048" > $OUT/draped.jsonl 2> $OUT/draped.err
cat $OUT/cpu.txt $OUT/*.err; python3 bench/baseline_summary.py $OUT/sweater.jsonl $OUT/draped.jsonl
python3 -c "
import json
for f in ['sweater', 'draped']:
    for l in open('$OUT/' + f + '.jsonl'):
        d = json.loads(l)
        if d.get('tool') == 'yarnvox': print(f, d['wall_seconds_runs'])"
