#!/usr/bin/env python3
"""Quality on blurred and upscaled glyphs, whose true outlines are known: ours (default,
and with --fixed-tolerance) against potrace, scored by the benchmark's score.py.

usage: python3 bench/soft_edges.py [--keep DIR] [--limit N]

Needs the benchmark folder beside the project (../shared/bench, or BENCH=DIR) with its
corpus built (make_corpus.sh), potrace, and the release build (cargo build --release;
OUTLINEFIT=PATH scores another build of ours).
From the corpus's anti-aliased 64 px and 256 px glyphs it makes three subsets in a
temporary folder (or DIR), each item with its truth:

  - up4:    a 64 px glyph upscaled 4x bicubically (its truth: the 64 px truth drawn 4x);
  - up8:    a 64 px glyph upscaled 8x bicubically;
  - blur2:  a 256 px glyph blurred by a Gaussian of 2 px.

and prints per subset and tool the mean area error (px^2), Hausdorff distance (px) and
segments, with ours over potrace's. potrace reads each image thresholded at 50 % as PBM.
"""
import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image, ImageFilter

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
BENCH = Path(os.environ.get("BENCH", ROOT.parent / "shared" / "bench"))
OURS = Path(os.environ.get("OUTLINEFIT", ROOT / "target" / "release" / "outlinefit"))

SUBSETS = {
    # name: (source subset, make the image from the source PNG, truth scale)
    "up4": ("dev-glyph64", lambda im: im.resize((im.width * 4, im.height * 4), Image.BICUBIC), 4),
    "up8": ("dev-glyph64", lambda im: im.resize((im.width * 8, im.height * 8), Image.BICUBIC), 8),
    "blur2": ("dev-glyph256", lambda im: im.filter(ImageFilter.GaussianBlur(2)), 1),
}


def scaled_truth(src: Path, dst: Path, scale: int) -> None:
    """The truth SVG drawn `scale` times larger: width and height scaled, viewBox kept."""
    text = src.read_text()
    head, rest = text.split(">", 1)
    for attr in ("width", "height"):
        key = f'{attr}="'
        i = head.index(key) + len(key)
        j = head.index('"', i)
        head = head[:i] + str(float(head[i:j]) * scale).rstrip("0").rstrip(".") + head[j:]
    dst.write_text(head + ">" + rest)


def make(corpus: Path, out: Path, limit: int) -> Path:
    rows = list(csv.DictReader(open(corpus / "manifest.csv")))
    (out / "png").mkdir(parents=True, exist_ok=True)
    (out / "truth").mkdir(exist_ok=True)
    (out / "pbm").mkdir(exist_ok=True)
    manifest = []
    for name, (source, transform, scale) in SUBSETS.items():
        picked = [r for r in rows if r["subset"] == source][:limit]
        for r in picked:
            ident = f"{name}_{r['id'].split('_', 1)[1]}"
            image = transform(Image.open(corpus / r["png"]).convert("L"))
            image.save(out / "png" / f"{ident}.png")
            image.point(lambda v: 0 if v < 128 else 255).convert("1").save(
                out / "pbm" / f"{ident}.pbm"
            )
            scaled_truth(corpus / r["truth"], out / "truth" / f"{ident}.svg", scale)
            manifest.append(
                {
                    "id": ident,
                    "subset": name,
                    "png": f"png/{ident}.png",
                    "truth": f"truth/{ident}.svg",
                    "width": image.width,
                    "height": image.height,
                    "source": r["source"],
                    "label": r["label"],
                }
            )
    path = out / "manifest.csv"
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(manifest[0]))
        writer.writeheader()
        writer.writerows(manifest)
    return path


def run_tool(out: Path, name: str, command) -> Path:
    svgdir = out / name
    svgdir.mkdir(exist_ok=True)
    for png in sorted((out / "png").glob("*.png")):
        ident = png.stem
        subprocess.run(command(ident, svgdir / f"{ident}.svg"), check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return svgdir


def score(manifest: Path, svgdir: Path) -> dict:
    scored = svgdir.with_suffix(".csv")
    subprocess.run([sys.executable, str(BENCH / "score.py"), "--svgdir", str(svgdir),
                    "--out", str(scored), "--manifest", str(manifest), "--no-cache"],
                   check=True, stdout=subprocess.DEVNULL)
    by_subset = {}
    for r in csv.DictReader(open(scored)):
        by_subset.setdefault(r["subset"], []).append(r)
    return {
        s: {k: statistics.mean(float(r[k]) for r in rows)
            for k in ("symdiff_px", "hausdorff_px", "segments")}
        for s, rows in by_subset.items()
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--keep", help="make the inputs and outputs here, and keep them")
    ap.add_argument("--limit", type=int, default=60, help="glyphs per subset (default 60)")
    args = ap.parse_args()
    if not OURS.exists():
        sys.exit(f"{OURS} is missing: run cargo build --release first")
    corpus = BENCH / "corpus"
    if not (corpus / "manifest.csv").exists():
        sys.exit(f"no corpus at {corpus}: run make_corpus.sh there first")
    out = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="soft_edges_"))
    manifest = make(corpus, out, args.limit)
    ours = lambda extra: lambda ident, svg: [
        str(OURS), "trace", str(out / "png" / f"{ident}.png"), "-o", str(svg), *extra]
    tools = {
        "outlinefit": ours([]),
        "outlinefit --fixed-tolerance": ours(["--fixed-tolerance"]),
        "potrace": lambda ident, svg: [
            "potrace", "-s", "-o", str(svg), str(out / "pbm" / f"{ident}.pbm")],
    }
    results = {}
    for name, command in tools.items():
        svgdir = run_tool(out, name.replace(" --", "_").replace("-", "_"), command)
        results[name] = score(manifest, svgdir)
    print("| subset | tool | area error px² | Hausdorff px | segments |")
    print("|---|---|---|---|---|")
    base = results["potrace"]
    for subset in SUBSETS:
        for name, by in results.items():
            m, p = by[subset], base[subset]
            cells = [f"{m[k]:.1f}" if name == "potrace" else f"{m[k]:.1f} = {m[k] / p[k]:.2f}×"
                     for k in ("symdiff_px", "hausdorff_px", "segments")]
            if name != "potrace":
                cells[1] = f"{m['hausdorff_px']:.2f} = {m['hausdorff_px'] / p['hausdorff_px']:.2f}×"
            else:
                cells[1] = f"{m['hausdorff_px']:.2f}"
            print(f"| {subset} | {name} | " + " | ".join(cells) + " |")
    if not args.keep:
        print(f"(inputs and outputs in {out}; --keep DIR keeps them somewhere chosen)")


if __name__ == "__main__":
    main()
