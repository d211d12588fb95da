#!/usr/bin/env bash
# What a change to the shaders costs a first run and a warm one, tried
# without rebuilding: for each folder of shader files given (YV_SHADER_DIR,
# `stock` for the built-in ones), one voxelize with NVIDIA's disk cache
# pointed at an empty folder (traced: each program's link, where the driver
# compiles, in ms), three warm runs at 1024 and two at 4096 (their --stats
# stages and GPU times), and a 1024 run's .vdb compared with the stock one's
# apart from its header's UUID (offsets 21 to 56).
#
#   bench/shader_variants.sh YARNVOX GARMENT.bcc stock|DIR...
#   env: YV_SCRATCH (default a temporary folder)
set -euo pipefail
bin=$1 garment=$2
shift 2
scratch=${YV_SCRATCH:-$(mktemp -d)}
mkdir -p "$scratch"
stats() { python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(json.dumps({'seconds': s['seconds'], 'gpu': {k: v for k, v in s['backend_stats'].items() if k.startswith('gpu_') or k == 'gl_program_seconds'}}))" "$1"; }
for variant in "$@"; do
  if [ "$variant" = stock ]; then unset YV_SHADER_DIR; else export YV_SHADER_DIR=$(cd "$variant" && pwd); fi
  cache="$scratch/glcache-$(basename "$variant")"
  rm -rf "$cache"; mkdir -p "$cache"
  export __GL_SHADER_DISK_CACHE_PATH="$cache" __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1
  start=$(date +%s%N)
  YV_TRACE="$scratch/first.trace.json" "$bin" voxelize "$garment" -o "$scratch/o.vdb" --resolution 1024 --quiet
  end=$(date +%s%N)
  echo "$variant first run: $(( (end - start) / 1000000 )) ms; link ms: $(python3 -c "
import json, sys
ev = [e for e in json.load(open(sys.argv[1]))['traceEvents'] if e.get('ph') == 'X' and e['name'].startswith('link ')]
print(' '.join('%s=%.0f' % (e['name'][5:], e['dur'] / 1e3) for e in ev if e['dur'] > 2000))" "$scratch/first.trace.json")"
  for size in 1024 1024 1024 4096 4096; do
    start=$(date +%s%N)
    "$bin" voxelize "$garment" -o "$scratch/o.vdb" --resolution $size --quiet --stats "$scratch/s.json"
    end=$(date +%s%N)
    echo "$variant warm $size: $(( (end - start) / 1000000 )) ms $(stats "$scratch/s.json")"
  done
  "$bin" voxelize "$garment" -o "$scratch/$(basename "$variant").vdb" --resolution 1024 --quiet
  if [ "$variant" != stock ] && [ -f "$scratch/stock.vdb" ]; then
    if cmp -s <(head -c 21 "$scratch/stock.vdb"; tail -c +58 "$scratch/stock.vdb") \
              <(head -c 21 "$scratch/$(basename "$variant").vdb"; tail -c +58 "$scratch/$(basename "$variant").vdb"); then
      echo "$variant: the 1024 .vdb has the stock shaders' bytes"
    else
      echo "$variant: the 1024 .vdb DIFFERS from the stock shaders'"
    fi
  fi
done
