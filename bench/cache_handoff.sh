#!/usr/bin/env bash
# Can other processes fill NVIDIA's disk shader cache for a yarnvox run that
# starts after they end? A first run on a machine waits about half a second
# on the driver compiling one program at a time; processes compile side by
# side, but a binary handed from one to another is finalised again at its
# first dispatch (bench/results/README.md, 2026-12-06). For each round and
# way, an empty cache folder, then the warmers (yv_bench_compile_threads
# --cold-warm-child: each a share of a default run's programs, linked, with
# --dispatch also run once), then two yarnvox voxelize runs at 1024, traced:
# their wall time, their links (ms; a link served by the cache takes about
# 1) and their first raster pass (about 0.29 s where a program is finalised
# there, 0.01 to 0.02 s where it is not). The ways: none (a plain first
# run), the whole list in one process with and without --dispatch, and
# K = 2, 3, 4 processes side by side with and without it.
#
#   bench/cache_handoff.sh YARNVOX BENCH_COMPILE_THREADS GARMENT.bcc
#   env: YV_SCRATCH (default a temporary folder), YV_ROUNDS (default 2)
set -uo pipefail
bin=$1 bench=$2 garment=$3
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=${YV_SCRATCH:-$(mktemp -d)}
mkdir -p "$scratch"
. "$root/bench/header.sh"
bench_header cache_handoff "$0 $*" ""
export __GL_SHADER_DISK_CACHE_SKIP_CLEANUP=1
ms() { echo $(( ($(date +%s%N) - $1) / 1000000 )); }
run() { # ROUND WAY WARMERS_MS WHICH
    local start; start=$(date +%s%N)
    YV_TRACE="$scratch/run.trace.json" "$bin" voxelize "$garment" -o "$scratch/out.vdb" --resolution 1024 --quiet
    python3 - "$1" "$2" "$3" "$4" "$(ms "$start")" "$scratch/run.trace.json" <<'PY'
import json, sys
round_, way, warmers_ms, which, run_ms, trace = sys.argv[1:]
ev = [e for e in json.load(open(trace))['traceEvents'] if e.get('ph') == 'X']
links = [e for e in ev if e['name'].startswith('link ')]
first = lambda name: next((round(e['dur'] / 1e3, 1) for e in ev if e['name'] == name), None)
print(json.dumps({'round': int(round_), 'way': way, 'warmers_ms': int(warmers_ms), 'run': which, 'run_ms': int(run_ms),
                  'links_ms': round(sum(e['dur'] for e in links) / 1e3, 1),
                  'slow_links_ms': {e['name'][5:]: round(e['dur'] / 1e3) for e in links if e['dur'] > 5000},
                  'first_raster_pass_ms': first('raster pass'), 'context_ms': first('make the GL context')}))
PY
}
for round in $(seq "${YV_ROUNDS:-2}"); do
    for way in none one one-dispatch 2 2-dispatch 3 3-dispatch 4 4-dispatch; do
        export __GL_SHADER_DISK_CACHE_PATH="$scratch/glcache-$round-$way"
        rm -rf "$__GL_SHADER_DISK_CACHE_PATH"
        mkdir -p "$__GL_SHADER_DISK_CACHE_PATH"
        processes=${way%-dispatch} dispatch=
        [ "$processes" = one ] && processes=1
        [ "$way" != "${way%-dispatch}" ] && dispatch=--dispatch
        start=$(date +%s%N)
        if [ "$processes" != none ]; then
            for w in $(seq 0 $((processes - 1))); do "$bench" --cold-warm-child "$w" $((processes - 1)) $dispatch & done
            wait
        fi
        warmers=$(ms "$start")
        run "$round" "$way" "$warmers" first
        run "$round" "$way" "$warmers" next
    done
done
