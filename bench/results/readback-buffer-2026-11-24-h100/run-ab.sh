#!/usr/bin/env bash
# A/B, alternating: build-dev/yarnvox-a (two pinned readback buffers, one
# pass's copy in each in turn) against build-dev/yarnvox-b (one buffer, the
# second only while two resolves are in flight). Wall time, the pinned
# allocations' time (YV_TRACE), and whether the two .vdb files hold the
# same bytes (but the header's UUID).
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox-b gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox-b voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 4096 d4096" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096"; do
  for run in 1 2 3; do
    for bin in yarnvox-a yarnvox-b; do
      set -- $g
      t0=$(date +%s.%N)
      YV_TRACE=/tmp/yvb/t.json $b/$bin voxelize $1 -o /tmp/yvb/$bin.vdb --yarn-radius $2 --resolution $3 --quiet
      t1=$(date +%s.%N)
      python3 - <<PY | tee -a $OUT/ab.txt
import json
ev = [e for e in json.load(open("/tmp/yvb/t.json"))["traceEvents"] if e.get("ph") == "X"]
alloc = sum(e["dur"] for e in ev if e["name"] == "allocate a readback buffer") / 1000
n = sum(1 for e in ev if e["name"] == "allocate a readback buffer")
vox = next(e["dur"] for e in ev if e["name"] == "voxelize") / 1000
print("$4 $bin wall", round($t1 - $t0, 3), "voxelize", round(vox, 1), "ms readback allocations", n, round(alloc, 1), "ms")
PY
    done
    python3 - <<'PY' | tee -a $OUT/ab.txt
a = bytearray(open("/tmp/yvb/yarnvox-a.vdb", "rb").read()); b = bytearray(open("/tmp/yvb/yarnvox-b.vdb", "rb").read())
a[21:57] = b[21:57] = bytes(36)
print("  same bytes but the UUID:", a == b, len(a))
PY
    rm -f /tmp/yvb/yarnvox-a.vdb /tmp/yvb/yarnvox-b.vdb
  done
done
