#!/usr/bin/env bash
# Probe: memcpy into fresh / huge-page / prefaulted memory; the raster's
# instance order (YV_LANES) on the flat and the draped garment; a trace of
# the sweater at 2048.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/memfault 344 2>&1 | tee $OUT/memfault.txt
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for g in "/tmp/yvb/f.bcc 0.3 2048 f2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/f.bcc 0.3 4096 f4096" ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048"; do
  for run in 1 2; do
    for lanes in 1 64 1024 16384; do
      set -- $g
      t0=$(date +%s.%N)
      YV_LANES=$lanes $b/yarnvox voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print('$4 lanes $lanes wall', round($t1-$t0,3), 'slices', round(d['seconds']['slices'],3), 'voxelize', round(d['seconds']['voxelize'],3), 'raster', round(b['gpu_raster_seconds'],3), 'sample', round(b['gpu_sample_seconds'],3), 'items', b['sample_items'], 'fragments', b['fragments'], 'active', d['active_voxels'], 'mass', d.get('mass'))" | tee -a $OUT/lanes.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
# Huge pages for the packed bricks (default) against small ones (YV_NO_HUGE=1).
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096"; do
  for run in 1 2; do
    for huge in 1 0; do
      set -- $g
      env=""; [ $huge = 0 ] && env="YV_NO_HUGE=1"
      t0=$(date +%s.%N)
      env $env YV_TRACE=/tmp/yvb/t.json $b/yarnvox voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 - /tmp/yvb/t.json <<PY | tee -a $OUT/huge.txt
import json, sys
ev = [e for e in json.load(open(sys.argv[1]))["traceEvents"] if e.get("ph") == "X"]
sums = {}
for e in ev: sums[e["name"]] = sums.get(e["name"], 0) + e["dur"] / 1000
d = json.load(open("/tmp/yvb/s.json"))
print("$4 huge $huge wall", round($t1 - $t0, 3), "voxelize", round(d["seconds"]["voxelize"], 3), "write", round(d["seconds"]["write"], 3),
      " ".join(f"{k.split()[0]}:{round(sums.get(k, 0), 1)}" for k in ("grow the packed bricks", "copy the packed bricks", "take in the pass before", "encode leaves")))
PY
      [ $run = 1 ] && [ $4 = s2048 ] && cp /tmp/yvb/t.json $OUT/$4-huge$huge.trace.json
      rm -f /tmp/yvb/o.vdb
    done
  done
done
YV_TRACE=$OUT/f2048.trace.json $b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 2048 --quiet
rm -f /tmp/yvb/o.vdb
