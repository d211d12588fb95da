#!/usr/bin/env bash
# The live view's benchmark end to end: starts `yarnvox view INPUT` on a free
# port, drives it with yv_view_bench (an orbit, a close-up, a zoom out;
# bench/view_bench.cpp), prints a header line and one JSON line a phase, and
# stops the view. Usage:
#   bench/view_bench.sh INPUT [--size WxH] [--frames N] [--mode M] [-- VIEW OPTIONS...]
# e.g. bench/view_bench.sh garment.vdb --size 1280x720 --frames 240 -- --device 0
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="${YV_BUILD_DIR:-$root/build}"
source "$root/bench/header.sh"
input=$1
shift
bench_args=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do bench_args+=("$1"); shift; done
[ $# -gt 0 ] && shift
view_args=("$@")
log=$(mktemp)
trap 'rm -f "$log"' EXIT
"$build/yarnvox" view "$input" --port 0 "${view_args[@]}" >"$log" 2>&1 &
view=$!
port=""
for _ in $(seq 6000); do
  port=$(grep -o 'http://127.0.0.1:[0-9]*/' "$log" | head -1 | sed 's/.*:\([0-9]*\)\//\1/') || true
  [ -n "$port" ] && break
  kill -0 "$view" 2>/dev/null || { cat "$log" >&2; exit 1; }
  sleep 0.1
done
[ -n "$port" ] || { echo "view_bench: no address from yarnvox view" >&2; kill -TERM "$view"; exit 1; }
bench_header view "yarnvox view $input ${view_args[*]}; yv_view_bench ${bench_args[*]}"
status=0
"$build/bench/yv_view_bench" --port "$port" --server-pid "$view" "${bench_args[@]}" || status=$?
kill -TERM "$view"
wait "$view" || status=$?
exit $status
