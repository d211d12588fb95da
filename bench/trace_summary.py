#!/usr/bin/env python3
"""Sums a YV_TRACE timeline (Chrome trace events) per thread and span name.

    YV_TRACE=run.trace.json yarnvox voxelize ...
    bench/trace_summary.py run.trace.json [--json]

Thread 0 is the one that ran the command (its stages and the GL backend's
waits); the others are the writer's threads. For each span name: how many,
their total seconds, and the longest. Spans of one thread never overlap,
except a stage and the spans within it.
"""
import argparse
import collections
import json
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trace")
    parser.add_argument("--json", action="store_true", help="one JSON object instead of a table")
    args = parser.parse_args()
    try:
        with open(args.trace) as f:
            events = json.load(f)["traceEvents"]
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"trace_summary: {args.trace}: not a YV_TRACE file ({e})")

    totals = collections.defaultdict(lambda: [0, 0.0, 0.0])  # count, seconds, longest
    for e in events:
        row = totals[(e["tid"], e["name"])]
        seconds = e["dur"] * 1e-6
        row[0] += 1
        row[1] += seconds
        row[2] = max(row[2], seconds)
    if args.json:
        out = collections.defaultdict(dict)
        for (tid, name), (n, s, longest) in sorted(totals.items()):
            out[str(tid)][name] = {"count": n, "seconds": round(s, 6), "longest": round(longest, 6)}
        print(json.dumps(out))
        return
    writers = collections.defaultdict(lambda: [0, 0.0, 0.0, 0])
    for (tid, name), (n, s, longest) in sorted(totals.items()):
        if tid == 0:
            print(f"thread 0  {name:45s} {n:6d} {s:9.3f} s  longest {longest:.3f} s")
        else:
            w = writers[name]
            w[0] += n
            w[1] += s
            w[2] = max(w[2], longest)
            w[3] += 1
    for name, (n, s, longest, threads) in sorted(writers.items()):
        print(f"{threads:2d} others {name:45s} {n:6d} {s:9.3f} s  longest {longest:.3f} s")


if __name__ == "__main__":
    main()
