//! Sub-pixel points of every boundary and the positions of its junctions.
//!
//! **Edge points.** A crack separates pixel r (region A, on the chain's right) from pixel
//! l (region B). Along the line through their centres, each pixel's *coverage* of A is
//! its position on the segment from colour B to colour A ([`super::palette::mix`]): 1 in A,
//! 0 in B, the area of A in an anti-aliased pixel between them. The edge crosses that line
//! at s = Σ f − (pixels on A's side) from the crack, summed over two pixels on each side,
//! which is exact for a straight box-filtered edge at any angle (the area of A in the strip
//! of pixels is the edge's crossing of the strip's centre line) — the colour form of the
//! coverage integration one-colour tracing uses. The window stops at a pixel of a third
//! colour, and where the coverage turns back (another edge). Where it did not reach pure
//! A and pure B (a riser of a shallow edge, whose crossing lies farther along the row than
//! the window reaches), the crack gives no point.
//!
//! **Bilevel images** (no anti-aliasing: under 2 % of boundary pixels mixed) have only
//! crack midpoints, a staircase; they are smoothed by four binomial passes ([1, 2, 1] / 4)
//! so the fit does not follow the steps, holding what is exact: the ends, points on the
//! image border, and square corners (a pixel corner between two straight runs of three
//! cracks or more), which are added as points.
//!
//! **Junctions.** Where chains meet, the point is where the lines fitted to each chain's
//! points 0.8–3.5 px from the pixel corner meet (least squares, held within 1 px of the
//! corner, on the image border when the corner is), since the pixels right at a junction
//! mix three colours. Every chain ending there starts or ends at that same point.

use super::map::{Map, VOID_SIDE};
use super::palette::{mix, Swatch, VOID};
use crate::geom::Point;

/// Pixels on each side of a crack over which coverage is summed.
const WINDOW: i64 = 2;
/// A coverage change against the expected direction larger than this ends the window.
const SLACK: f32 = 0.05;
/// Coverage the outermost pixel on each side must reach (1 − this, or this).
const SATURATION: f32 = 0.15;
/// Largest accepted distance of an edge point from its crack (px).
const MAX_SHIFT: f64 = 1.0;
/// Share of mixed pixels among boundary cracks below which an image is bilevel.
const BILEVEL_SHARE: f64 = 0.02;
/// Chain points nearer than this to a junction's pixel corner are left out (px).
const JUNCTION_CLEAR: f64 = 0.8;
/// Reach of the lines fitted at a junction (px).
const JUNCTION_REACH: f64 = 3.5;
/// Largest move of a junction from its pixel corner (px).
const JUNCTION_MOVE: f64 = 1.0;
/// Points nearer than this to the previous one are dropped (px).
const MIN_SPACING: f64 = 0.3;

/// What the edge placement reads.
pub(crate) struct Pixels<'a> {
    pub colours: &'a [[f32; 4]],
    pub label: &'a [u16],
    pub palette: &'a [Swatch],
    /// Palette index of every region.
    pub region_colour: &'a [u16],
}

impl Pixels<'_> {
    fn colour_of_side(&self, side: u32) -> u16 {
        if side == VOID_SIDE {
            VOID
        } else {
            self.region_colour[side as usize]
        }
    }

    /// Label and premultiplied colour of pixel (x, y); outside the image, transparent.
    fn at(&self, map: &Map, x: i64, y: i64) -> (u16, [f32; 4]) {
        if x < 0 || y < 0 || x >= map.width as i64 || y >= map.height as i64 {
            (VOID, [0.0; 4])
        } else {
            let i = y as usize * map.width + x as usize;
            (self.label[i], self.colours[i])
        }
    }
}

/// The edge point of the crack from vertex `v` in direction `d` between colours `a` (right)
/// and `b` (left), or `None` where the window does not support one.
fn edge_point(px: &Pixels, map: &Map, v: (u32, u32), d: u8, a: u16, b: u16) -> Option<Point> {
    let (dx, dy) = [(1i64, 0i64), (0, 1), (-1, 0), (0, -1)][d as usize];
    // Right and left pixels, and the normal from right to left.
    let (vx, vy) = (i64::from(v.0), i64::from(v.1));
    let (r, l) = match d {
        0 => ((vx, vy), (vx, vy - 1)),
        1 => ((vx - 1, vy), (vx, vy)),
        2 => ((vx - 1, vy - 1), (vx - 1, vy)),
        _ => ((vx, vy - 1), (vx - 1, vy - 1)),
    };
    let (nx, ny) = (l.0 - r.0, l.1 - r.1);
    let (ca, cb) = (
        &px.palette[a as usize].premul,
        &px.palette[b as usize].premul,
    );
    let coverage = |p: (i64, i64)| -> Option<f32> {
        let (lab, c) = px.at(map, p.0, p.1);
        (lab == a || lab == b).then(|| mix(&c, ca, cb).0)
    };
    let mut s = 0.0f32;
    // A's side, inwards: coverage should not fall.
    let mut last_a = 1.0;
    let mut prev = None;
    for k in 0..WINDOW {
        let p = (r.0 - k * nx, r.1 - k * ny);
        let Some(f) = coverage(p) else { break };
        if prev.is_some_and(|q: f32| f < q - SLACK) {
            break;
        }
        s -= 1.0 - f;
        last_a = f;
        prev = Some(f);
    }
    // B's side, outwards: coverage should not rise.
    let mut last_b = 0.0;
    let mut prev = None;
    for k in 0..WINDOW {
        let p = (l.0 + k * nx, l.1 + k * ny);
        let Some(f) = coverage(p) else { break };
        if prev.is_some_and(|q: f32| f > q + SLACK) {
            break;
        }
        s += f;
        last_b = f;
        prev = Some(f);
    }
    let s = f64::from(s);
    if last_a < 1.0 - SATURATION || last_b > SATURATION || s.abs() > MAX_SHIFT {
        return None;
    }
    let mid = Point::new(vx as f64 + 0.5 * dx as f64, vy as f64 + 0.5 * dy as f64);
    Some(mid + Point::new(nx as f64, ny as f64) * s)
}

/// Midpoint of the crack from `v` in direction `d`.
fn midpoint(v: (u32, u32), d: u8) -> Point {
    let (dx, dy) = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][d as usize];
    Point::new(f64::from(v.0) + 0.5 * dx, f64::from(v.1) + 0.5 * dy)
}

/// Per chain, the edge points of its cracks in order (a crack that supports none gives
/// none), and the corners of the image it passes, which are exact points of the outline.
fn crack_points(px: &Pixels, map: &Map, bilevel: bool) -> Vec<Vec<Point>> {
    let (w, h) = (map.width as u32, map.height as u32);
    let image_corner = |v: (u32, u32)| (v.0 == 0 || v.0 == w) && (v.1 == 0 || v.1 == h);
    map.chains
        .iter()
        .map(|ch| {
            let (a, b) = (px.colour_of_side(ch.right), px.colour_of_side(ch.left));
            let mut out = Vec::with_capacity(ch.cracks() + 1);
            let n = ch.cracks();
            // Length (up to 3) of the run of cracks in direction `d` from `k` by `step`.
            let run = |k: usize, d: u8, back: bool| {
                (0..3)
                    .take_while(|&j| {
                        let i = if back { k.checked_sub(j) } else { Some(k + j) };
                        i.is_some_and(|i| i < n && ch.direction(i) == d)
                    })
                    .count()
            };
            for k in 0..n {
                let (v, d) = (ch.vertices[k], ch.direction(k));
                if k == 0 && ch.closed && image_corner(v) {
                    out.push(Point::new(f64::from(v.0), f64::from(v.1)));
                }
                let square_corner = bilevel
                    && k > 0
                    && ch.direction(k - 1) != d
                    && run(k - 1, ch.direction(k - 1), true) == 3
                    && run(k, d, false) == 3;
                if k > 0 && (image_corner(v) || square_corner) {
                    out.push(Point::new(f64::from(v.0), f64::from(v.1)));
                }
                let p = if bilevel {
                    Some(midpoint(v, d))
                } else {
                    edge_point(px, map, v, d, a, b)
                };
                out.extend(p);
            }
            out
        })
        .collect()
}

/// Binomial smoothing of a polyline, `passes` times; an open one keeps its ends, and
/// points for which `fixed` holds stay where they are.
fn smooth(points: &mut [Point], closed: bool, passes: usize, fixed: &dyn Fn(Point) -> bool) {
    let n = points.len();
    if n < 3 {
        return;
    }
    let hold: Vec<bool> = points.iter().map(|&p| fixed(p)).collect();
    for _ in 0..passes {
        let old = points.to_vec();
        for i in 0..n {
            if (!closed && (i == 0 || i == n - 1)) || hold[i] {
                continue;
            }
            let (p, q) = ((i + n - 1) % n, (i + 1) % n);
            points[i] = (old[p] + old[i] * 2.0 + old[q]) * 0.25;
        }
    }
}

/// A point whose least-squares distance to `lines` (point, unit normal) is smallest,
/// drawn towards `v` with weight `lambda`.
fn meet(lines: &[(Point, Point)], v: Point, lambda: f64) -> Point {
    let (mut a, mut b, mut c) = (lambda, 0.0, lambda);
    let (mut rx, mut ry) = (lambda * v.x, lambda * v.y);
    for &(p, n) in lines {
        let k = n.dot(p);
        a += n.x * n.x;
        b += n.x * n.y;
        c += n.y * n.y;
        rx += n.x * k;
        ry += n.y * k;
    }
    let det = a * c - b * b;
    if det.abs() < 1e-12 {
        return v;
    }
    Point::new((c * rx - b * ry) / det, (a * ry - b * rx) / det)
}

/// The line (centroid, unit normal) through `points` by principal axes.
fn fit_line(points: &[Point]) -> Option<(Point, Point)> {
    if points.len() < 2 {
        return None;
    }
    let c = points.iter().fold(Point::new(0.0, 0.0), |s, &p| s + p) * (1.0 / points.len() as f64);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let d = *p - c;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let dir = Point::new(angle.cos(), angle.sin());
    (sxx + syy > 1e-9).then_some((c, dir.perp()))
}

/// The sub-pixel polyline of every chain: an open chain from its start junction to its
/// end junction, a closed one round its loop.
pub(crate) fn chain_polylines(px: &Pixels, map: &Map, mixed_pixels: usize) -> Vec<Vec<Point>> {
    let cracks: usize = map.chains.iter().map(|c| c.cracks()).sum();
    let bilevel = (mixed_pixels as f64) < BILEVEL_SHARE * cracks as f64;
    let points = crack_points(px, map, bilevel);
    // Junction positions: every pixel corner where open chains end.
    let mut at_corner: std::collections::BTreeMap<(u32, u32), Vec<(usize, bool)>> =
        std::collections::BTreeMap::new();
    for (c, ch) in map.chains.iter().enumerate() {
        if !ch.closed {
            at_corner.entry(ch.vertices[0]).or_default().push((c, true));
            at_corner
                .entry(*ch.vertices.last().expect("chains have vertices"))
                .or_default()
                .push((c, false));
        }
    }
    let (w, h) = (map.width as u32, map.height as u32);
    let junction: std::collections::BTreeMap<(u32, u32), Point> = at_corner
        .iter()
        .map(|(&v, ends)| {
            let vp = Point::new(f64::from(v.0), f64::from(v.1));
            let lines: Vec<(Point, Point)> = ends
                .iter()
                .filter_map(|&(c, _)| {
                    let near: Vec<Point> = points[c]
                        .iter()
                        .copied()
                        .filter(|p| {
                            let d = p.distance(vp);
                            (JUNCTION_CLEAR..=JUNCTION_REACH).contains(&d)
                        })
                        .collect();
                    fit_line(&near)
                })
                .collect();
            let mut j = meet(&lines, vp, 0.05);
            let off = j - vp;
            if off.length() > JUNCTION_MOVE {
                j = vp + off * (JUNCTION_MOVE / off.length());
            }
            if v.0 == 0 || v.0 == w {
                j.x = vp.x;
            }
            if v.1 == 0 || v.1 == h {
                j.y = vp.y;
            }
            if bilevel {
                j = vp;
            }
            (v, j)
        })
        .collect();
    // Exact points that smoothing keeps: on the image border, and pixel corners (square
    // corners of bilevel regions, junctions).
    let fixed = |p: Point| {
        p.x == 0.0
            || p.y == 0.0
            || p.x == f64::from(w)
            || p.y == f64::from(h)
            || (p.x.fract() == 0.0 && p.y.fract() == 0.0)
    };
    map.chains
        .iter()
        .zip(&points)
        .map(|(ch, pts)| {
            let mut line: Vec<Point> = pts.clone();
            if line.len() < ch.cracks() / 4 {
                // Too few supported points (thin or busy detail): the crack midpoints.
                line = (0..ch.cracks())
                    .map(|k| midpoint(ch.vertices[k], ch.direction(k)))
                    .collect();
            }
            if ch.closed {
                if bilevel {
                    smooth(&mut line, true, 4, &fixed);
                } else {
                    line = sharpen_corners(line, true);
                }
                return thin_out(line, true);
            }
            let v0 = ch.vertices[0];
            let v1 = *ch.vertices.last().expect("chains have vertices");
            let (p0, p1) = (junction[&v0], junction[&v1]);
            let corner = |v: (u32, u32)| Point::new(f64::from(v.0), f64::from(v.1));
            let clear = |p: &Point| {
                p.distance(corner(v0)) >= JUNCTION_CLEAR
                    && p.distance(corner(v1)) >= JUNCTION_CLEAR
                    && p.distance(p0) >= JUNCTION_CLEAR
                    && p.distance(p1) >= JUNCTION_CLEAR
            };
            let mut out = vec![p0];
            out.extend(line.into_iter().filter(clear));
            out.push(p1);
            if bilevel {
                smooth(&mut out, false, 4, &fixed);
            } else {
                out = sharpen_corners(out, false);
            }
            thin_out(out, false)
        })
        .collect()
}

/// Arc length (px) to the chord ends of the corner detector.
const CORNER_REACH: f64 = 2.0;
/// Smallest chord angle (degrees) of a corner.
const CORNER_ANGLE_DEG: f64 = 50.0;
/// Arc length (px) on each side of a corner treated as rounded by anti-aliasing.
const CORNER_SKIP: f64 = 1.2;
/// Arc length (px) of each straight side fitted beyond the rounded part.
const CORNER_SIDE: f64 = 3.0;
/// Largest distance (px) of a side point from its fitted line.
const CORNER_RESIDUAL: f64 = 0.1;
/// Largest distance (px) from the sharpened corner to the nearest rounded point.
const CORNER_MOVE: f64 = 1.0;

/// Anti-aliasing rounds corners off, and the pixel at a corner mixes more than two
/// colours, so it gives no point: where the line turns by more than [`CORNER_ANGLE_DEG`]
/// within ±[`CORNER_REACH`] px and is straight on both sides beyond the rounded part, the
/// points of the rounded part are replaced by the intersection of the two side lines (as
/// one-colour tracing does on grey levels). An open line keeps its ends.
fn sharpen_corners(points: Vec<Point>, closed: bool) -> Vec<Point> {
    let n = points.len();
    if n < 8 {
        return points;
    }
    if closed {
        // Start on the straightest point, so that no corner straddles the start.
        let mut ext = points.clone();
        ext.extend_from_slice(&points);
        ext.extend_from_slice(&points);
        let arc = arc_lengths(&ext);
        let start = (n..2 * n)
            .min_by(|&a, &b| turn(&ext, &arc, a).total_cmp(&turn(&ext, &arc, b)))
            .unwrap_or(n)
            - n;
        let mut rotated = points;
        rotated.rotate_left(start);
        return sharpen_open(rotated);
    }
    sharpen_open(points)
}

/// Cumulative arc length along `points`.
fn arc_lengths(points: &[Point]) -> Vec<f64> {
    let mut arc = vec![0.0; points.len()];
    for i in 1..points.len() {
        arc[i] = arc[i - 1] + points[i].distance(points[i - 1]);
    }
    arc
}

/// First index at arc distance ≥ |d| from `i`, in the direction of `d` (the end where
/// the line is shorter).
fn index_at(arc: &[f64], i: usize, d: f64) -> usize {
    if d >= 0.0 {
        (i..arc.len())
            .find(|&k| arc[k] - arc[i] >= d)
            .unwrap_or(arc.len() - 1)
    } else {
        (0..=i).rev().find(|&k| arc[i] - arc[k] >= -d).unwrap_or(0)
    }
}

/// Angle between the chords to the points [`CORNER_REACH`] back and ahead of `i`.
fn turn(points: &[Point], arc: &[f64], i: usize) -> f64 {
    let (b, a) = (
        index_at(arc, i, -CORNER_REACH),
        index_at(arc, i, CORNER_REACH),
    );
    if b == i || a == i {
        return 0.0;
    }
    crate::geom::angle_between(points[i] - points[b], points[a] - points[i])
}

/// [`sharpen_corners`] on a line whose first and last points stay where they are.
fn sharpen_open(points: Vec<Point>) -> Vec<Point> {
    let m = points.len();
    let arc = arc_lengths(&points);
    let angles: Vec<f64> = (0..m).map(|i| turn(&points, &arc, i)).collect();
    let min = CORNER_ANGLE_DEG.to_radians();
    let line = |r: std::ops::RangeInclusive<usize>| -> Option<(Point, Point)> {
        let pts = &points[r];
        let (c, nrm) = fit_line(pts)?;
        let worst = pts
            .iter()
            .map(|p| (*p - c).dot(nrm).abs())
            .fold(0.0, f64::max);
        (worst <= CORNER_RESIDUAL).then_some((c, nrm))
    };
    // Written points with their index in `points` (`None` for a sharpened corner).
    let mut out: Vec<(Option<usize>, Point)> = Vec::with_capacity(m);
    let mut i = 0;
    while i < m {
        let (b, a) = (
            index_at(&arc, i, -CORNER_REACH),
            index_at(&arc, i, CORNER_REACH),
        );
        let is_max = i > 0
            && i + 1 < m
            && angles[i] >= min
            && (b..i).all(|k| angles[k] < angles[i])
            && (i + 1..=a).all(|k| angles[k] <= angles[i]);
        let sharpened = is_max.then(|| {
            let (ib, ia) = (
                index_at(&arc, i, -CORNER_SKIP),
                index_at(&arc, i, CORNER_SKIP),
            );
            let ob = index_at(&arc, i, -(CORNER_SKIP + CORNER_SIDE));
            let oa = index_at(&arc, i, CORNER_SKIP + CORNER_SIDE);
            // Both sides whole, and the rounded part not reaching back into what is written.
            // A corner already written must lie before this one's straight side: the
            // first point written after it comes from `ob` or earlier.
            let after_corner = match out.iter().rposition(|(k, _)| k.is_none()) {
                None => true,
                Some(c) => out.get(c + 1).and_then(|e| e.0).is_some_and(|k| k <= ob),
            };
            if ib < ob + 1 || oa < ia + 1 || ib == 0 || ia == m - 1 || !after_corner {
                return None;
            }
            let (c1, n1) = line(ob..=ib)?;
            let (c2, n2) = line(ia..=oa)?;
            let x = meet(&[(c1, n1), (c2, n2)], points[i], 0.0);
            let nearest = (ib..=ia)
                .map(|k| points[k].distance(x))
                .fold(f64::INFINITY, f64::min);
            (x.is_finite() && nearest <= CORNER_MOVE).then_some((ib, ia, x))
        });
        match sharpened.flatten() {
            Some((ib, ia, x)) => {
                // Keep points up to ib, the corner, then go on from ia.
                while out.last().is_some_and(|(k, _)| k.is_some_and(|k| k > ib)) {
                    out.pop();
                }
                out.push((None, x));
                i = ia;
            }
            None => {
                out.push((Some(i), points[i]));
                i += 1;
            }
        }
    }
    out.into_iter().map(|(_, p)| p).collect()
}

/// Drops points nearer than [`MIN_SPACING`] to the previous kept one (an open line keeps
/// both ends).
fn thin_out(points: Vec<Point>, closed: bool) -> Vec<Point> {
    let n = points.len();
    if n < 3 {
        return points;
    }
    let mut out: Vec<Point> = Vec::with_capacity(n);
    for (i, p) in points.iter().enumerate() {
        let last = !closed && i == n - 1;
        match out.last() {
            Some(q) if q.distance(*p) < MIN_SPACING && !last => {}
            Some(q) if last && q.distance(*p) < MIN_SPACING && out.len() > 1 => {
                out.pop();
                out.push(*p);
            }
            _ => out.push(*p),
        }
    }
    if closed && out.len() > 3 && out[0].distance(out[out.len() - 1]) < MIN_SPACING {
        out.pop();
    }
    out
}
