#!/usr/bin/env python3
"""Runs one command and prints one JSON line: its wall time, the peak
resident memory of the process and its children (getrusage, which counts
only this command: the script runs nothing else), its exit code and the
last line it printed to stderr.

    bench/peak_memory.py LABEL [--timeout SECONDS] -- COMMAND [ARGS...]
"""
import json
import resource
import subprocess
import sys
import time


def main():
    args = sys.argv[1:]
    label = args.pop(0)
    timeout = None
    if args and args[0] == "--timeout":
        timeout = float(args[1])
        args = args[2:]
    if not args or args[0] != "--":
        sys.exit(__doc__)
    command = args[1:]
    start = time.monotonic()
    try:
        done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout)
        code, err = done.returncode, done.stderr.decode(errors="replace").strip().splitlines()
    except subprocess.TimeoutExpired as e:
        code, err = "timeout", [f"stopped after {timeout:g} s"]
    wall = time.monotonic() - start
    peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    print(json.dumps({"label": label, "command": " ".join(command), "wall_s": round(wall, 3),
                      "peak_rss_gb": round(peak_kib / 2**20, 3), "exit": code,
                      "stderr_tail": err[-1][:300] if err else ""}), flush=True)


if __name__ == "__main__":
    main()
