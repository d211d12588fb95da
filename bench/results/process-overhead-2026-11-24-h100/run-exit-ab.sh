#!/usr/bin/env bash
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 512 --quiet; rm -f /tmp/yvb/o.vdb
for run in 1 2 3 4; do
 for quick in 0 1; do
  python3 - "$b/yarnvox" $quick <<'PY' | tee -a $OUT/exit-ab.txt
import json, os, subprocess, sys, time
cmd = [sys.argv[1], "voxelize", ".data/sweater_flame_ribbing.bcc", "-o", "/tmp/yvb/o.vdb", "--yarn-radius", "0.1",
       "--resolution", "2048", "--quiet", "--stats", "/tmp/yvb/s.json"]
env = {**os.environ, "YV_TRACE": "/tmp/yvb/t.json"}
if sys.argv[2] == "1": env["YV_QUICK_EXIT"] = "1"
t0 = time.monotonic()
subprocess.run(cmd, env=env, check=True)
t1 = time.monotonic()
d = json.load(open("/tmp/yvb/t.json"))
origin = d["otherData"]["origin_monotonic_seconds"]
ev = [e for e in d["traceEvents"] if e.get("ph") == "X"]
run = next(e for e in ev if e["name"] == "run the command")
end = origin + (run["ts"] + run["dur"]) * 1e-6
s = json.load(open("/tmp/yvb/s.json"))
print(f"quick {sys.argv[2]} wall {t1 - t0:.3f} start {origin - t0:.3f} command {run['dur'] * 1e-6:.3f} exit {t1 - end:.3f} program {s['backend_stats']['gl_program_seconds']:.3f} context {s['backend_stats']['gl_context_seconds']:.3f}")
PY
  rm -f /tmp/yvb/o.vdb
 done
done
cp /tmp/yvb/t.json $OUT/s2048.trace.json
