#!/usr/bin/python3
"""Stress benchmark: the whole yarnvox pipeline at garment scale, against the
paper's dense method and the CPU backend, in one run on one machine.

For each garment size and resolution it runs `yarnvox gen` and
`yarnvox voxelize --stats` for each method (gl: sparse, out of core; dense: the
paper's 3D textures; cpu: the TBB reference) and records per stage seconds,
slices/s, fragments/s, active voxels/s, peak host and GPU memory, bytes on
disk, regions and splits. Runs that cannot happen here are skipped with the
reason, never faked.

Output in --out (default bench/results/stress-<date>-<host>): results.json,
results.csv, summary.md and SVG plots.

    bench/stress.py --quick            # minutes on a 2-core machine, no GPU
    bench/stress.py                    # 0.1M to 41M slices, 1024 to 8192
"""
import argparse
import csv
import datetime
import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# (name, crossings, slices per segment): the name is the slice count at the
# paper's spacing (--paper-spacing: slices ~ 2 * crossings * K); by default
# yarnvox places slices one voxel apart, so the count follows the resolution.
FULL_SIZES = [("0.1M", 2000, 25), ("1M", 20000, 25), ("5M", 100000, 25),
              ("17.6M", 352000, 25), ("41M", 410000, 50)]
QUICK_SIZES = [("0.1M", 2000, 25), ("0.5M", 10000, 25)]
FULL_RES = [1024, 2048, 4096, 8192]
QUICK_RES = [256, 512]


def run(cmd, timeout):
    start = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout + p.stderr, time.monotonic() - start


def child_peak_rss_bytes():
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="small sizes that run in minutes on 2 cores")
    ap.add_argument("--yarnvox", default=os.path.join(ROOT, "build", "yarnvox"))
    ap.add_argument("--methods", default="gl,dense,cpu")
    ap.add_argument("--sizes", default=None, help="comma-separated subset of the size names, e.g. 0.1M,41M")
    ap.add_argument("--resolutions", default=None, help="comma-separated resolutions instead of the set's")
    ap.add_argument("--paper-spacing", action="store_true",
                    help="the paper's 25 or 50 slices per segment instead of yarnvox's default (one voxel apart)")
    ap.add_argument("--voxelize-args", default="",
                    help="more options for every `yarnvox voxelize` run, e.g. '--cross-section disk' (the dense method's "
                         "point samples miss the fibre cross-section's fibres where a yarn is thinner than a voxel)")
    ap.add_argument("--out", default=None)
    ap.add_argument("--timeout", type=float, default=900, help="seconds per run")
    ap.add_argument("--work", default="/tmp/yv-stress", help="scratch folder for garments and outputs")
    ap.add_argument("--combine", nargs="+", metavar="RESULTS_JSON",
                    help="merge the results.json of several partial runs (one machine) into --out, with summary and plots")
    args = ap.parse_args()
    if args.combine:
        combine(args.combine, args.out)
        return

    if not os.access(args.yarnvox, os.X_OK):
        sys.exit(f"stress: {args.yarnvox} not found: build first (tools/test or tools/demo)")
    sizes = QUICK_SIZES if args.quick else FULL_SIZES
    resolutions = QUICK_RES if args.quick else FULL_RES
    if args.sizes:
        sizes = [s for s in sizes if s[0] in args.sizes.split(",")]
    if args.resolutions:
        resolutions = [int(r) for r in args.resolutions.split(",")]
    methods = args.methods.split(",")
    host = platform.node()
    date = datetime.date.today().isoformat()
    out = args.out or os.path.join(ROOT, "bench", "results", f"stress-{date}-{'quick' if args.quick else 'full'}-{host}")
    os.makedirs(out, exist_ok=True)
    os.makedirs(args.work, exist_ok=True)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()

    rows = []
    for name, crossings, k in sizes:
        bcc = os.path.join(args.work, f"plain-{crossings}.bcc")
        if not os.path.exists(bcc):
            rc, log, _ = run([args.yarnvox, "gen", "--pattern", "plain", "--crossings", str(crossings), "-o", bcc], args.timeout)
            if rc:
                sys.exit(f"stress: gen failed: {log}")
        for res in resolutions:
            for method in methods:
                row = {"size": name, "crossings": crossings, "slices_per_segment": k if args.paper_spacing else None,
                       "resolution": res, "method": method}
                if method == "cpu" and (res > 2048 or crossings > 100000) and not args.quick:
                    row["skipped"] = "the CPU reference takes minutes beyond 2048 and 5M slices; only run up to those"
                    rows.append(row)
                    continue
                vdb = os.path.join(args.work, "out.vdb")
                stats = os.path.join(args.work, "stats.json")
                for f in (vdb, stats):
                    if os.path.exists(f):
                        os.remove(f)
                cmd = [args.yarnvox, "voxelize", bcc, "-o", vdb, "--resolution", str(res), "--stats", stats, "--quiet"]
                if args.paper_spacing:
                    cmd += ["--slices-per-segment", str(k)]
                cmd += args.voxelize_args.split()
                cmd += {"gl": ["--backend", "gl"], "dense": ["--backend", "gl", "--method", "dense"], "cpu": ["--backend", "cpu"]}[method]
                try:
                    rc, log, wall = run(cmd, args.timeout)
                except subprocess.TimeoutExpired:
                    row["skipped"] = f"did not finish within {args.timeout:.0f} s"
                    rows.append(row)
                    continue
                if rc:
                    # The dense method stops where one 3D texture ends: that is a result, not a failure.
                    row["skipped"] = log.strip().splitlines()[-1] if log.strip() else f"exit {rc}"
                    rows.append(row)
                    continue
                s = json.load(open(stats))
                b = s.get("backend_stats", {})
                secs = s["seconds"]
                row.update({
                    "slices": s["slices"], "grid": s["grid_dims"], "wall_seconds": wall,
                    "seconds": secs, "voxelize_seconds": secs.get("voxelize", 0.0),
                    "slices_per_second": s["slices_per_second"], "active_voxels": s["active_voxels"],
                    "active_voxels_per_second": s["active_voxels_per_second"],
                    "fragments": b.get("fragments", s.get("samples", 0)),
                    "raster_fragments_per_second": b["fragments"] / b["gpu_raster_seconds"] if b.get("gpu_raster_seconds") and b.get("fragments") else None,
                    "brick_fragments_per_second": b["fragments"] / b["gpu_brick_seconds"] if b.get("gpu_brick_seconds") and b.get("fragments") else None,
                    "peak_host_bytes": s["peak_host_bytes"], "peak_gpu_bytes": b.get("gpu_peak_bytes"),
                    "bytes_on_disk": os.path.getsize(vdb) + b.get("store_bytes_on_disk", 0),
                    "regions": b.get("zoom_regions"), "splits": b.get("overflow_retries"), "list_growths": b.get("fragment_list_growths"),
                    "renderer": b.get("renderer", "cpu"),
                })
                rows.append(row)
                print(f"{name:>6} {res:>5} {method:>5}: {wall:7.2f} s  {row['active_voxels']:>11} voxels", flush=True)

    meta = {"date": date, "host": host, "commit": commit, "command": " ".join([os.path.relpath(sys.argv[0], ROOT)] + sys.argv[1:]),
            "renderer": next((r["renderer"] for r in rows if r.get("renderer") not in (None, "cpu")), "none")}
    json.dump({"meta": meta, "runs": rows}, open(os.path.join(out, "results.json"), "w"), indent=1)
    fields = ["size", "crossings", "resolution", "method", "slices", "grid", "wall_seconds", "voxelize_seconds",
              "slices_per_second", "active_voxels", "active_voxels_per_second", "fragments", "raster_fragments_per_second",
              "brick_fragments_per_second", "peak_host_bytes", "peak_gpu_bytes", "bytes_on_disk", "regions", "splits", "list_growths", "skipped"]
    with open(os.path.join(out, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    write_summary(out, meta, rows, methods)
    write_plots(out, rows, methods)
    print(f"wrote {out}")


def combine(paths, out):
    """Partial runs (e.g. one per device call) become one result set."""
    if not out:
        sys.exit("stress: --combine needs --out")
    os.makedirs(out, exist_ok=True)
    parts = [json.load(open(p)) for p in paths]
    rows = [r for part in parts for r in part["runs"]]
    meta = dict(parts[0]["meta"])
    meta["command"] = " + ".join(part["meta"]["command"] for part in parts)
    methods = list(dict.fromkeys(r["method"] for r in rows))
    json.dump({"meta": meta, "runs": rows, "parts": [part["meta"] for part in parts]},
              open(os.path.join(out, "results.json"), "w"), indent=1)
    write_summary(out, meta, rows, methods)
    write_plots(out, rows, methods)
    print(f"wrote {out}")


def fmt(v, unit=""):
    if v is None:
        return "-"
    for scale, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(v) >= scale:
            return f"{v / scale:.3g}{suffix}{unit}"
    return f"{v:.3g}{unit}"


def write_summary(out, meta, rows, methods):
    lines = [f"# yarnvox stress benchmark", "",
             f"{meta['date']}, host {meta['host']}, renderer {meta['renderer']}, commit {meta['commit']}", "",
             f"Command: `{meta['command']}`", "",
             "| size | res | method | wall | voxelize | slices/s | active voxels | peak host | peak GPU | on disk | regions | note |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "skipped" in r:
            lines.append(f"| {r['size']} | {r['resolution']} | {r['method']} | - | - | - | - | - | - | - | - | skipped: {r['skipped']} |")
        else:
            lines.append(f"| {r['size']} | {r['resolution']} | {r['method']} | {r['wall_seconds']:.2f} s | {r['voxelize_seconds']:.2f} s | "
                         f"{fmt(r['slices_per_second'])} | {fmt(r['active_voxels'])} | {fmt(r['peak_host_bytes'], 'B')} | "
                         f"{fmt(r['peak_gpu_bytes'], 'B')} | {fmt(r['bytes_on_disk'], 'B')} | {r['regions'] or '-'} | |")
    lines += ["", "## Ratios (same garment, same resolution, this run)", "",
              "Each ratio is baseline / yarnvox (gl): above 1, yarnvox is faster or uses less.", "",
              "| size | res | time: dense / gl | GPU memory: dense / gl | time: cpu / gl |", "|---|---|---|---|---|"]
    index = {(r["size"], r["resolution"], r["method"]): r for r in rows if "skipped" not in r}
    for (size, res, method), r in index.items():
        if method != "gl":
            continue
        d, c = index.get((size, res, "dense")), index.get((size, res, "cpu"))
        t_d = f"{d['wall_seconds'] / r['wall_seconds']:.2f}" if d else "dense cannot run"
        m_d = f"{d['peak_gpu_bytes'] / r['peak_gpu_bytes']:.2f}" if d and d.get("peak_gpu_bytes") and r.get("peak_gpu_bytes") else "-"
        t_c = f"{c['wall_seconds'] / r['wall_seconds']:.2f}" if c else "-"
        lines.append(f"| {size} | {res} | {t_d} | {m_d} | {t_c} |")
    lines += ["", "Plots: `time.svg`, `memory.svg`, `throughput.svg`, `ratio.svg`."]
    open(os.path.join(out, "summary.md"), "w").write("\n".join(lines) + "\n")


def chart(path, title, series, xlabel, ylabel):
    """A line chart on log axes through matplotlib (Debian's python3-matplotlib,
    tools/setup), written as SVG and PNG. series: {label: [(x, y)]}; one colour
    a series, the legend outside the axes."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib import ticker
    except ImportError:
        print("stress: no plots: python3-matplotlib is not installed (tools/setup installs it)", file=sys.stderr)
        return
    series = {k: sorted((x, y) for x, y in v if x and y and x > 0 and y > 0) for k, v in series.items()}
    series = {k: v for k, v in series.items() if v}
    fig, ax = plt.subplots(figsize=(8, 4.8), layout="constrained")
    colors = plt.get_cmap("tab10" if len(series) <= 10 else "tab20").colors
    markers = "osD^v<>ph*"
    for i, (label, pts) in enumerate(series.items()):
        ax.plot([x for x, _ in pts], [y for _, y in pts], color=colors[i % len(colors)],
                marker=markers[i % len(markers)], markersize=5, linewidth=1.8, label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    for axis in (ax.xaxis, ax.yaxis):
        # Real values at every tick, decades and the steps between them when
        # the data spans few decades, in the units of the summary (k, M, G).
        axis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0), numticks=15))
        axis.set_minor_locator(ticker.LogLocator(base=10, subs=tuple(range(1, 10)), numticks=15))
        axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: fmt(v)))
        axis.set_minor_formatter(ticker.NullFormatter())
    ax.grid(True, which="major", color="0.85")
    ax.grid(True, which="minor", color="0.94", linewidth=0.6)
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if series:
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0, frameon=False)
    else:
        ax.text(0.5, 0.5, "no runs", transform=ax.transAxes, ha="center", va="center")
    for ext in ("svg", "png"):
        fig.savefig(os.path.splitext(path)[0] + "." + ext, dpi=110)
    plt.close(fig)


def write_plots(out, rows, methods):
    ok = [r for r in rows if "skipped" not in r]
    res = sorted({r["resolution"] for r in ok})
    def series(metric, filt=lambda r: True):
        return {f"{m} @{q}": [(r["slices"], metric(r)) for r in ok if r["method"] == m and r["resolution"] == q and filt(r)]
                for m in methods for q in res}
    chart(os.path.join(out, "time.svg"), "End-to-end time", series(lambda r: r["wall_seconds"]), "slices", "seconds")
    chart(os.path.join(out, "memory.svg"), "Peak host memory", series(lambda r: r["peak_host_bytes"]), "slices", "bytes")
    chart(os.path.join(out, "throughput.svg"), "Throughput per stage (gl)",
          {**{f"raster frag/s @{q}": [(r["slices"], r["raster_fragments_per_second"]) for r in ok if r["method"] == "gl" and r["resolution"] == q] for q in res},
           **{f"brick frag/s @{q}": [(r["slices"], r["brick_fragments_per_second"]) for r in ok if r["method"] == "gl" and r["resolution"] == q] for q in res}},
          "slices", "fragments / s")
    index = {(r["size"], r["resolution"], r["method"]): r for r in ok}
    ratio = {}
    for (size, q, m), r in index.items():
        if m == "gl":
            for base in ("dense", "cpu"):
                b = index.get((size, q, base))
                if b:
                    ratio.setdefault(f"{base}/gl time @{q}", []).append((r["slices"], b["wall_seconds"] / r["wall_seconds"]))
    chart(os.path.join(out, "ratio.svg"), "Baseline time / yarnvox time", ratio, "slices", "ratio")


if __name__ == "__main__":
    main()
