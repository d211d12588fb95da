#!/usr/bin/env bash
# Two builds' yv_bench_plan_stages (plan_stages.cpp) on one garment, alternately:
# A then B, B then A, for --alternations rounds, each call its own --rounds.
# One JSON line a round on stdout, tagged with its side and alternation.
#
#   bench/plan_stages_ab.sh A_BENCH B_BENCH ALTERNATIONS -- --input G.bcc --yarn-radius R --resolution N [...]
#
# A build of another commit: git worktree add DIR COMMIT, copy bench/plan_stages.cpp and
# bench/CMakeLists.txt in when the commit has none, then ninja -C DIR/build yv_bench_plan_stages.
set -euo pipefail
[ $# -ge 4 ] && [ "$4" = "--" ] || { echo "usage: $0 A_BENCH B_BENCH ALTERNATIONS -- ARGS..." >&2; exit 2; }
a=$1 b=$2 alternations=$3
shift 4
for ((r = 1; r <= alternations; ++r)); do
    order="a b"
    (( r % 2 == 0 )) && order="b a"
    for side in $order; do
        bin=$a
        [ "$side" = b ] && bin=$b
        "$bin" "$@" | sed "s/^{/{\"side\": \"$side\", \"alternation\": $r, /"
    done
done
