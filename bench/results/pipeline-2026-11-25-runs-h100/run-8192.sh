#!/usr/bin/env bash
# The same commit at 8192, one call: the disk's write speed (dd with
# fsync), the draped garment (two runs) against OpenVDB's density-only
# baseline (one run; the orientation baseline took 201 s in
# pipeline-2026-11-25-h100/ and is left out here), and the flat garment once.
set -u
mkdir -p /tmp/yvb
b=build-dev
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2> $OUT/disk-8192.txt; rm -f /tmp/yvb/dd.bin
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize /tmp/yvb/f.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for run in "d 1" "d 2" "f 1"; do
  set -- $run
  t0=$(date +%s.%N)
  $b/yarnvox voxelize /tmp/yvb/$1.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.3 --resolution 8192 --quiet --stats /tmp/yvb/s.json
  t1=$(date +%s.%N)
  python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); b=d['backend_stats']
print(json.dumps({'garment': '$1', 'run': $2, 'resolution': 8192, 'wall_seconds': round($t1 - $t0, 3), 'file_bytes': $(stat -c %s /tmp/yvb/o.vdb),
  'peak_host_bytes': d['peak_host_bytes'], 'seconds': d['seconds'], 'gpu_raster_seconds': b['gpu_raster_seconds'],
  'gpu_sample_seconds': b['gpu_sample_seconds'], 'fragments': b['fragments'], 'slices_drawn': b['slices_drawn'],
  'primitives_drawn': b['primitives_drawn']}))" | tee -a $OUT/yarnvox-8192.jsonl
  rm -f /tmp/yvb/o.vdb
done
t0=$(date +%s.%N)
line=$($b/bench/yv_openvdb_baseline --input /tmp/yvb/d.bcc --yarn-radius 0.3 --resolution 8192 -o /tmp/yvb/base.vdb)
t1=$(date +%s.%N)
python3 -c 'import json, sys; d = json.loads(sys.argv[1]); d["wall_seconds"] = round(float(sys.argv[3]) - float(sys.argv[2]), 3); print(json.dumps(d))' "$line" "$t0" "$t1" | tee $OUT/baseline-draped-8192.jsonl
rm -f /tmp/yvb/base.vdb
cat $OUT/disk-8192.txt
