#!/usr/bin/env python3
"""Scores centre-line tracing against the ground truth of make_set.py, beside a simple
baseline (scikit-image's skeletonize, the skeleton's pixel paths simplified by
Douglas-Peucker, widths from the Euclidean distance transform).

    python3 bench/centerline/score.py [--bin target/release/outlinefit] [--set DIR]
                                      [--out DIR] [--runs 3] [--sheet worst.png]

Builds the set with make_set.py when DIR has none, traces it with `outlinefit batch
--mode centerline` (JSON reports) and with `--mode outline` (for the time ratio; the two
are run alternately, `--runs` times each, and the medians compared), runs the baseline,
and prints per item kind:

  centre   mean distance between the traced and the true centre lines, px (both ways:
           traced samples to the truth and truth samples to the trace, averaged)
  width    mean |traced width - true width| at the traced samples, px
  count    share of items whose stroke count is exactly the truth's
  IoU      intersection over union of the re-rendered strokes and the input: coverage
           against coverage (8x8 samples per pixel) for anti-aliased input, the strokes'
           coverage thresholded at one half against the pixels for bilevel input

Targets (the issue's): anti-aliased strokes >= 3 px wide centre <= 0.25 px, bilevel
<= 0.5 px; width <= 0.3 px; count exact on >= 95 % of items; IoU >= 0.97.
"""
import argparse
import glob
import json
import math
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from PIL import Image
from scipy.ndimage import distance_transform_edt
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_set  # noqa: E402


def wang_ball_cubic(disks, t):
    """A cubic disk Wang-Ball curve at t: (x, y, r). Basis (1-t)^2, 2t(1-t)^2,
    2t^2(1-t), t^2."""
    m = 1 - t
    b = (m * m, 2 * t * m * m, 2 * t * t * m, t * t)
    return tuple(sum(bi * d[k] for bi, d in zip(b, disks)) for k in range(3))


def our_strokes(report):
    """Every stroke of a JSON report as centre samples [x, y, r] about 0.25 px apart."""
    out = []
    for st in report["trace"]["strokes"]:
        samples = []
        for seg in st["segments"]:
            disks = seg["control_disks"]
            coarse = [wang_ball_cubic(disks, k / 16) for k in range(17)]
            length = sum(math.dist(a[:2], b[:2]) for a, b in zip(coarse, coarse[1:]))
            n = max(1, int(math.ceil(length / 0.25)))
            start = 0 if not samples else 1
            samples += [list(wang_ball_cubic(disks, k / n)) for k in range(start, n + 1)]
        out.append(samples)
    return out


def measure(strokes, truth, coverage):
    """centre (both ways), width error, IoU of strokes given as [x, y, r] samples."""
    ours = np.array([p for s in strokes for p in s]) if any(strokes) else np.zeros((0, 3))
    true = np.array([p for s in truth["strokes"] for p in s])
    if len(ours) == 0:
        return dict(centre=float("inf"), fwd=float("inf"), back=float("inf"), werr=float("inf"), wbias=0.0, iou=0.0)
    t_tree = cKDTree(true[:, :2])
    d_fwd, idx = t_tree.query(ours[:, :2])
    o_tree = cKDTree(ours[:, :2])
    d_back, _ = o_tree.query(true[:, :2])
    width = np.abs(2 * ours[:, 2] - 2 * true[idx, 2])
    w, h = truth["size"]
    drawn = make_set.render([[(float(x), float(y), max(float(r), 0.0)) for x, y, r in s] for s in strokes], w, h)
    if truth["kind"] == "bw":
        # A bilevel input is compared with the strokes drawn bilevel, as a viewer would
        # see both at the image's resolution.
        drawn = (drawn >= 0.5).astype(np.float64)
    inter = np.minimum(drawn, coverage).sum()
    union = np.maximum(drawn, coverage).sum()
    return dict(
        centre=float((d_fwd.mean() + d_back.mean()) / 2),
        fwd=float(d_fwd.mean()),
        back=float(d_back.mean()),
        werr=float(width.mean()),
        wbias=float((2 * ours[:, 2] - 2 * true[idx, 2]).mean()),
        iou=float(inter / union) if union > 0 else 1.0,
    )


# --- the baseline ----------------------------------------------------------------------

RING = [(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)]


def skeleton_paths(skel):
    """Pixel paths of a skeleton between its nodes (pixels with other than two
    neighbours), and its loops."""
    from skimage.measure import approximate_polygon  # noqa: F401  (checked present)
    h, w = skel.shape
    pix = set(zip(*np.nonzero(skel)))

    def nbrs(p):
        return [(p[0] + dy, p[1] + dx) for dy, dx in RING if (p[0] + dy, p[1] + dx) in pix]

    node = {p for p in pix if len(nbrs(p)) != 2}
    seen_edges = set()
    visited = set()
    paths = []
    for n in node:
        for q in nbrs(n):
            if (n, q) in seen_edges:
                continue
            path = [n, q]
            prev, cur = n, q
            while cur not in node:
                visited.add(cur)
                nxt = [x for x in nbrs(cur) if x != prev and x not in path[-3:]]
                if not nxt:
                    break
                prev, cur = cur, nxt[0]
                path.append(cur)
            seen_edges.add((path[-1], path[-2]))
            seen_edges.add((n, q))
            paths.append(path)
        if not nbrs(n):
            paths.append([n])
    for p in pix - node - visited:
        if p in visited:
            continue
        path = [p]
        visited.add(p)
        prev, cur = None, p
        while True:
            nxt = [x for x in nbrs(cur) if x != prev and x not in visited]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            visited.add(cur)
            path.append(cur)
        paths.append(path)
    return paths


def baseline(coverage, tolerance=0.5):
    """(strokes as [x, y, r] samples, seconds): skeletonize + Douglas-Peucker + EDT."""
    from skimage.measure import approximate_polygon
    from skimage.morphology import skeletonize
    started = time.perf_counter()
    mask = coverage >= 0.5
    skel = skeletonize(mask)
    dist = distance_transform_edt(mask)
    strokes = []
    for path in skeleton_paths(skel):
        arr = np.array(path, dtype=float)
        simple = approximate_polygon(arr, tolerance) if len(arr) > 2 else arr
        rs = [dist[int(p[0]), int(p[1])] for p in simple]
        pts = [(p[1] + 0.5, p[0] + 0.5) for p in simple]
        if len(pts) == 1:
            strokes.append([[pts[0][0], pts[0][1], rs[0]]])
            continue
        samples = []
        for (a, ra), (b, rb) in zip(zip(pts, rs), zip(pts[1:], rs[1:])):
            n = max(1, int(math.ceil(math.dist(a, b) / 0.25)))
            for k in range(0 if not samples else 1, n + 1):
                t = k / n
                samples.append([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), ra + t * (rb - ra)])
        strokes.append(samples)
    return strokes, time.perf_counter() - started


def timed_batch(binary, png, out, mode):
    started = time.perf_counter()
    subprocess.run([binary, "batch", png, "-o", out, "--mode", mode, "--no-timings"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - started


def summarize(rows, label):
    def group(name, sel):
        items = [r for r in rows if sel(r)]
        if not items:
            return
        mean = lambda k: statistics.fmean(r[k] for r in items)
        exact = sum(r["count_ok"] for r in items) / len(items)
        print(f"| {label} | {name} | {len(items)} | {mean('centre'):.3f} | {mean('werr'):.3f} ({mean('wbias'):+.3f}) | "
              f"{100 * exact:.1f} % | {mean('iou'):.4f} | {min(r['iou'] for r in items):.4f} |")
    group("anti-aliased, width >= 3", lambda r: r["kind"] == "aa" and r["width"] >= 3)
    group("anti-aliased, width 1.5-2", lambda r: r["kind"] == "aa" and r["width"] < 3)
    group("bilevel, width >= 3", lambda r: r["kind"] == "bw" and r["width"] >= 3)
    group("bilevel, width 1.5-2", lambda r: r["kind"] == "bw" and r["width"] < 3)
    group("all", lambda r: True)


def sheet(rows, setdir, path, count=12):
    """The worst items (by centre error, stroke count first): input grey, traced strokes
    re-rendered with lost ink blue and invented ink red, true centre lines green, traced
    ones black."""
    from PIL import ImageDraw
    worst = sorted(rows, key=lambda r: (r["count_ok"], -r["centre"]))[:count]
    tiles = []
    for r in worst:
        truth = r["truth"]
        w, h = truth["size"]
        cov = r["coverage"]
        drawn = r["drawn"]
        z = max(1, int(300 / max(w, h)))
        rgb = np.stack([255 - 90 * cov] * 3, axis=-1)
        lost = (cov >= 0.5) & (drawn < 0.5)
        inv = (cov < 0.5) & (drawn >= 0.5)
        rgb[lost] = (40, 90, 255)
        rgb[inv] = (230, 40, 40)
        img = Image.fromarray(rgb.astype(np.uint8)).resize((w * z, h * z), Image.NEAREST)
        d = ImageDraw.Draw(img)
        for s in truth["strokes"]:
            d.line([(x * z, y * z) for x, y, _ in s], fill=(0, 170, 0), width=1)
        for s in r["strokes"]:
            if len(s) > 1:
                d.line([(x * z, y * z) for x, y, _ in s], fill=(0, 0, 0), width=1)
        d.text((4, 4), f"{truth['name']} c={r['centre']:.2f} n={r['n']}/{truth['count']}", fill=(0, 0, 0))
        tiles.append(img)
    cols = 4
    tw = max(t.width for t in tiles)
    th = max(t.height for t in tiles)
    out = Image.new("RGB", (cols * tw, ((len(tiles) + cols - 1) // cols) * th), "white")
    for k, t in enumerate(tiles):
        out.paste(t, ((k % cols) * tw, (k // cols) * th))
    out.save(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=os.path.join(HERE, "..", "..", "target", "release", "outlinefit"))
    ap.add_argument("--set", default="/tmp/outlinefit-centerline-set")
    ap.add_argument("--out", default="/tmp/outlinefit-centerline-out")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--sheet", default=None)
    args = ap.parse_args()
    png = os.path.join(args.set, "png")
    if not os.path.isdir(png):
        subprocess.run([sys.executable, os.path.join(HERE, "make_set.py"), args.set], check=True)
    ours_dir = os.path.join(args.out, "centerline")
    outline_dir = os.path.join(args.out, "outline")
    times = {"centerline": [], "outline": []}
    for _ in range(args.runs):
        times["centerline"].append(timed_batch(args.bin, png, ours_dir, "centerline"))
        times["outline"].append(timed_batch(args.bin, png, outline_dir, "outline"))
    ours_rows, base_rows = [], []
    base_time = 0.0
    for tf in sorted(glob.glob(os.path.join(args.set, "truth", "*.json"))):
        truth = json.load(open(tf))
        name = truth["name"]
        cov = 1.0 - np.asarray(Image.open(os.path.join(png, name + ".png")).convert("L"), dtype=float) / 255.0
        report = json.load(open(os.path.join(ours_dir, name + ".json")))
        strokes = our_strokes(report)
        m = measure(strokes, truth, cov)
        w, h = truth["size"]
        drawn = make_set.render([[(x, y, max(r, 0)) for x, y, r in s] for s in strokes], w, h)
        ours_rows.append(dict(m, kind=truth["kind"], width=truth["width"], n=len(strokes),
                              count_ok=len(strokes) == truth["count"], truth=truth, strokes=strokes,
                              coverage=cov, drawn=drawn, held=report["trace"]["check"]["held"]))
        bs, secs = baseline(cov)
        base_time += secs
        mb = measure(bs, truth, cov)
        base_rows.append(dict(mb, kind=truth["kind"], width=truth["width"], n=len(bs),
                              count_ok=len(bs) == truth["count"]))
    print(f"{len(ours_rows)} items in {args.set}\n")
    print("| tracer | items | n | centre px | width px (bias) | count exact | IoU mean | IoU min |")
    print("|---|---|---|---|---|---|---|---|")
    summarize(ours_rows, "outlinefit")
    summarize(base_rows, "skeletonize + DP")
    tc, to = statistics.median(times["centerline"]), statistics.median(times["outline"])
    print(f"\ntime: centerline batch {tc:.2f} s, outline batch {to:.2f} s: {tc / to:.2f}x "
          f"(median of {args.runs} alternating runs); baseline {base_time:.2f} s in-process")
    held = sum(r["held"] for r in ours_rows)
    print(f"check held on {held} of {len(ours_rows)} items")
    bad = [r for r in ours_rows if not r["count_ok"]]
    if bad:
        print("stroke count wrong: " + ", ".join(f"{r['truth']['name']} ({r['n']} vs {r['truth']['count']})" for r in bad))
    if args.sheet:
        sheet(ours_rows, args.set, args.sheet)
        print(f"worst items: {args.sheet}")


if __name__ == "__main__":
    main()
