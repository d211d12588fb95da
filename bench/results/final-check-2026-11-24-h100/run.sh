#!/usr/bin/env bash
set -u
mkdir -p /tmp/yvb
b=build-dev
S=""; command -v strace >/dev/null && S="strace -f -e trace=fcntl -o /tmp/yvb/st.txt"; touch /tmp/yvb/st.txt
dd if=/dev/zero of=/tmp/yvb/dd.bin bs=64M count=64 conv=fsync 2>&1 | tail -1; rm -f /tmp/yvb/dd.bin
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" ".data/sweater_flame_ribbing.bcc 0.1 4096 s4096" "/tmp/yvb/d.bcc 0.3 8192 d8192"; do
  set -- $g
  t0=$(date +%s.%N)
  YV_TRACE=$OUT/$4.trace.json $S $b/yarnvox voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats $OUT/$4.stats.json 2>&1 | tail -2
  t1=$(date +%s.%N)
  echo "== $4 wall $(python3 -c "print(round($t1-$t0,3))") file $(stat -c %s /tmp/yvb/o.vdb); fcntl: $(grep -c O_DIRECT /tmp/yvb/st.txt)"
  python3 bench/trace_summary.py $OUT/$4.trace.json | grep -E "write the file|fsync|voxelize|  write "
  rm -f /tmp/yvb/o.vdb
done
