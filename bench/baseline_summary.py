#!/usr/bin/env python3
"""Ratio table from bench/baseline_compare.sh output (JSON lines).

    bench/baseline_summary.py sweater.jsonl draped.jsonl ... [--disk-gbps 1.0] [--append append.jsonl]

One row per garment and resolution: yarnvox's wall time, each baseline's
time, and the ratios baseline / yarnvox (above 1: yarnvox is faster). The
baselines' times are their processes' wall times where the file has them
(measured as yarnvox's is), else their own "total", which leaves out the
process's start and exit; with both, the ratio against "total" follows in
brackets. With --disk-gbps, yarnvox's time over the time its output takes
to write at that speed (the disk floor). With --append (bench/yv_bench_append's
output from the same machine), the GPU's raster and sampling of yarnvox's
run (fragments over gpu_raster_seconds + gpu_sample_seconds) against the
bare append of 8-pixel squares: how many times slower.
"""
import argparse
import json


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--disk-gbps", type=float, default=0.0, help="measured disk write speed, GB/s")
    parser.add_argument("--append", help="bench/yv_bench_append output (JSON lines)")
    args = parser.parse_args()
    append_rate = None
    if args.append:
        for line in open(args.append):
            if line.strip().startswith("{"):
                d = json.loads(line)
                if d.get("bench") == "append" and d.get("side_pixels") == 8:
                    append_rate = d["fragments_per_second"]
    rows = []
    for path in args.files:
        current = None
        for line in open(path):
            line = line.strip()
            if not line.startswith("{"):
                continue
            d = json.loads(line)
            if d.get("tool") == "yarnvox":
                stats = d.get("backend_stats", {})
                gpu = stats.get("gpu_raster_seconds", 0.0) + stats.get("gpu_sample_seconds", 0.0)
                current = {"garment": d["garment"], "res": d["resolution"], "yarnvox": d["wall_seconds"],
                           "bytes": d["file_bytes"], "peak": d["peak_host_bytes"],
                           "raster_rate": d["fragments"] / gpu if gpu > 0 else None}
                rows.append(current)
            elif "baseline" in d and current is not None and d["resolution"] == current["res"]:
                key = "orientation" if d["orientation"] else "density"
                current[key] = (d.get("wall_seconds"), d["seconds"]["total"])
    print("| garment | res | yarnvox | OpenVDB density | ratio | OpenVDB + orientation | ratio | peak host |"
          + (" vs disk floor |" if args.disk_gbps else "")
          + (f" raster + sampling | below the bare append ({append_rate / 1e9:.2f} G/s) |" if append_rate else ""))
    print("|---|---|---|---|---|---|---|---|" + ("---|" if args.disk_gbps else "") + ("---|---|" if append_rate else ""))
    for r in rows:
        cells = [r["garment"], str(r["res"]), f'{r["yarnvox"]:.2f} s']
        for key in ("density", "orientation"):
            if key not in r:
                cells += ["", ""]
                continue
            wall, total = r[key]
            shown = wall if wall is not None else total
            ratio = f"{shown / r['yarnvox']:.2f}"
            if wall is not None:
                ratio += f" ({total / r['yarnvox']:.2f})"
            cells += [f"{shown:.1f} s", ratio]
        cells.append(f'{r["peak"] / 1e9:.2f} GB')
        if args.disk_gbps:
            cells.append(f'{r["yarnvox"] / (r["bytes"] / 1e9 / args.disk_gbps):.1f}x')
        if append_rate:
            rate = r["raster_rate"]
            cells += [f"{rate / 1e9:.2f} G/s", f"{append_rate / rate:.1f}"] if rate else ["", ""]
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
