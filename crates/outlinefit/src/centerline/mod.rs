//! Centre-line tracing: line art and handwriting as strokes with their width.
//!
//! The pipeline ([`trace_centerline`]):
//!
//! 1. **Mask and boundary.** The thresholded foreground, with specks and pin holes below
//!    `min_area` removed, and its boundary traced exactly as for outlines (sub-pixel on
//!    anti-aliased input).
//! 2. **Skeleton** (`skeleton`): Zhang–Suen thinning of the mask to one pixel.
//! 3. **Centres and radii** (`medial`): each skeleton point is moved across the stroke
//!    until its distances to the boundary on the two sides are equal; the radius is that
//!    distance. This uses the sub-pixel boundary, so on anti-aliased strokes the centre is
//!    not tied to pixel centres.
//! 4. **Stroke graph** (`graph`): end points, junctions and the paths between them.
//!    A branch from an end point to a junction is a spur, and removed, when its disks
//!    reach less than `max(1 px, 2 × tolerance)` beyond the junction's disk: it only
//!    describes a bump of the boundary that high. Junctions closer than their radius are
//!    one junction (thinning splits the crossing of two thick strokes in two). At a
//!    junction, the two branches that turn least are one stroke, if they turn by at most
//!    [`PAIR_TURN_DEGREES`]; so an "x" or a "t" is two strokes, a "T" two, a "Y" two. A
//!    stroke that ends at a junction ends at its centre. At a free end, points whose disk
//!    lies inside an earlier one are dropped: the medial axis of a round cap ends at the
//!    cap's centre.
//! 5. **Fit** (`fit`): each stroke as a chain of cubic disk Wang–Ball curves, corners
//!    where the centre line turns by more than the corner angle, G1 joints elsewhere, the
//!    centre within the tolerance of the centres, the radius within it of the radii (or
//!    one radius per stroke with [`StrokeWidth::Constant`]).
//! 6. **Check** (`check`): the drawn envelope (the union of the disks) is rasterised and
//!    compared with the mask, as the outline check does: regions lost or invented.
//!
//! Written by hand: thinning (no maintained crate has it), the graph, the centring and
//! the disk-curve fit. The curve fit itself is the outline fit's (`fit::solve`).
//!
//! Files: `skeleton` (thinning), `medial` (centres and radii from the boundary), `graph`
//! (the stroke graph), `fit` (the disk-curve chains), `check` (the drawn strokes against
//! the mask), `result` (what a trace gives), `svg` and `report` (the outputs).

mod check;
mod fit;
mod graph;
mod medial;
mod report;
mod result;
mod skeleton;
mod svg;

pub use fit::StrokeSegment;
pub use report::{to_csv, write_json};
pub use result::{
    CenterlineResult, Junction, Stroke, StrokeCheck, StrokeEnd, StrokeWidth, PAIR_TURN_DEGREES,
    STROKE_LIKE_LENGTH,
};
pub use svg::{centerline_overlay_svg, centerline_svg, CENTERLINE_WIDTH};

use crate::contour::{self, ContourOptions};
use crate::error::Result;
use crate::geom::Point;
use crate::raster::Bitmap;
use crate::trace::{nothing_traced, Config, ImageInfo};
use fit::{fit_stroke, StrokeFitOptions};
use graph::{EdgeEnd, Graph};
use medial::BoundaryIndex;
use skeleton::Grid;
use std::time::Instant;

/// The thresholded mask without components (8-connected) or holes (4-connected, not
/// touching the image border) smaller than `min_area` pixels.
fn clean_mask(bitmap: &Bitmap, min_area: f64) -> Grid {
    use imageproc::region_labelling::{connected_components, Connectivity};
    let mut mask = bitmap.mask();
    let (w, h) = (mask.width() as usize, mask.height() as usize);
    // imageproc's labelling asserts on a one-pixel image, which has nothing to clean.
    if w * h >= 2 {
        // Pass 0 drops small shapes; pass 1 fills small holes (labelled on the inverse).
        for pass in 0..2 {
            let mut probe = mask.clone();
            if pass == 1 {
                for p in probe.pixels_mut() {
                    p[0] = 255 - p[0];
                }
            }
            let connectivity = [Connectivity::Eight, Connectivity::Four][pass];
            let labels = connected_components(&probe, connectivity, image::Luma([0u8]));
            let count = labels.pixels().map(|p| p[0]).max().unwrap_or(0) as usize;
            let mut area = vec![0usize; count + 1];
            let mut border = vec![false; count + 1];
            for (x, y, p) in labels.enumerate_pixels() {
                let l = p[0] as usize;
                area[l] += 1;
                border[l] |= x == 0 || y == 0 || x as usize + 1 == w || y as usize + 1 == h;
            }
            let value = [0u8, 255][pass];
            for (x, y, p) in labels.enumerate_pixels() {
                let l = p[0] as usize;
                // Background touching the image border is paper, not a hole.
                if l > 0 && (area[l] as f64) < min_area && (pass == 0 || !border[l]) {
                    mask.put_pixel(x, y, image::Luma([value]));
                }
            }
        }
    }
    Grid {
        width: w,
        height: h,
        cells: mask.pixels().map(|p| p[0] > 0).collect(),
    }
}

/// Moves every skeleton point to the stroke's centre and measures its radius.
fn measure(graph: &mut Graph, index: &BoundaryIndex) {
    let centre = |p: Point, tangent: Point| -> (Point, f64) {
        let d = index.distance(p, 8.0).unwrap_or(0.5);
        // The radius is the distance to the nearest boundary (the largest disk there),
        // which at a cap or in a corner is not a side's.
        index
            .centre(p, tangent, 2.0 * d + 2.0)
            .filter(|(c, _)| c.distance(p) <= d + 1.0)
            .map(|(c, r)| (c, index.distance(c, r + 1.0).map_or(r, |n| n.min(r))))
            .unwrap_or((p, d))
    };
    for node in &mut graph.nodes {
        node.radius = index.distance(node.centre, 8.0).unwrap_or(0.5);
    }
    for e in &mut graph.edges {
        let n = e.points.len();
        let closed = e.ends.is_none();
        let raw = e.points.clone();
        for i in 0..n {
            let k = 3;
            let (a, b) = if closed {
                (raw[(i + n - k % n) % n], raw[(i + k) % n])
            } else {
                (raw[i.saturating_sub(k)], raw[(i + k).min(n - 1)])
            };
            let t = (b - a).normalized().unwrap_or(Point::new(1.0, 0.0));
            let (c, r) = centre(raw[i], t);
            e.points[i] = c;
            e.radii[i] = r;
        }
    }
}

/// Drops the points at the end of a run whose disk lies inside an earlier one (within
/// `eps`): past the centre of a round cap.
fn trim_end(points: &mut Vec<Point>, radii: &mut Vec<f64>, eps: f64) {
    while points.len() > 2 {
        let (p, r) = (points[points.len() - 1], radii[radii.len() - 1]);
        let look = (4.0 * r).ceil() as usize + 4;
        let inside = points[..points.len() - 1]
            .iter()
            .zip(&radii[..radii.len() - 1])
            .rev()
            .take(look)
            .any(|(q, rq)| q.distance(p) + r <= rq + eps);
        if !inside {
            break;
        }
        points.pop();
        radii.pop();
    }
}

/// Rebuilds the end of a run up to the centre of its cap. The last centres are the least
/// sure (thinning erodes and bends the ends of strokes, and near the cap the two sides
/// are the cap itself), so they are replaced: from a point `max(2 r, 3)` px before the
/// end, the run follows the quadratic (in arc length) that fits the `max(6 r, 16)` px
/// before that point, its radius the line that fits their radii, to where the boundary
/// ahead along it is one radius away.
fn extend_end(points: &mut Vec<Point>, radii: &mut Vec<f64>, index: &BoundaryIndex) {
    let n = points.len();
    let span = (2.0 * radii[n - 1]).max(3.0);
    let back_from = |from: usize, length: f64| {
        (0..from)
            .rev()
            .find(|&k| points[k].distance(points[from]) >= length)
    };
    let window = (6.0 * radii[n - 1]).max(16.0);
    let (b, b2) = match back_from(n - 1, span).and_then(|b| Some((b, back_from(b, window)?))) {
        Some(pair) => pair,
        None => (n - 1, back_from(n - 1, window).unwrap_or(0)),
    };
    if b2 >= b {
        return;
    }
    let (pb, rb) = (points[b], radii[b]);
    // p(s) = pb + v s + a s² / 2 through the points b2..b (s ≤ 0 their arc length from b).
    let (mut m11, mut m12, mut m22) = (0.0, 0.0, 0.0);
    let (mut r1, mut r2) = (Point::new(0.0, 0.0), Point::new(0.0, 0.0));
    // The radius goes on changing as it did: the line that fits the window's radii.
    let (mut sn, mut s1, mut s2, mut sr, mut ssr) = (1.0, 0.0, 0.0, rb, 0.0);
    let mut s = 0.0;
    for k in (b2..b).rev() {
        s -= points[k].distance(points[k + 1]);
        sn += 1.0;
        s1 += s;
        s2 += s * s;
        sr += radii[k];
        ssr += s * radii[k];
        let (f1, f2) = (s, 0.5 * s * s);
        m11 += f1 * f1;
        m12 += f1 * f2;
        m22 += f2 * f2;
        r1 += (points[k] - pb) * f1;
        r2 += (points[k] - pb) * f2;
    }
    let det = m11 * m22 - m12 * m12;
    let quadratic = (b - b2 >= 3 && det.abs() > 1e-12).then(|| {
        (
            (r1 * m22 - r2 * m12) * (1.0 / det),
            (r2 * m11 - r1 * m12) * (1.0 / det),
        )
    });
    // The bend is kept only where it is larger than the centres' noise: a sagitta over
    // the window above 0.1 px. Extrapolated, the noise's bend would move a straight
    // stroke's end sideways.
    let (v, a) = match quadratic {
        Some((v, a)) if a.length() * s * s / 8.0 > 0.1 => (v, a),
        _ if m11 > 0.0 => (r1 * (1.0 / m11), Point::new(0.0, 0.0)),
        _ => return,
    };
    let Some(_) = v.normalized() else { return };
    let speed = v.length();
    // Its slope counts where it changes the radius by more than 0.2 px over the window
    // (a taper; within ±0.15); otherwise the window's mean radius goes on.
    let det_r = sn * s2 - s1 * s1;
    let slope = if det_r > 1e-12 {
        ((sn * ssr - s1 * sr) / det_r).clamp(-0.15, 0.15)
    } else {
        0.0
    };
    let (rb, slope) = if slope.abs() * s.abs() > 0.2 {
        ((sr - slope * s1) / sn, slope)
    } else {
        (sr / sn, 0.0)
    };
    let at = |s: f64| pb + v * s + a * (0.5 * s * s);
    let limit = 2.0 * span + 4.0 * rb + 8.0;
    let mut extension = Vec::new();
    let mut t = 0.0;
    while t < limit {
        let next = t + 0.5 / speed;
        let q = at(next);
        let r = (rb + slope * next * speed).max(0.0);
        let Some(dir) = (v + a * next).normalized() else {
            break;
        };
        // Only whether the boundary ahead is farther than the radius matters.
        match index.ray(q, dir, r + 1.0) {
            Some(ahead) if ahead <= r => break,
            _ => {
                extension.push((q, r));
                t = next;
            }
        }
    }
    if extension.is_empty() {
        return;
    }
    points.truncate(b + 1);
    radii.truncate(b + 1);
    for (q, r) in extension {
        points.push(q);
        radii.push(r);
    }
}

/// Where a branch that stops at junction `n` ends: where its own line (its first points
/// outside the junction's disk, `points` running away from the junction) meets the line of
/// the stroke that passes through the junction, as a "T"'s stem ends on the bar's centre
/// line. The junction's centre when no stroke passes through or the lines meet far from
/// it.
fn branch_end(
    graph: &Graph,
    through: &Option<(Point, Point)>,
    n: usize,
    points: &[Point],
) -> Point {
    let node = &graph.nodes[n];
    let (Some((a, b)), Some(&c)) = (through, points.first()) else {
        return node.centre;
    };
    let span = node.radius.max(4.0);
    let far = points
        .iter()
        .find(|p| p.distance(c) >= span)
        .copied()
        .unwrap_or(points[points.len() - 1]);
    let (Some(d), ab) = ((c - far).normalized(), *b - *a) else {
        return node.centre;
    };
    let den = d.cross(ab);
    if den.abs() < 1e-9 {
        return node.centre;
    }
    let s = (*a - c).cross(ab) / den;
    let e = c + d * s;
    if s >= 0.0 && e.distance(node.centre) <= node.radius + 1.0 {
        e
    } else {
        node.centre
    }
}

/// A stroke before fitting: its points, radii, and how it ends.
struct RawStroke {
    points: Vec<Point>,
    radii: Vec<f64>,
    closed: bool,
    ends: [Option<usize>; 2],
}

/// Follows the pairings into strokes.
fn assemble(
    graph: &Graph,
    link: &[[Option<EdgeEnd>; 2]],
    index: &BoundaryIndex,
    eps: f64,
) -> Vec<RawStroke> {
    let degree = graph.degrees();
    let mut used = vec![false; graph.edges.len()];
    let mut chains: Vec<(Vec<(usize, bool)>, bool)> = Vec::new();
    // The edges of one stroke, from edge `k` entered at its end `start_end`, through the
    // pairings, as (edge, forwards); each edge is taken once.
    let follow = |used: &mut Vec<bool>, k: usize, start_end: usize| {
        let mut chain = vec![(k, start_end == 0)];
        used[k] = true;
        let mut exit = (k, 1 - start_end);
        while let Some((k2, e2)) = link[exit.0][exit.1] {
            if used[k2] {
                break;
            }
            used[k2] = true;
            chain.push((k2, e2 == 0));
            exit = (k2, 1 - e2);
        }
        chain
    };
    // Open chains start at an end without a continuation.
    for k in 0..graph.edges.len() {
        for start_end in 0..2 {
            let e = &graph.edges[k];
            if used[k] || !e.alive || e.ends.is_none() || link[k][start_end].is_some() {
                continue;
            }
            let chain = follow(&mut used, k, start_end);
            chains.push((chain, false));
        }
    }
    // What is left is closed: loops, or cycles of pairings.
    for k in 0..graph.edges.len() {
        if used[k] || !graph.edges[k].alive {
            continue;
        }
        // A loop has no ends, so no pairing to follow.
        let chain = follow(&mut used, k, 0);
        chains.push((chain, true));
    }
    // The line a stroke passing through each junction takes across it: from where its
    // one branch leaves the junction's disk to where the other does.
    let mut through: Vec<Option<(Point, Point)>> = vec![None; graph.nodes.len()];
    for (k, ends) in link.iter().enumerate() {
        for (e, other) in ends.iter().enumerate() {
            let (Some((k2, e2)), Some(nodes)) = (other, graph.edges[k].ends) else {
                continue;
            };
            let n = nodes[e];
            if through[n].is_none() && (k, e) != (*k2, *e2) {
                through[n] = Some((graph.leaving(k, e).0, graph.leaving(*k2, *e2).0));
            }
        }
    }
    let node_at = |k: usize, forward: bool, last: bool| -> Option<usize> {
        let ends = graph.edges[k].ends?;
        Some(if forward == last { ends[1] } else { ends[0] })
    };
    let outside = |n: usize| {
        let node = &graph.nodes[n];
        move |p: &Point| p.distance(node.centre) > node.radius
    };
    let mut strokes = Vec::new();
    for (chain, closed) in chains {
        let mut points: Vec<Point> = Vec::new();
        let mut radii: Vec<f64> = Vec::new();
        for (idx, &(k, forward)) in chain.iter().enumerate() {
            let e = &graph.edges[k];
            let mut pr: Vec<(Point, f64)> = e
                .points
                .iter()
                .copied()
                .zip(e.radii.iter().copied())
                .collect();
            if !forward {
                pr.reverse();
            }
            if idx > 0 {
                if let Some(n) = node_at(k, forward, false) {
                    // A stroke passing through drops its points within 1.5 junction radii:
                    // their disks there also touch the other stroke, and would widen it.
                    let node = &graph.nodes[n];
                    let keep = move |p: &Point| p.distance(node.centre) > 1.5 * node.radius;
                    while points.len() > 1 && !keep(&points[points.len() - 1]) {
                        points.pop();
                        radii.pop();
                    }
                    let skip = pr.iter().take_while(|(p, _)| !keep(p)).count();
                    pr.drain(..skip.min(pr.len().saturating_sub(1)));
                }
            }
            for (p, r) in pr {
                points.push(p);
                radii.push(r);
            }
        }
        let (first, last) = (chain[0], chain[chain.len() - 1]);
        let mut ends = [None, None];
        if !closed || graph.edges[first.0].ends.is_some() {
            let start_node = node_at(first.0, first.1, false);
            let end_node = node_at(last.0, last.1, true);
            for (side, node) in [(0, start_node), (1, end_node)] {
                let Some(n) = node else { continue };
                if degree[n] >= 3 {
                    ends[side] = Some(n);
                }
            }
        }
        if closed {
            // A cycle through a junction: drop the points inside it at both ends.
            if let Some(n) = ends[0] {
                let keep = outside(n);
                while points.len() > 3 && !keep(&points[points.len() - 1]) {
                    points.pop();
                    radii.pop();
                }
                let skip = points
                    .iter()
                    .take_while(|p| !keep(p))
                    .count()
                    .min(points.len().saturating_sub(3));
                points.drain(..skip);
                radii.drain(..skip);
            }
            strokes.push(RawStroke {
                points,
                radii,
                closed,
                ends: [None, None],
            });
            continue;
        }
        for side in 0..2 {
            if side == 1 {
                points.reverse();
                radii.reverse();
            }
            match ends[side] {
                Some(n) => {
                    let keep = outside(n);
                    let skip = points
                        .iter()
                        .take_while(|p| !keep(p))
                        .count()
                        .min(points.len().saturating_sub(1));
                    let r = radii[skip];
                    points.drain(..skip);
                    radii.drain(..skip);
                    let end = branch_end(graph, &through[n], n, &points);
                    points.insert(0, end);
                    radii.insert(0, r);
                }
                None => {
                    points.reverse();
                    radii.reverse();
                    trim_end(&mut points, &mut radii, eps);
                    extend_end(&mut points, &mut radii, index);
                    points.reverse();
                    radii.reverse();
                }
            }
            if side == 1 {
                points.reverse();
                radii.reverse();
            }
        }
        strokes.push(RawStroke {
            points,
            radii,
            closed,
            ends,
        });
    }
    for &n in &graph.dots {
        let node = &graph.nodes[n];
        strokes.push(RawStroke {
            points: vec![node.centre],
            radii: vec![node.radius],
            closed: false,
            ends: [None, None],
        });
    }
    strokes
}

/// Traces the centre lines of `bitmap`'s strokes with `config`'s threshold, tolerance,
/// corner angle, minimum area, check and timing settings.
///
/// Errors: [`crate::Error::NoForeground`] or [`crate::Error::AllBelowMinArea`] when there
/// is nothing to trace; an invalid `config`.
pub fn trace_centerline(
    bitmap: &Bitmap,
    config: &Config,
    width: StrokeWidth,
) -> Result<CenterlineResult> {
    config.validate()?;
    let started = Instant::now();
    let extraction = contour::extract_borders(
        bitmap,
        &ContourOptions {
            min_area: config.min_area,
            edge_spread: false,
        },
    )?;
    if extraction.contours.is_empty() {
        return Err(nothing_traced(bitmap, config.min_area));
    }
    let polygons: Vec<Vec<Point>> = extraction
        .contours
        .iter()
        .map(|c| c.points.clone())
        .collect();
    drop(extraction);
    let index = BoundaryIndex::new(&polygons, bitmap.width(), bitmap.height());
    let mut grid = clean_mask(bitmap, config.min_area);
    let ink = grid.clone();
    skeleton::thin(&mut grid);
    let skeleton: Vec<Point> = (0..grid.cells.len())
        .filter(|&i| grid.cells[i])
        .map(|i| Point::new((i % grid.width) as f64 + 0.5, (i / grid.width) as f64 + 0.5))
        .collect();
    let mut graph = graph::build(&grid);
    measure(&mut graph, &index);
    let limit = (2.0 * config.tolerance).max(1.0);
    let mut spurs = graph.prune_spurs(limit);
    spurs += graph.absorb_corner_tips(limit);
    graph.join_close_junctions();
    spurs += graph.prune_spurs(limit);
    graph.join_through_degree_two();
    let link = graph::pair_at_junctions(&graph, PAIR_TURN_DEGREES.to_radians());
    let raw = assemble(&graph, &link, &index, 0.5 * config.tolerance);
    // Junctions that strokes end at or pass through, renumbered.
    let degree = graph.degrees();
    let mut junction_id = vec![usize::MAX; graph.nodes.len()];
    let mut junctions = Vec::new();
    for (n, node) in graph.nodes.iter().enumerate() {
        if node.alive && degree[n] >= 3 {
            junction_id[n] = junctions.len();
            junctions.push(Junction {
                centre: node.centre,
                radius: node.radius,
                branches: degree[n],
            });
        }
    }
    let opts = StrokeFitOptions {
        tolerance: config.tolerance,
        corner_angle: config.corner_angle.to_radians(),
        constant_width: width == StrokeWidth::Constant,
    };
    let fit_one = |s: &RawStroke| -> Stroke {
        let chain = fit_stroke(&s.points, &s.radii, s.closed, &opts);
        let (mut lo, mut hi, mut length) = (f64::INFINITY, 0.0f64, 0.0);
        for seg in &chain.segments {
            let steps = 32;
            let mut prev = seg.curve.center(0.0);
            for i in 0..=steps {
                let t = i as f64 / steps as f64;
                let r = seg.curve.radius(t);
                lo = lo.min(r);
                hi = hi.max(r);
                let p = seg.curve.center(t);
                length += p.distance(prev);
                prev = p;
            }
        }
        let end =
            |e: Option<usize>| e.map_or(StrokeEnd::Free, |n| StrokeEnd::Junction(junction_id[n]));
        Stroke {
            closed: s.closed,
            ends: [end(s.ends[0]), end(s.ends[1])],
            length,
            width_range: [2.0 * lo.max(0.0), 2.0 * hi.max(0.0)],
            centre_max: chain
                .segments
                .iter()
                .map(|g| g.centre_max)
                .fold(0.0, f64::max),
            centre_rms: chain.centre_rms,
            radius_max: chain
                .segments
                .iter()
                .map(|g| g.radius_max)
                .fold(0.0, f64::max),
            radius_rms: chain.radius_rms,
            segments: chain.segments,
            data: s
                .points
                .iter()
                .copied()
                .zip(s.radii.iter().copied())
                .collect(),
        }
    };
    let strokes: Vec<Stroke> = {
        use rayon::prelude::*;
        if raw.len() > 16 {
            raw.par_iter().map(fit_one).collect()
        } else {
            raw.iter().map(fit_one).collect()
        }
    };
    let check = if config.check {
        check::check(&strokes, &ink, config.tolerance, config.min_area.max(2.0))
    } else {
        StrokeCheck::default()
    };
    let total_ink: f64 = strokes.iter().map(Stroke::ink).sum();
    let blob_ink: f64 = strokes
        .iter()
        .filter(|s| !s.is_stroke_like())
        .map(Stroke::ink)
        .sum();
    let seconds = if config.timings {
        started.elapsed().as_secs_f64()
    } else {
        0.0
    };
    Ok(CenterlineResult {
        image: ImageInfo::of(bitmap),
        stroke_width: width,
        strokes,
        junctions,
        spurs_removed: spurs,
        check,
        not_stroke_like: blob_ink >= 0.25 * total_ink,
        seconds,
        skeleton,
    })
}
