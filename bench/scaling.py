#!/usr/bin/env python3
"""Time and peak memory of `outlinefit trace` against potrace on large inputs.

usage: python3 bench/scaling.py [OUTLINEFIT] [--repeats N] [--keep DIR]

Inputs, written to a temporary folder (or DIR):
  - scikit-image's horse silhouette (400 x 328, bilevel) upscaled bicubically by 1, 2, 4
    and 10.24 (4096 x 3359): the same outline at growing resolution;
  - a 600 dpi A4 page (4960 x 7016) of 12-point DejaVu Sans text, anti-aliased, 41 lines.
potrace gets each input thresholded at 50 % as PBM (its own format; not timed). Prints,
per input and tool, the median wall time, CPU time (user + system) and peak resident
memory over the repeats, then our ratios to potrace. Needs scikit-image, Pillow and GNU
time (/usr/bin/time).
"""
import os
import random
import statistics
import sys
import tempfile

import numpy as np
from PIL import Image, ImageDraw, ImageFont
from skimage import data

from timing import run

args = [a for a in sys.argv[1:]]
repeats = 3
keep = None
if "--repeats" in args:
    i = args.index("--repeats")
    repeats = int(args[i + 1])
    del args[i : i + 2]
if "--keep" in args:
    i = args.index("--keep")
    keep = args[i + 1]
    del args[i : i + 2]
ours = args[0] if args else os.path.join(os.path.dirname(__file__), "..", "target", "release", "outlinefit")
FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
if not os.path.exists(FONT):
    FONT = os.path.join(os.path.dirname(__file__), "..", "samples", "fonts", "DejaVuSans.ttf")


def make_inputs(folder):
    horse = Image.fromarray(np.where(data.horse(), 255, 0).astype(np.uint8))
    inputs = []
    for scale in (1, 2, 4, 10.24):
        size = (round(horse.width * scale), round(horse.height * scale))
        img = horse if scale == 1 else horse.resize(size, Image.BICUBIC)
        name = f"horse{scale}"
        img.save(os.path.join(folder, name + ".png"))
        inputs.append((name, img))
    rng = random.Random(1)
    page = Image.new("L", (4960, 7016), 255)
    draw = ImageDraw.Draw(page)
    font = ImageFont.truetype(FONT, 100)  # 12 pt at 600 dpi
    words = ("outline fitting rational cubic Bezier harmony search tolerance contour vector "
             "glyph logo potrace segment curvature break point weight least squares").split()
    y = 400
    while y < page.height - 500:
        line = []
        while True:
            w = rng.choice(words)
            if draw.textlength(" ".join(line + [w]), font=font) > page.width - 800:
                break
            line.append(w)
        draw.text((400, y), " ".join(line), font=font, fill=0)
        y += 150
    page.save(os.path.join(folder, "a4page.png"))
    inputs.append(("a4page", page))
    for name, img in inputs:
        img.point(lambda v: 0 if v < 128 else 255).convert("1").save(os.path.join(folder, name + ".pbm"))
    return [name for name, _ in inputs]


def median_run(cmd):
    runs = [run(cmd) for _ in range(repeats)]
    return tuple(statistics.median(r[k] for r in runs) for k in range(3))


def main():
    folder = keep or tempfile.mkdtemp(prefix="outlinefit-scaling-")
    os.makedirs(folder, exist_ok=True)
    names = make_inputs(folder)
    print(f"inputs in {folder}; median of {repeats} runs")
    print("| input | pixels | outlinefit wall s | CPU s | peak MB | potrace wall s | CPU s | peak MB | time ratio | memory ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in names:
        png, pbm = os.path.join(folder, name + ".png"), os.path.join(folder, name + ".pbm")
        w, h = Image.open(png).size
        o = median_run([ours, "trace", png, "-o", os.path.join(folder, name + ".svg")])
        p = median_run(["potrace", "-s", "-o", os.path.join(folder, name + ".potrace.svg"), pbm])
        print(f"| {name} | {w} x {h} | {o[0]:.3f} | {o[1]:.3f} | {o[2]:.0f} | {p[0]:.3f} | {p[1]:.3f} | "
              f"{p[2]:.0f} | {o[0] / p[0]:.1f} | {o[2] / p[2]:.1f} |")


main()
