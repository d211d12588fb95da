#!/usr/bin/env bash
# A machine's first GL run against the next one (sweater, 2048), and the flat
# 410k-crossing garment at 8192 with its file kept long enough to be measured.
set -u
S=/tmp/yvc; mkdir -p $S
for run in first second; do
  t0=$(date +%s.%N)
  build-dev/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o $S/s.vdb --yarn-radius 0.1 --resolution 2048 --quiet --stats $OUT/sweater-2048-$run.json
  t1=$(date +%s.%N)
  python3 -c "print('$run', 'wall', round($t1 - $t0, 3))" >> $OUT/walls.txt
done
build-dev/yarnvox gen --pattern plain --shape flat --crossings 410000 -o $S/flat.bcc --quiet
t0=$(date +%s.%N)
build-dev/yarnvox voxelize $S/flat.bcc -o $S/f.vdb --yarn-radius 0.3 --resolution 8192 --quiet --stats $OUT/flat-8192.json
t1=$(date +%s.%N)
python3 -c "print('flat-8192', 'wall', round($t1 - $t0, 3), 'file_bytes', $(stat -c %s $S/f.vdb))" >> $OUT/walls.txt
cat $OUT/walls.txt
