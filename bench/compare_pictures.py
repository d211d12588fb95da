#!/usr/bin/env python3
"""How far apart two renders of the same scene are, as one JSON line:
PSNR over the RGB channels (0-255 scale), the largest per-channel pixel
difference, the pixels whose largest channel difference is over 1 and over
8, and the mean absolute difference; and the PSNR over the foreground only:
the pixels where either picture is not the top left pixel's colour (the
flat background of tools/render-blender.py), so that a garment small in the
frame does not have its difference diluted by the background.

    bench/compare_pictures.py A.png B.png [LABEL]

Needs numpy and PIL (Debian: python3-numpy, python3-pil). Pictures of
different sizes are refused in one line.
"""

import json
import math
import sys

import numpy as np
from PIL import Image


def rgb(path):
    try:
        return np.asarray(Image.open(path).convert("RGB"), dtype=np.int16)
    except OSError as e:
        raise SystemExit(f"compare_pictures: {path}: {e}")


def psnr(diff):
    """None where the pictures are identical."""
    mse = float(np.mean(diff.astype(np.float64) ** 2)) if diff.size else 0.0
    return None if mse == 0 else round(10 * math.log10(255.0 ** 2 / mse), 2)


def compare(a, b):
    diff = np.abs(a - b)
    per_pixel = diff.max(axis=2)
    foreground = np.any(a != a[0, 0], axis=2) | np.any(b != b[0, 0], axis=2)
    return {
        "psnr_db": psnr(diff),
        "psnr_db_foreground": psnr(diff[foreground]),
        "foreground_pixels": int(np.count_nonzero(foreground)),
        "max_channel_diff": int(diff.max()),
        "pixels_over_1": int(np.count_nonzero(per_pixel > 1)),
        "pixels_over_8": int(np.count_nonzero(per_pixel > 8)),
        "pixels": int(per_pixel.size),
        "mean_abs_diff": round(float(diff.mean()), 4),
    }


def main():
    if len(sys.argv) not in (3, 4):
        raise SystemExit("usage: bench/compare_pictures.py A.png B.png [LABEL]")
    a, b = rgb(sys.argv[1]), rgb(sys.argv[2])
    if a.shape != b.shape:
        raise SystemExit(f"compare_pictures: {sys.argv[1]} is {a.shape[1]}x{a.shape[0]}, "
                         f"{sys.argv[2]} {b.shape[1]}x{b.shape[0]}")
    line = {"compare": sys.argv[3]} if len(sys.argv) == 4 else {}
    line.update(compare(a, b))
    print(json.dumps(line))


main()
