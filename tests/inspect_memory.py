#!/usr/bin/env python3
"""Peak host memory of `yarnvox inspect` does not grow with the volume: the
same garment of tubes (write_tube_volume) at 1024 and at 2048 (four times the
leaves), as a .vdb with and without a level-of-detail pyramid and as a work
directory, each inspect command's peak resident memory at 2048 within 1.5
times its peak at 1024 (the GPU budget fixed): on a .vdb the summary and the
whole-volume renders, on a work directory --verify, a region's render and the
HTML report. Memory is read with getrusage of the child alone: each
command runs from its own short-lived Python process.

    tests/inspect_memory.py --yarnvox BIN --writer BIN --scratch DIR

Renders need an OpenGL 4.5 context (llvmpipe will do); where none can be
made the test fails, unless YV_GL_TESTS=skip (then only the summary runs,
and it says so).
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

PEAK = r"""
import resource, subprocess, sys, json
r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
print(json.dumps({"exit": r.returncode, "stderr": r.stderr.decode(errors="replace"),
                  "peak_kib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss}))
"""


def peak(command):
    out = subprocess.run([sys.executable, "-c", PEAK] + command, check=True, capture_output=True, text=True)
    result = json.loads(out.stdout)
    if result["exit"] != 0:
        sys.exit(f"inspect_memory: {' '.join(command)} failed ({result['exit']}): {result['stderr'].strip()}")
    return result["peak_kib"] / 1024.0


def gl_available(yarnvox, volume, scratch):
    probe = subprocess.run([yarnvox, "inspect", volume, "--render", "mip", "--size", "8x8",
                            "-o", os.path.join(scratch, "probe.png")], capture_output=True, text=True)
    return probe.returncode == 0


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--yarnvox", required=True)
    p.add_argument("--writer", required=True)
    p.add_argument("--scratch", required=True)
    a = p.parse_args()
    shutil.rmtree(a.scratch, ignore_errors=True)
    os.makedirs(a.scratch)
    volumes = {}
    for lod in (0, 3):
        for res in (1024, 2048):
            path = os.path.join(a.scratch, f"tubes-{res}-lod{lod}.vdb")
            subprocess.run([a.writer, path, str(res), str(lod)], check=True)
            volumes[(res, lod)] = path
    for res in (1024, 2048):
        path = os.path.join(a.scratch, f"tubes-{res}.work")
        subprocess.run([a.writer, path, str(res), "work"], check=True)
        volumes[(res, "work")] = path
    commands = {"summary": []}
    work_commands = {"verify": ["--verify"]}
    if gl_available(a.yarnvox, volumes[(1024, 0)], a.scratch):
        png = os.path.join(a.scratch, "picture.png")
        budget = ["--gpu-budget", "48M", "--size", "320x240", "-o", png]
        commands["raycast"] = ["--render", "raycast"] + budget
        commands["orientation"] = ["--render", "orientation"] + budget
        work_commands["region raycast"] = ["--render", "raycast", "--region", "7"] + budget
        work_commands["html"] = ["--html", os.path.join(a.scratch, "report"), "--html-renders", "2",
                                 "--gpu-budget", "48M"]
    elif os.environ.get("YV_GL_TESTS") == "skip":
        print("inspect_memory: no OpenGL 4.5 context: renders not measured (YV_GL_TESTS=skip)")
    else:
        sys.exit("inspect_memory: no OpenGL 4.5 context could be made for the renders (YV_GL_TESTS=skip to skip them)")
    failed = []
    runs = [(f"{name}, lod {lod}", lod, args) for lod in (0, 3) for name, args in commands.items()]
    runs += [(f"{name}, work dir", "work", args) for name, args in work_commands.items()]
    for label, kind, args in runs:
        peaks = []
        for res in (1024, 2048):
            shutil.rmtree(os.path.join(a.scratch, "report"), ignore_errors=True)
            peaks.append(peak([a.yarnvox, "inspect", volumes[(res, kind)]] + args))
        small, large = peaks
        ratio = large / small
        print(f"inspect {label}: peak {small:.0f} MiB at 1024, {large:.0f} MiB at 2048: {ratio:.2f}x")
        if ratio > 1.5:
            failed.append(f"{label}: {ratio:.2f}x")
    sizes = {k: os.path.getsize(v) for k, v in volumes.items() if os.path.isfile(v)}
    print("file bytes:", {f"{r}/lod{l}": s for (r, l), s in sizes.items()})
    shutil.rmtree(a.scratch, ignore_errors=True)
    if failed:
        sys.exit("inspect_memory: peak memory grew with the volume: " + ", ".join(failed))


if __name__ == "__main__":
    main()
