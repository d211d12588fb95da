#!/usr/bin/env bash
# GL against the CPU reference on the H100, the five garments of 2026-11-23-h100-compare.jsonl.
set -u
for g in "plain flat 1" "twill cylinder 2" "knit cylinder 1" "satin sphere 0.5" "knit flat 3"; do
  set -- $g
  build-dev/bench/yv_bench_voxelize --backend compare --pattern $1 --shape $2 --twist $3 --crossings 2000 --resolution 512
done
