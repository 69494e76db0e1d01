#!/usr/bin/env python3
"""The speed, memory and size ratios of the README's speed table, against potrace and
vtracer, from one run on this machine.

usage: python3 bench/ratios.py [--repeats N] [--keep DIR] [--skip-corpus] [--quality]

Needs the benchmark folder beside the project (../shared/bench, or BENCH=DIR) with its
corpus built (make_corpus.sh), scikit-image (pip install scikit-image), potrace, GNU
time (/usr/bin/time) and the release build (cargo build --release; OUTLINEFIT=PATH
times another build of ours, e.g. the statically linked one of the README's "Start-up"
paragraph). Inputs are made in a temporary folder (or DIR):

  - scan:      a 600 dpi A4 page of 12-point serif text with scanner blur and noise
               (realworld/make_scan.py's scan.png, 4960 x 7016; potrace gets its scan.pbm);
  - upscaled:  scikit-image's scanned page upscaled 10x (make_scan.py's upscaled.png);
  - horse S:   scikit-image's horse upscaled bicubically by S = 1, 2, 4, 8.192 (the last
               is 3277 x 2687) and 10.24 (4096 x 3359), thresholded for potrace.

Each command runs N times (default 3), alternating ours and potrace; the median wall
time, CPU time and peak memory are printed with their ratios, then the SVG bytes and
segments of the last run. The corpus part times one process per file for ours and
potrace over the corpus (912 images) and one process for the folder for ours (`batch`)
and vtracer (its Python API looping over the folder, as the benchmark's harness runs
it). `--quality` also scores the per-file outputs against the truth (score.py) and
prints per subset the mean area error, Hausdorff distance and segments of ours over
potrace's. The start-up of `outlinefit --version` is timed beside `potrace --version`.
"""
import csv
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from timing import run

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BENCH = Path(os.environ.get("BENCH", ROOT.parent / "shared" / "bench")).resolve()
OURS = os.environ.get("OUTLINEFIT", str(ROOT / "target" / "release" / "outlinefit"))

args = sys.argv[1:]


def option(name, default):
    if name in args:
        i = args.index(name)
        value = args[i + 1]
        del args[i : i + 2]
        return value
    return default


repeats = int(option("--repeats", "3"))
keep = option("--keep", None)
skip_corpus = "--skip-corpus" in args
quality = "--quality" in args


def alternate(a, b):
    """Median (wall, CPU, MB) of `a` and of `b`, run in turn `repeats` times."""
    ra, rb = [], []
    for _ in range(repeats):
        ra.append(run(a))
        rb.append(run(b))
    med = lambda rs: tuple(statistics.median(r[k] for r in rs) for k in range(3))
    return med(ra), med(rb)


def segments(svg):
    """Drawn pieces of an SVG's paths (the benchmark's own count)."""
    sys.path.insert(0, str(BENCH))
    from score import count_segments

    text = Path(svg).read_text()
    return sum(count_segments(d)[0] for d in re.findall(r'\sd="([^"]*)"', text))


def make_inputs(folder):
    from PIL import Image
    import numpy as np
    from skimage import data

    realworld = BENCH / "realworld"
    if not (realworld / "inputs" / "page.png").exists():
        subprocess.run([sys.executable, str(realworld / "make_inputs.py")], check=True,
                       stdout=subprocess.DEVNULL)
    if not (folder / "scan.png").exists():
        subprocess.run([sys.executable, str(realworld / "make_scan.py"), str(folder)], check=True)
    horse = Image.fromarray(np.where(data.horse(), 255, 0).astype(np.uint8))
    names = ["scan", "upscaled"]
    for scale in (1, 2, 4, 8.192, 10.24):
        name = f"horse{scale:g}"
        size = (round(horse.width * scale), round(horse.height * scale))
        img = horse if scale == 1 else horse.resize(size, Image.BICUBIC)
        img.save(folder / f"{name}.png")
        img.point(lambda v: 0 if v < 128 else 255).convert("1").save(folder / f"{name}.pbm")
        names.append(name)
    return names


def large_inputs(folder):
    names = make_inputs(folder)
    print(f"## Large inputs (median of {repeats}, alternating; inputs in {folder})\n")
    print("| input | ours wall s | CPU s | MB | potrace wall s | CPU s | MB | wall | memory | bytes | segments | repaired contours |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    walls = {}
    for name in names:
        png, pbm = folder / f"{name}.png", folder / f"{name}.pbm"
        ours_svg, pot_svg = folder / f"{name}.svg", folder / f"{name}.potrace.svg"
        report = folder / f"{name}.json"
        o, p = alternate([OURS, "trace", str(png), "-o", str(ours_svg), "--report", str(report)],
                         ["potrace", "-s", "-o", str(pot_svg), str(pbm)])
        walls[name] = o[0]
        import json

        fidelity = json.loads(report.read_text())["images"][0]["fidelity"]
        sb, pb = ours_svg.stat().st_size, pot_svg.stat().st_size
        ss, ps = segments(ours_svg), segments(pot_svg)
        print(f"| {name} | {o[0]:.3f} | {o[1]:.3f} | {o[2]:.0f} | {p[0]:.3f} | {p[1]:.3f} | {p[2]:.0f} "
              f"| **{o[0] / p[0]:.2f}×** | {o[2] / p[2]:.2f}× | {sb / pb:.2f}× | {ss / ps:.2f}× "
              f"| {fidelity['repaired_contours']} |")
    print()
    steps = [("horse1", "horse2"), ("horse2", "horse4"), ("horse4", "horse8.192")]
    print("Time for 2× the linear size: " + ", ".join(
        f"{a}→{b} {walls[b] / walls[a]:.2f}×" for a, b in steps) + "\n")


def startup():
    o, p = alternate([OURS, "--version"], ["potrace", "--version"])
    print(f"Start-up (`--version`, median of {repeats}): ours {o[0] * 1000:.1f} ms, "
          f"potrace {p[0] * 1000:.1f} ms ({o[0] / p[0]:.2f}×)\n")


def timed_loop(cmds):
    start = time.perf_counter()
    for cmd in cmds:
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def timed(cmd):
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def corpus(folder):
    pngs = sorted((BENCH / "corpus" / "png").glob("*.png"))
    if not pngs:
        sys.exit(f"no corpus in {BENCH}/corpus: run make_corpus.sh there first")
    pbm_dir = folder / "pbm"
    subprocess.run([sys.executable, str(BENCH / "tools" / "png2pbm.py"), str(BENCH / "corpus" / "png"),
                    str(pbm_dir)], check=True, stdout=subprocess.DEVNULL)
    dirs = {k: folder / k for k in ("ours", "potrace", "batch", "vtracer")}
    per_file, batch = ([], []), ([], [])
    for _ in range(repeats):
        for d in dirs.values():
            shutil.rmtree(d, ignore_errors=True)
            d.mkdir(parents=True)
        per_file[0].append(timed_loop(
            [[OURS, "trace", str(p), "-o", str(dirs["ours"] / (p.stem + ".svg"))] for p in pngs]))
        per_file[1].append(timed_loop(
            [["potrace", "-s", "-o", str(dirs["potrace"] / (p.stem + ".svg")), str(pbm_dir / (p.stem + ".pbm"))]
             for p in pngs]))
        batch[0].append(timed([OURS, "batch", str(BENCH / "corpus" / "png"), "-o", str(dirs["batch"]),
                               "--svg-only"]))
        batch[1].append(timed([sys.executable, str(BENCH / "tools" / "vtracer_batch.py"),
                               str(BENCH / "corpus" / "png"), str(dirs["vtracer"])]))
    pf = [statistics.median(v) for v in per_file]
    bt = [statistics.median(v) for v in batch]
    print(f"## Corpus ({len(pngs)} images, median of {repeats}, wall seconds)\n")
    print("| run | ours | baseline | ratio |")
    print("|---|---|---|---|")
    print(f"| one process per file, against potrace | {pf[0]:.2f} | {pf[1]:.2f} | **{pf[0] / pf[1]:.2f}×** |")
    print(f"| one process for the folder, against vtracer's loop | {bt[0]:.2f} | {bt[1]:.2f} | **{bt[0] / bt[1]:.2f}×** |")
    print()
    if quality:
        scores = {}
        for k in ("ours", "potrace"):
            out = folder / f"{k}.csv"
            subprocess.run([sys.executable, str(BENCH / "score.py"), "--svgdir", str(dirs[k]), "--out", str(out),
                            "--no-cache"], check=True, stdout=subprocess.DEVNULL)
            with open(out) as fh:
                scores[k] = list(csv.DictReader(fh))
        print("## Quality, ours / potrace (means per subset)\n")
        print("| subset | area error | Hausdorff | segments | items > 3 px ours / potrace |")
        print("|---|---|---|---|---|")
        subsets = sorted({r["subset"] for r in scores["ours"]})
        for s in subsets:
            rows = {k: [r for r in v if r["subset"] == s and r["status"] == "ok"] for k, v in scores.items()}
            mean = lambda k, f: statistics.fmean(float(r[f]) for r in rows[k])
            gross = lambda k: sum(float(r["hausdorff_px"]) > 3 for r in rows[k])
            print(f"| {s} | {mean('ours', 'symdiff_px') / mean('potrace', 'symdiff_px'):.2f}× "
                  f"| {mean('ours', 'hausdorff_px') / mean('potrace', 'hausdorff_px'):.2f}× "
                  f"| {mean('ours', 'segments') / mean('potrace', 'segments'):.2f}× "
                  f"| {gross('ours')} / {gross('potrace')} |")
        print()


def main():
    if not Path(OURS).exists():
        sys.exit(f"{OURS} missing: cargo build --release first")
    for module, package in (("PIL", "pillow"), ("numpy", "numpy"), ("skimage", "scikit-image")):
        try:
            __import__(module)
        except ImportError:
            sys.exit(f"the inputs need Python's {package}: python3 -m pip install {package}")
    folder = Path(keep or tempfile.mkdtemp(prefix="outlinefit-ratios-"))
    folder.mkdir(parents=True, exist_ok=True)
    startup()
    large_inputs(folder)
    if not skip_corpus:
        corpus(folder)


main()
