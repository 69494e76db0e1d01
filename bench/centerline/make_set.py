#!/usr/bin/env python3
"""Builds the centre-line ground truth: strokes of known centre line and width, rendered
anti-aliased and bilevel.

    python3 bench/centerline/make_set.py DIR [--quick]

writes DIR/png/<name>.png (the image) and DIR/truth/<name>.json (the truth: every stroke
as centre samples [x, y, r] about 0.25 px apart, and the stroke count the tracer should
find). A stroke is the union of the disks along its centre line: round caps, round joins.

Families: line, arc, S-curve, spiral, ring, X, T and Y junctions, tapered line/arc/S, and
letters and words from the Hershey single-stroke fonts (PyPI `Hershey-Fonts`). Widths
1.5-12 px. Anti-aliased images are rendered at 8x8 samples per pixel; bilevel ones are
the same coverage thresholded at one half.

The truth's stroke count follows the rules the tracer documents: strokes that meet end to
end are one stroke; at a junction, the two branches that turn least continue each other
when they turn by at most 50 degrees; so an X or a t is two strokes. For the Hershey text
the count is computed with those rules from the font's polylines (crossings and
touchings found geometrically).
"""
import json
import math
import os
import sys

import numpy as np
from PIL import Image

SS = 8  # samples per pixel side
PAIR_TURN = math.radians(50.0)
STEP = 0.25


def resample(points, step=STEP):
    """A polyline resampled about `step` px apart (ends kept)."""
    out = [points[0]]
    for a, b in zip(points, points[1:]):
        d = math.dist(a, b)
        n = max(1, int(math.ceil(d / step)))
        for k in range(1, n + 1):
            t = k / n
            out.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    return out


def stroke(points, r0, r1=None):
    """Centre samples [x, y, r] of a stroke with radius r0 (tapering linearly to r1)."""
    pts = resample(points)
    r1 = r0 if r1 is None else r1
    s = [0.0]
    for a, b in zip(pts, pts[1:]):
        s.append(s[-1] + math.dist(a, b))
    total = s[-1] or 1.0
    return [[p[0], p[1], r0 + (r1 - r0) * si / total] for p, si in zip(pts, s)]


def render(strokes, w, h):
    """Coverage (0-1 floats, h x w) of the union of every stroke's disks: a sample (SS x SS
    per pixel, at the sample's centre) is inside when it lies within some disk."""
    inside = np.zeros((h * SS, w * SS), dtype=bool)
    for st in strokes:
        for x, y, r in st:
            cx, cy, rr = x * SS, y * SS, r * SS
            x0, x1 = max(0, int(cx - rr) - 1), min(w * SS, int(cx + rr) + 2)
            y0, y1 = max(0, int(cy - rr) - 1), min(h * SS, int(cy + rr) + 2)
            if x0 >= x1 or y0 >= y1:
                continue
            xs = np.arange(x0, x1) + 0.5 - cx
            ys = np.arange(y0, y1) + 0.5 - cy
            inside[y0:y1, x0:x1] |= (xs[None, :] ** 2 + ys[:, None] ** 2) <= rr * rr
    return inside.reshape(h, SS, w, SS).mean(axis=(1, 3))


def arc_points(cx, cy, rad, a0, a1, n=400):
    return [(cx + rad * math.cos(a0 + (a1 - a0) * k / n), cy + rad * math.sin(a0 + (a1 - a0) * k / n)) for k in range(n + 1)]


def bezier(p0, p1, p2, p3, n=400):
    out = []
    for k in range(n + 1):
        t = k / n
        m = 1 - t
        out.append(tuple(m ** 3 * a + 3 * m * m * t * b + 3 * m * t * t * c + t ** 3 * d for a, b, c, d in zip(p0, p1, p2, p3)))
    return out


def spiral(cx, cy, a0, pitch, turns, n=2000):
    out = []
    for k in range(n + 1):
        th = 2 * math.pi * turns * k / n
        rad = a0 + pitch * th / (2 * math.pi)
        out.append((cx + rad * math.cos(th), cy + rad * math.sin(th)))
    return out


def synthetic(widths, rng):
    """(name, strokes, count, size) of the drawn families."""
    items = []
    for w in widths:
        r = w / 2
        m = r + 6  # margin
        size = int(2 * m + 100)
        c = size / 2
        ang = rng.uniform(0, math.pi)
        d = (math.cos(ang) * 48, math.sin(ang) * 48)
        items.append(("line", [stroke([(c - d[0], c - d[1]), (c + d[0], c + d[1])], r)], 1, size))
        a0 = rng.uniform(0, 2 * math.pi)
        items.append(("arc", [stroke(arc_points(c, c, 40, a0, a0 + rng.uniform(1.2, 4.5)), r)], 1, size))
        items.append(("scurve", [stroke(bezier((c - 45, c + 30), (c + 60, c + 40), (c - 60, c - 40), (c + 45, c - 30)), r)], 1, size))
        items.append(("ring", [stroke(arc_points(c, c, 38, 0, 2 * math.pi), r)], 1, size))
        pitch = max(2.5 * w + 4, 10)
        items.append(("spiral", [stroke(spiral(c, c, pitch, pitch, 1.6), r)], 1, size))
        t = rng.uniform(math.radians(55), math.radians(90))
        e1 = (math.cos(ang) * 45, math.sin(ang) * 45)
        e2 = (math.cos(ang + t) * 45, math.sin(ang + t) * 45)
        items.append(("x", [stroke([(c - e1[0], c - e1[1]), (c + e1[0], c + e1[1])], r),
                            stroke([(c - e2[0], c - e2[1]), (c + e2[0], c + e2[1])], r)], 2, size))
        items.append(("t", [stroke([(c - 45, c - 25), (c + 45, c - 25)], r),
                            stroke([(c, c - 25), (c, c + 45)], r)], 2, size))
        bend = math.radians(rng.uniform(15, 30))
        up = (0, -1)
        arm = (math.sin(bend), -math.cos(bend))
        other = (-math.sin(math.radians(45)), -math.cos(math.radians(45)))
        j = (c, c + 5)
        items.append(("y", [stroke([(c, c + 48), j, (j[0] + arm[0] * 45, j[1] + arm[1] * 45)], r),
                            stroke([j, (j[0] + other[0] * 45, j[1] + other[1] * 45)], r)], 2, size))
        if w >= 3:
            lo, hi = 0.75, r
            items.append(("taper-line", [stroke([(c - d[0], c - d[1]), (c + d[0], c + d[1])], lo, hi)], 1, size))
            items.append(("taper-arc", [stroke(arc_points(c, c, 40, a0, a0 + 3.5), hi, lo)], 1, size))
            items.append(("taper-s", [stroke(bezier((c - 45, c + 30), (c + 60, c + 40), (c - 60, c - 40), (c + 45, c - 30)), lo, hi)], 1, size))
    return items


# --- the stroke count of polylines, by the tracer's rules ---------------------------------

def seg_intersection(a, b, c, d):
    """Parameter pair (t, u) where segment ab meets cd, or None."""
    r = (b[0] - a[0], b[1] - a[1])
    s = (d[0] - c[0], d[1] - c[1])
    den = r[0] * s[1] - r[1] * s[0]
    if abs(den) < 1e-12:
        return None
    q = (c[0] - a[0], c[1] - a[1])
    t = (q[0] * s[1] - q[1] * s[0]) / den
    u = (q[0] * r[1] - q[1] * r[0]) / den
    if -1e-9 <= t <= 1 + 1e-9 and -1e-9 <= u <= 1 + 1e-9:
        return t, u
    return None


def stroke_count(polylines, merge_dist):
    """Strokes of a drawing of polylines: nodes at ends, crossings and touchings (points
    closer than `merge_dist` are one node); end-to-end strokes joined; at junctions the
    pair that turns least continues, if it turns by at most 50 degrees."""
    # Split every polyline at its crossings with the others (and itself).
    cuts = [set() for _ in polylines]  # (segment index, t)
    for i, p in enumerate(polylines):
        for j, q in enumerate(polylines):
            for a in range(len(p) - 1):
                for b in range(len(q) - 1):
                    if i == j and abs(a - b) <= 1:
                        continue
                    hit = seg_intersection(p[a], p[a + 1], q[b], q[b + 1])
                    if hit:
                        cuts[i].add((a, round(hit[0], 9)))
    # Touchings: an end within merge_dist of another polyline's interior.
    for i, p in enumerate(polylines):
        for end in (p[0], p[-1]):
            for j, q in enumerate(polylines):
                for b in range(len(q) - 1):
                    a_, b_ = q[b], q[b + 1]
                    vx, vy = b_[0] - a_[0], b_[1] - a_[1]
                    L2 = vx * vx + vy * vy
                    if L2 == 0:
                        continue
                    t = ((end[0] - a_[0]) * vx + (end[1] - a_[1]) * vy) / L2
                    if 0 < t < 1:
                        foot = (a_[0] + t * vx, a_[1] + t * vy)
                        if math.dist(foot, end) < merge_dist and not (j == i):
                            cuts[j].add((b, round(t, 9)))
    pieces = []
    for i, p in enumerate(polylines):
        marks = sorted(cuts[i])
        cur = [p[0]]
        k = 0
        for a in range(len(p) - 1):
            while k < len(marks) and marks[k][0] == a:
                t = marks[k][1]
                pt = (p[a][0] + t * (p[a + 1][0] - p[a][0]), p[a][1] + t * (p[a + 1][1] - p[a][1]))
                if math.dist(pt, cur[-1]) > 1e-9:
                    cur.append(pt)
                if len(cur) >= 2:
                    pieces.append(cur)
                cur = [pt]
                k += 1
            cur.append(p[a + 1])
        if len(cur) >= 2 and sum(math.dist(x, y) for x, y in zip(cur, cur[1:])) > 1e-9:
            pieces.append(cur)
    pieces = [pc for pc in pieces if sum(math.dist(x, y) for x, y in zip(pc, pc[1:])) > 1e-6]
    # Nodes: piece ends merged within merge_dist.
    nodes = []

    def node_of(pt):
        for k, n in enumerate(nodes):
            if math.dist(n, pt) < merge_dist:
                return k
        nodes.append(pt)
        return len(nodes) - 1

    ends = [(node_of(pc[0]), node_of(pc[-1])) for pc in pieces]
    degree = [0] * len(nodes)
    for a, b in ends:
        degree[a] += 1
        degree[b] += 1

    def leaving(k, end):
        pc = pieces[k] if end == 0 else pieces[k][::-1]
        far = pc[-1]
        acc = 0.0
        for x, y in zip(pc, pc[1:]):
            acc += math.dist(x, y)
            far = y
            if acc >= 8.0:
                break
        v = (far[0] - pc[0][0], far[1] - pc[0][1])
        n = math.hypot(*v) or 1.0
        return (v[0] / n, v[1] / n)

    link = {}
    for n in range(len(nodes)):
        at = [(k, e) for k, (a, b) in enumerate(ends) for e, x in ((0, a), (1, b)) if x == n]
        if len(at) == 2:
            link[at[0]] = at[1]
            link[at[1]] = at[0]
            continue
        dirs = [leaving(k, e) for k, e in at]
        pairs = []
        for i in range(len(at)):
            for j in range(i + 1, len(at)):
                a, b = (-dirs[i][0], -dirs[i][1]), dirs[j]
                turn = math.atan2(abs(a[0] * b[1] - a[1] * b[0]), a[0] * b[0] + a[1] * b[1])
                if turn <= PAIR_TURN:
                    pairs.append((turn, i, j))
        used = set()
        for _, i, j in sorted(pairs):
            if i in used or j in used:
                continue
            used |= {i, j}
            link[at[i]] = at[j]
            link[at[j]] = at[i]
    seen = set()
    count = 0
    for k in range(len(pieces)):
        if k in seen:
            continue
        count += 1
        stack = [k]
        while stack:
            x = stack.pop()
            if x in seen:
                continue
            seen.add(x)
            for e in (0, 1):
                y = link.get((x, e))
                if y and y[0] not in seen:
                    stack.append(y[0])
    return count


def hershey(words, widths, scale):
    from HersheyFonts import HersheyFonts
    font = HersheyFonts()
    font.load_default_font("futural")
    items = []
    for text in words:
        polys = [[(x * scale, y * scale) for x, y in line] for line in font.strokes_for_text(text)]
        xs = [p[0] for pl in polys for p in pl]
        ys = [p[1] for pl in polys for p in pl]
        for w in widths:
            m = w / 2 + 6
            dx, dy = m - min(xs), m - min(ys)
            moved = [[(x + dx, y + dy) for x, y in pl] for pl in polys]
            wpx = int(math.ceil(max(xs) - min(xs) + 2 * m))
            hpx = int(math.ceil(max(ys) - min(ys) + 2 * m))
            count = stroke_count(moved, max(w, 1.0))
            items.append((f"hershey-{text}", [stroke(pl, w / 2) for pl in moved], count, (wpx, hpx)))
    return items


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    quick = "--quick" in sys.argv
    rng = np.random.default_rng(7)

    class R:
        def uniform(self, a, b):
            return float(rng.uniform(a, b))

    widths = [1.5, 3, 5, 8, 12] if not quick else [3, 8]
    items = synthetic(widths, R())
    words = ["t", "x", "A", "K", "y", "s", "hello", "Wave", "stroke"] if not quick else ["t", "hello"]
    items += hershey(words, [2, 3.5, 5], 4.0)
    os.makedirs(os.path.join(out, "png"), exist_ok=True)
    os.makedirs(os.path.join(out, "truth"), exist_ok=True)
    seen = {}
    for name, strokes, count, size in items:
        # Every item is framed by its own extent plus a margin (a spiral can outgrow the
        # nominal square).
        m = max(p[2] for s in strokes for p in s) + 6
        x0 = min(p[0] for s in strokes for p in s) - m
        y0 = min(p[1] for s in strokes for p in s) - m
        strokes = [[[p[0] - x0, p[1] - y0, p[2]] for p in s] for s in strokes]
        w = int(math.ceil(max(p[0] for s in strokes for p in s) + m))
        h = int(math.ceil(max(p[1] for s in strokes for p in s) + m))
        width = round(2 * max(p[2] for s in strokes for p in s), 2)
        cov = render(strokes, w, h)
        for kind in ("aa", "bw"):
            img = cov if kind == "aa" else (cov >= 0.5).astype(np.float64)
            stem = f"{name}-w{width:g}-{kind}"
            seen[stem] = seen.get(stem, 0) + 1
            if seen[stem] > 1:
                stem += f"-{seen[stem]}"
            Image.fromarray(np.round(255 * (1 - img)).astype(np.uint8)).save(os.path.join(out, "png", stem + ".png"))
            truth = {
                "name": stem,
                "family": name,
                "kind": kind,
                "width": width,
                "tapered": name.startswith("taper"),
                "strokes": [[[round(v, 4) for v in p] for p in s] for s in strokes],
                "count": count,
                "size": [w, h],
            }
            with open(os.path.join(out, "truth", stem + ".json"), "w") as f:
                json.dump(truth, f)
    print(f"{len(items) * 2} images in {out}")


if __name__ == "__main__":
    main()
