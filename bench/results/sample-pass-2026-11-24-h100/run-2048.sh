#!/usr/bin/env bash
# The 2048 runs, three times each, alternating: build-dev/yarnvox-a (before
# this session), build-dev/yarnvox, and build-dev/yarnvox-exit with
# YV_QUICK_EXIT=1 (the same binary but for a std::_Exit after the command:
# what the process's exit costs; a probe, not part of yarnvox).
set -u
mkdir -p /tmp/yvb
b=build-dev
$b/yarnvox gen --pattern twill --shape cylinder --crossings 410000 -o /tmp/yvb/d.bcc --quiet
$b/yarnvox gen --pattern plain --shape flat --crossings 410000 -o /tmp/yvb/f.bcc --quiet
$b/yarnvox voxelize .data/sweater_flame_ribbing.bcc -o /tmp/yvb/o.vdb --yarn-radius 0.1 --resolution 1024 --quiet
rm -f /tmp/yvb/o.vdb
for g in ".data/sweater_flame_ribbing.bcc 0.1 2048 s2048" "/tmp/yvb/d.bcc 0.3 2048 d2048" "/tmp/yvb/f.bcc 0.3 2048 f2048"; do
  set -- $g
  for run in 1 2 3; do
    for v in "yarnvox-a" "yarnvox" "yarnvox-exit YV_QUICK_EXIT=1"; do
      set -- $g; bin=${v%% *}; envs=""; [ "$bin" != "$v" ] && envs=${v#* }
      t0=$(date +%s.%N)
      env $envs $b/$bin voxelize $1 -o /tmp/yvb/o.vdb --yarn-radius $2 --resolution $3 --quiet --stats /tmp/yvb/s.json
      t1=$(date +%s.%N)
      python3 -c "
import json; d=json.load(open('/tmp/yvb/s.json')); s=d['seconds']; b=d['backend_stats']
print('$4 $bin wall', round($t1-$t0,3), 'stages', round(sum(s.values()),3), ' '.join(f'{k}={v:.3f}' for k,v in s.items()),
      'growths', b['fragment_list_growths'], 'overflows', b['overflow_retries'], 'passes', b['raster_passes'])" | tee -a $OUT/runs-2048.txt
      rm -f /tmp/yvb/o.vdb
    done
  done
done
