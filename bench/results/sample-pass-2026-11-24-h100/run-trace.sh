#!/usr/bin/env bash
# Where a 2048 run's time goes with the sampling pass: YV_TRACE of the
# sweater, the draped and the flat garment, the command thread's spans in
# order (start and length, ms) and the per-span sums.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
rm -f /tmp/yvb/o.vdb
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/f.bcc 0.3 2048 f2048"; do
  set -- $g
  t0=$(date +%s.%N)
  YV_TRACE=$OUT/$4.trace.json $b/yarnvox voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
  t1=$(date +%s.%N)
  echo "== $4 wall $(python3 -c "print(round($t1-$t0,3))")"
  python3 - $OUT/$4.trace.json <<'PY'
import json, sys
ev = [e for e in json.load(open(sys.argv[1]))["traceEvents"] if e.get("ph") == "X"]
t0 = min(e["ts"] for e in ev)
main = sorted((e for e in ev if e["tid"] == min(x["tid"] for x in ev)), key=lambda e: e["ts"])
for e in main:
    if e["dur"] >= 5000 or e["name"] in ("finish", "write the stats", "run the command"):
        print(f'  {(e["ts"]-t0)/1000:8.1f} {e["dur"]/1000:8.1f}  {e["name"]}')
print('  end', round((max(e["ts"] + e["dur"] for e in ev) - t0) / 1000, 1))
PY
  rm -f /tmp/yvb/o.vdb
done
