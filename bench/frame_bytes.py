#!/usr/bin/env python3
"""The bytes a view frame takes as JPEG, from pictures of its halves.

A view frame is its halves side by side (the slices on the left, the ray
cast on the right) in one JPEG, 4:2:0 as the view encodes it. Given a left
and a right picture (PNG, e.g. from `yarnvox inspect --render slices` and
`--render raycast` at the view's size and camera), prints one JSON line per
quality: the frame's bytes and the Mbit/s that many frames a second take.

    bench/frame_bytes.py LEFT.png RIGHT.png [--qualities 85,70] [--rate 30]

Pillow's libjpeg-turbo encodes with the accurate DCT where the view's
TurboJPEG takes the fast one: the sizes agree within a few per cent.
"""
import argparse
import io
import json

from PIL import Image


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("left")
    p.add_argument("right")
    p.add_argument("--qualities", default="85,75,70,65,60")
    p.add_argument("--rate", type=float, default=30.0, help="frames a second (default 30)")
    o = p.parse_args()
    left, right = Image.open(o.left).convert("RGB"), Image.open(o.right).convert("RGB")
    if left.height != right.height:
        raise SystemExit(f"frame_bytes: the halves differ in height ({left.height} and {right.height})")
    frame = Image.new("RGB", (left.width + right.width, left.height))
    frame.paste(left, (0, 0))
    frame.paste(right, (left.width, 0))
    for q in (int(x) for x in o.qualities.split(",")):
        out = io.BytesIO()
        frame.save(out, "JPEG", quality=q, subsampling=2)  # 2: 4:2:0
        n = len(out.getvalue())
        print(json.dumps({"left": o.left, "right": o.right, "width": frame.width, "height": frame.height,
                          "quality": q, "bytes": n, "mbit_per_second": round(n * 8 * o.rate / 1e6, 2), "rate": o.rate}))


if __name__ == "__main__":
    main()
