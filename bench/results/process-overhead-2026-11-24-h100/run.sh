#!/usr/bin/env bash
# The process around the command: from the exec to main's timeline origin
# (the dynamic loader, static initialisers), and from the command's end to the
# process's exit, for the sweater at 2048 (three runs), from YV_TRACE's
# origin on the monotonic clock.
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for run in 1 2 3; do
  python3 - "$b/yarnvox" <<'PY' | tee -a $OUT/overhead.txt
import json, os, subprocess, sys, time
cmd = [sys.argv[1], "voxelize", ".data/sweater_flame_ribbing.bcc", "-o", "/tmp/yvb/o.vdb", "--yarn-radius", "0.1",
       "--resolution", "2048", "--quiet"]
t0 = time.monotonic()
subprocess.run(cmd, env={**os.environ, "YV_TRACE": "/tmp/yvb/t.json"}, check=True)
t1 = time.monotonic()
d = json.load(open("/tmp/yvb/t.json"))
origin = d["otherData"]["origin_monotonic_seconds"]
ev = [e for e in d["traceEvents"] if e.get("ph") == "X"]
run = next(e for e in ev if e["name"] == "run the command")
end = origin + (run["ts"] + run["dur"]) * 1e-6
print(f"wall {t1 - t0:.3f} start {origin - t0:.3f} command {run['dur'] * 1e-6:.3f} exit {t1 - end:.3f}")
PY
  rm -f /tmp/yvb/o.vdb
done
cp /tmp/yvb/t.json $OUT/s2048.trace.json
