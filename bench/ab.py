#!/usr/bin/env python3
"""A/B: one yarnvox command line run with two builds, alternately, on one machine.

Each side is a ready binary (--a-bin, --b-bin) or a commit (--a, --b), or the
A commit with a patch applied (--b-patch). Commits are built in a git worktree
of their own under --work (Release, -DYARNVOX_MPI=ON, as tools/test builds;
a build is kept and reused while its binary is there).

The command line after `--` is yarnvox's arguments; `{out}` in it becomes the
side's own output folder, so that the two sides write apart:

    bench/ab.py --a HEAD~1 --b HEAD --rounds 5 -- \\
        voxelize g.bcc -o {out}/g.vdb --resolution 128 --backend cpu --stats {out}/s.json

After one untimed warm-up run each, round r runs A then B (B then A on even
rounds). After every round the two output folders must hold the same files
with the same bytes: a .vdb apart from its header's UUID (bytes 21 to 56,
formats/vdb-subset.md), a .json (--stats) apart from keys that are times,
rates, memory or the output path. Prints one line of text and writes the JSON
report (--json); exits 1 when the outputs differ, 2 on a failed run or build.

Two settings of one build: the same binary on both sides, with --a-env and
--b-env, or with --a-arg and --b-arg (arguments appended to one side's
command line); --differ-key names a --stats key the setting changes (say
slice_primitive), which the comparison then leaves out:

    bench/ab.py --a-bin build/yarnvox --b-bin build/yarnvox --b-arg=--sample-items \\
        --b-arg=raster --differ-key slice_primitive --differ-key primitives_drawn -- voxelize ...
"""
import argparse
import hashlib
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VDB_MAGIC = (0x56444220).to_bytes(8, "little")
UUID_BYTES = slice(21, 57)  # i64 magic, u32 version, 2 x u32 library version, u8 offsets flag, then 36 bytes
# --stats keys that change from run to run: times, rates, memory, queues, threads used, the output path,
# and how much of the file was streamed before the run's end (the writer's pace against the GPU's).
VOLATILE_KEY = re.compile(r"seconds|per_second|peak|queued|wait|^threads$|^output$|streamed_before_end")


def fail(msg, code=2):
    print("ab: " + msg, file=sys.stderr)
    sys.exit(code)


def git(*args, cwd=ROOT, capture=True):
    r = subprocess.run(["git", *args], cwd=cwd, text=True, capture_output=capture)
    if r.returncode != 0:
        fail("git " + " ".join(args) + " failed: " + (r.stderr or "").strip())
    return (r.stdout or "").strip()


def build(rev, patch, work, jobs):
    """The yarnvox binary of commit rev (with patch applied), built in its own worktree."""
    sha = git("rev-parse", "--verify", rev + "^{commit}")
    name = sha[:12]
    if patch:
        with open(patch, "rb") as f:
            name += "-" + hashlib.sha256(f.read()).hexdigest()[:12]
    src = os.path.join(work, name)
    binary = os.path.join(src, "build", "yarnvox")
    if os.path.exists(binary):
        return binary, name
    if os.path.exists(src):
        subprocess.run(["git", "worktree", "remove", "--force", src], cwd=ROOT, capture_output=True)
        shutil.rmtree(src, ignore_errors=True)
    git("worktree", "add", "--detach", src, sha)
    if patch:
        git("apply", os.path.abspath(patch), cwd=src)
    cfg = ["cmake", "-S", src, "-B", os.path.join(src, "build"), "-G", "Ninja",
           "-DCMAKE_BUILD_TYPE=Release", "-DYARNVOX_MPI=ON"]
    if shutil.which("ccache"):
        cfg.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    print(f"ab: building {name} in {src}", file=sys.stderr)
    for cmd in (cfg, ["cmake", "--build", os.path.join(src, "build"), "--target", "yarnvox", "--parallel", str(jobs)]):
        if subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode != 0:
            fail("build of " + name + " failed: " + " ".join(cmd))
    return binary, name


DIFFER_KEYS = set()  # --differ-key: what the sides' settings change


def strip_volatile(v):
    """The stats without their volatile keys; a whole number written as a
    double ("0.0" where another build writes "0") read as the integer."""
    if isinstance(v, dict):
        return {k: strip_volatile(x) for k, x in v.items() if not VOLATILE_KEY.search(k) and k not in DIFFER_KEYS}
    if isinstance(v, list):
        return [strip_volatile(x) for x in v]
    if isinstance(v, float) and v.is_integer():
        return int(v)
    return v


def comparable(path):
    with open(path, "rb") as f:
        data = bytearray(f.read())
    if data[:8] == VDB_MAGIC and len(data) >= UUID_BYTES.stop:
        data[UUID_BYTES] = bytes(UUID_BYTES.stop - UUID_BYTES.start)
        return bytes(data)
    if path.endswith(".json"):
        try:
            return json.dumps(strip_volatile(json.loads(data)), sort_keys=True).encode()
        except ValueError:
            pass
    return bytes(data)


def differences(dir_a, dir_b):
    def files(d):
        return sorted(os.path.relpath(os.path.join(p, f), d) for p, _, fs in os.walk(d) for f in fs)
    fa, fb = files(dir_a), files(dir_b)
    diffs = [f"{f}: only in A" for f in fa if f not in fb] + [f"{f}: only in B" for f in fb if f not in fa]
    for f in fa:
        if f in fb:
            a, b = comparable(os.path.join(dir_a, f)), comparable(os.path.join(dir_b, f))
            if a != b and f.endswith(".json") and a[:1] == b"{" and b[:1] == b"{":
                def leaves(v, p=""):
                    return {q: x for k, w in v.items() for q, x in leaves(w, p + k + ".").items()} \
                        if isinstance(v, dict) else {p[:-1]: v}
                la, lb = leaves(json.loads(a)), leaves(json.loads(b))
                keys = sorted(k for k in set(la) | set(lb) if la.get(k) != lb.get(k))
                diffs.append(f"{f}: differs in " + ", ".join(f"{k} ({la.get(k)} against {lb.get(k)})" for k in keys))
            elif a != b:
                at = next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))
                diffs.append(f"{f}: differs ({len(a)} and {len(b)} bytes compared, first at {at})")
    return diffs


def run_once(side, args, out):
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    cmd = [side["bin"]] + [a.replace("{out}", out) for a in args + side["args"]]
    env = {**os.environ, **side["env"]}
    t0 = time.monotonic()
    r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wall = time.monotonic() - t0
    if r.returncode != 0:
        fail(f"side {side['name']} failed (exit {r.returncode}): {' '.join(cmd)}\n{r.stderr.decode(errors='replace')[-2000:]}")
    return wall


def summary(walls):
    med = statistics.median(walls)
    return {"wall_seconds": [round(w, 4) for w in walls], "median": round(med, 4), "min": round(min(walls), 4),
            "max": round(max(walls), 4), "spread": round((max(walls) - min(walls)) / med, 4) if med else None}


def env_pairs(items):
    env = {}
    for item in items:
        if "=" not in item:
            fail(f"--a-env/--b-env take NAME=VALUE, not {item!r}")
        k, v = item.split("=", 1)
        env[k] = v
    return env


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--a", help="commit of side A (built here)")
    p.add_argument("--b", help="commit of side B (built here)")
    p.add_argument("--b-patch", help="side B: side A's commit with this patch applied (git apply)")
    p.add_argument("--a-bin", help="side A: a ready yarnvox binary")
    p.add_argument("--b-bin", help="side B: a ready yarnvox binary")
    p.add_argument("--a-env", action="append", default=[], metavar="NAME=VALUE",
                   help="environment for side A's runs (e.g. YV_SHADER_DIR=DIR); repeatable")
    p.add_argument("--b-env", action="append", default=[], metavar="NAME=VALUE", help="the same for side B")
    p.add_argument("--a-arg", action="append", default=[], metavar="ARG",
                   help="an argument appended to side A's command line (repeat for more; --a-arg=--option)")
    p.add_argument("--b-arg", action="append", default=[], metavar="ARG", help="the same for side B")
    p.add_argument("--differ-key", action="append", default=[], metavar="KEY",
                   help="a --stats key the two sides' settings change, left out of the comparison")
    p.add_argument("--rounds", type=int, default=5, help="timed rounds (default 5)")
    p.add_argument("--warmup", type=int, default=1, help="untimed runs of each side first (default 1)")
    p.add_argument("--work", default=os.path.join(ROOT, "build-ab"),
                   help="worktrees, builds and outputs (default build-ab/ in the repository, ignored by git)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="build parallelism")
    p.add_argument("--json", help="write the report here (default: WORK/report.json)")
    p.add_argument("args", nargs=argparse.REMAINDER, help="-- then yarnvox's arguments; {out} is the side's folder")
    o = p.parse_args()
    args = o.args[1:] if o.args[:1] == ["--"] else o.args
    if not args:
        fail("no yarnvox command line (after --)")
    if o.rounds < 1:
        fail("--rounds must be at least 1")
    if bool(o.a) == bool(o.a_bin):
        fail("side A: give one of --a and --a-bin")
    if sum(map(bool, (o.b, o.b_bin, o.b_patch))) != 1:
        fail("side B: give one of --b, --b-patch and --b-bin")
    if o.b_patch and not o.a:
        fail("--b-patch applies to side A's commit: give --a")
    work = os.path.abspath(o.work)
    os.makedirs(work, exist_ok=True)
    DIFFER_KEYS.update(o.differ_key)

    sides = []
    for name, rev, patch, binary, env, extra in (("A", o.a, None, o.a_bin, o.a_env, o.a_arg),
                                                ("B", o.b or (o.a if o.b_patch else None), o.b_patch, o.b_bin, o.b_env,
                                                 o.b_arg)):
        if binary:
            if not os.access(binary, os.X_OK):
                fail(f"side {name}: {binary} is not an executable")
            label = os.path.abspath(binary)
            binary = os.path.abspath(binary)
        else:
            binary, label = build(rev, patch, work, o.jobs)
        sides.append({"name": name, "bin": binary, "label": label, "env": env_pairs(env), "args": extra,
                      "commit": git("rev-parse", "--short=12", rev) if rev else None, "patch": patch, "walls": []})

    outs = [os.path.join(work, "out-a"), os.path.join(work, "out-b")]
    for _ in range(o.warmup):
        for s, out in zip(sides, outs):
            run_once(s, args, out)
    diffs = []
    for r in range(o.rounds):
        order = (0, 1) if r % 2 == 0 else (1, 0)
        for i in order:
            sides[i]["walls"].append(run_once(sides[i], args, outs[i]))
        for d in differences(*outs):
            diffs.append(f"round {r + 1}: {d}")

    a, b = (summary(s["walls"]) for s in sides)
    report = {
        "command": ["yarnvox"] + args, "rounds": o.rounds, "warmup": o.warmup,
        "machine": {"host": platform.node(), "cpus": os.cpu_count()},
        "a": {**{k: sides[0][k] for k in ("label", "commit", "patch", "env", "args")}, **a},
        "b": {**{k: sides[1][k] for k in ("label", "commit", "patch", "env", "args")}, **b},
        "differ_keys": sorted(DIFFER_KEYS),
        "ratio_b_over_a": round(b["median"] / a["median"], 4) if a["median"] else None,
        "identical": not diffs, "differences": diffs[:20],
    }
    path = o.json or os.path.join(work, "report.json")
    with open(path, "w") as f:
        json.dump(report, f, indent=1)
        f.write("\n")

    def side_text(name, s, r):
        env = "".join(f" {k}={v}" for k, v in s["env"].items()) + "".join(" " + a for a in s["args"])
        return f"{name} {s['label']}{env}: median {r['median']:.3f} s ({r['min']:.3f}-{r['max']:.3f}, spread {100 * r['spread']:.1f} %)"
    print(f"{side_text('A', sides[0], a)}; {side_text('B', sides[1], b)}; B/A {report['ratio_b_over_a']}; "
          f"{o.rounds} rounds; outputs " + ("identical" if not diffs else f"DIFFER ({diffs[0]})"))
    print(f"ab: report in {path}", file=sys.stderr)
    sys.exit(1 if diffs else 0)


if __name__ == "__main__":
    main()
