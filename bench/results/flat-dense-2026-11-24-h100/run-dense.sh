#!/usr/bin/env bash
# The paper's dense method on the draped and the flat 410k-crossing garments
# at 2048, 4096 and 8192 (the first device call ran run-flat.sh before this;
# the device's file limit kept only part of that call's files, so run-flat.sh
# was run again in a second call).
set -u
mkdir -p /tmp/yvb
[ -f /tmp/yvb/gen-plain-flat-410000.bcc ] || build-dev/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/gen-plain-flat-410000.bcc --quiet
build-dev/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/draped.bcc --quiet
for g in draped:/tmp/yvb/draped.bcc flat:/tmp/yvb/gen-plain-flat-410000.bcc; do
  for res in 2048 4096 8192; do
    name=${g%%:*}; file=${g#*:}
    t0=$(date +%s.%N)
    build-dev/yarnvox voxelize $file -o /tmp/yvb/d.vdb --yarn-radius 0.3 --resolution $res --method dense --quiet --stats $OUT/dense-$name-$res.json > $OUT/dense-$name-$res.log 2>&1
    rc=$?; t1=$(date +%s.%N)
    python3 -c "print('$name', $res, 'rc', $rc, 'wall', round($t1 - $t0, 3))" >> $OUT/dense-wall.txt
    rm -f /tmp/yvb/d.vdb
  done
done
