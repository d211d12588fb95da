#!/usr/bin/env bash
# Second sweep: the command reset on the GPU (no host write that waits),
# and run length 1 drawn directly (no runs pass, no indirect draw).
# Runs of slices drawn as one point sprite (slice_runs.comp), swept through
# the temporary switches YV_RUN_SLICES (slices a run holds at most) and
# YV_RUN_SPREAD (pixels its centres may spread over), alternating in one
# call with the binary before (71e8f40, a point a slice). Raster time (its
# placing part now includes joining the runs), items, points drawn, and
# whether each .vdb holds the same bytes as 71e8f40's but the header UUID.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
cp .data/sweater_flame_ribbing.bcc /tmp/yvb/s.bcc
for bin in yarnvox yarnvox-71e8f40; do $b/$bin voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; done; rm -f /tmp/yvb/o.vdb
for g in "f 0.3 2048" "d 0.3 2048" "s 0.1 2048" "f 0.3 4096"; do
  set -- $g
  for round in 1 2; do
    for v in before "1 2" "2 2" "3 2" "4 2" "4 3"; do
      bin=yarnvox; runs=""; spread=""
      if [ "$v" = before ]; then bin=yarnvox-71e8f40; else set -- $g $v; runs=$4; spread=$5; fi
      out=/tmp/yvb/$(echo $v | tr ' ' _).vdb
      YV_RUN_SLICES=$runs YV_RUN_SPREAD=$spread $b/$bin voxelize /tmp/yvb/$1.bcc -o $out --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$1$3 [$v] raster', round(b['gpu_raster_seconds'],4), 'place', round(b['gpu_place_seconds'],4), 'sample', round(b['gpu_sample_seconds'],4), 'items', b['sample_items'], 'slices', b['slices_drawn'], 'points', b.get('primitives_drawn'), 'fragments', b['fragments'])" | tee -a $OUT/sweep2.txt
      set -- $g
    done
    python3 - <<'PY' | tee -a $OUT/sweep2.txt
import glob
ref = bytearray(open("/tmp/yvb/before.vdb", "rb").read()); ref[21:57] = bytes(36)
same = []
for f in sorted(glob.glob("/tmp/yvb/*_*.vdb")):
    b = bytearray(open(f, "rb").read()); b[21:57] = bytes(36)
    same.append(f.split("/")[-1][:-4] + (" same" if b == ref else " DIFFERENT"))
print("  against 71e8f40, the bytes but the UUID:", ", ".join(same))
PY
    rm -f /tmp/yvb/*.vdb
  done
done
