//! Fitting one boundary: the same breaks and `lsq` fit as a one-colour outline.
//!
//! A closed boundary is a contour like any other. An open one (junction to junction) is
//! extended at both ends by its point reflection through the end point — a straight,
//! smooth continuation, so curvature and tangent windows near the ends see no false
//! corner — and closed through that padding; its ends become corners, and the run
//! between them is fitted exactly as a run between two corners of an outline is. The
//! padding's own run is discarded. Its first and last control points are the junctions,
//! so every boundary meeting at a junction meets at the same point.

use crate::breaks::{find_breaks, Break, BreakOptions, BreakReason, JointKind};
use crate::contour::Contour;
use crate::curve::RationalCubic;
use crate::fit::lsq::{fit_contour, LsqOptions};
use crate::fit::solve::segment_error;
use crate::fit::FittedSegment;
use crate::geom::Point;

/// Points of reflected padding at each end of an open boundary.
const PADDING: usize = 16;
/// Inner breaks nearer than this to an end are dropped (px).
const END_CLEAR: f64 = 1.0;

/// A fitted boundary: its points and the segments over them (indices into `points`).
#[derive(Clone, Debug)]
pub(crate) struct FittedChain {
    pub points: Vec<Point>,
    pub segments: Vec<FittedSegment>,
}

/// Closed boundaries of this many points or fewer (a region of a pixel or two) are drawn
/// as their polygon: too few points for a curve to follow without overshooting.
const SMALL_LOOP: usize = 8;

/// A closed polyline as straight segments.
fn polygon(line: &[Point]) -> FittedChain {
    let mut points = line.to_vec();
    points.push(line[0]);
    let segments = (0..line.len())
        .map(|k| straight(&points, k, k + 1))
        .collect();
    FittedChain { points, segments }
}

/// A straight segment from `points[a]` to `points[b]` over the points between.
fn straight(points: &[Point], a: usize, b: usize) -> FittedSegment {
    let (p, q) = (points[a], points[b]);
    let run = &points[a..=b];
    let len2 = (q - p).length_squared();
    let params: Vec<f64> = run
        .iter()
        .map(|r| {
            if len2 > 0.0 {
                ((*r - p).dot(q - p) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
        .collect();
    let curve = RationalCubic::new(
        [p, p.lerp(q, 1.0 / 3.0), p.lerp(q, 2.0 / 3.0), q],
        [1.0, 1.0],
    );
    FittedSegment {
        error: segment_error(&curve, run, &params),
        curve,
        start: a,
        end: b,
        point_count: run.len(),
        params,
        arc_range: [0.0, 0.0],
        evaluations: 0,
        seconds: 0.0,
        on_search_boundary: None,
        history: Vec::new(),
        drawn: Default::default(),
    }
}

/// Fits a boundary polyline (closed, or open between its first and last point).
pub(crate) fn fit_boundary(
    line: &[Point],
    closed: bool,
    breaks: &BreakOptions,
    lsq: &LsqOptions,
) -> FittedChain {
    let n = line.len();
    let length: f64 = line.windows(2).map(|w| w[0].distance(w[1])).sum();
    if closed && n <= SMALL_LOOP {
        return polygon(line);
    }
    if closed {
        let contour = Contour {
            points: line.to_vec(),
            is_hole: false,
            parent: None,
            edge_spread: None,
        };
        let fitted = fit_contour(&find_breaks(&contour, breaks, None), lsq);
        if !fitted.segments.is_empty() {
            return FittedChain {
                points: fitted.points,
                segments: fitted.segments,
            };
        }
        // Too few points for a curve: the polygon.
        return polygon(line);
    }
    if n < 4 || length < 2.0 {
        // Too short for a curve: one line if it holds its points, else the polyline.
        let one = straight(line, 0, n - 1);
        let segments = if one.error.max_distance <= lsq.tolerance {
            vec![one]
        } else {
            (0..n - 1).map(|k| straight(line, k, k + 1)).collect()
        };
        return FittedChain {
            points: line.to_vec(),
            segments,
        };
    }
    let pad = PADDING.min(n - 1);
    let (first, last) = (line[0], line[n - 1]);
    let mut padded: Vec<Point> = Vec::with_capacity(n + 2 * pad);
    padded.extend((1..=pad).rev().map(|k| first * 2.0 - line[k]));
    padded.extend_from_slice(line);
    padded.extend((1..=pad).map(|k| last * 2.0 - line[n - 1 - k]));
    let contour = Contour {
        points: padded,
        is_hole: false,
        parent: None,
        edge_spread: None,
    };
    let mut seg = find_breaks(&contour, breaks, None);
    // The ends, wherever the breaks left them (they may insert or replace points).
    let nearest = |target: Point, around: usize| -> usize {
        let lo = around.saturating_sub(pad);
        let hi = (around + pad + 1).min(seg.points.len());
        (lo..hi)
            .min_by(|&a, &b| {
                seg.points[a]
                    .distance(target)
                    .total_cmp(&seg.points[b].distance(target))
            })
            .unwrap_or(around)
    };
    // The last point moved by as many points as the breaks added before it (fewer when
    // they dropped some): an unsigned difference of the lengths would underflow then.
    let i0 = nearest(first, pad);
    let i1 = nearest(
        last,
        (pad + n - 1 + seg.points.len()).saturating_sub(contour.points.len()),
    )
    .max(i0 + 1);
    seg.points[i0] = first;
    seg.points[i1] = last;
    let corner = |index| Break {
        index,
        kind: JointKind::Corner,
        reason: BreakReason::Corner,
    };
    let inner = seg.breaks.iter().copied().filter(|b| {
        b.index > i0
            && b.index < i1
            && seg.points[b.index].distance(first) >= END_CLEAR
            && seg.points[b.index].distance(last) >= END_CLEAR
    });
    seg.breaks = std::iter::once(corner(i0))
        .chain(inner)
        .chain(std::iter::once(corner(i1)))
        .collect();
    let fitted = fit_contour(&seg, lsq);
    let points = seg.points[i0..=i1].to_vec();
    let mut segments: Vec<FittedSegment> = fitted
        .segments
        .into_iter()
        .filter(|s| s.start >= i0 && s.end <= i1 && s.start < s.end)
        .map(|mut s| {
            s.start -= i0;
            s.end -= i0;
            s
        })
        .collect();
    if segments.is_empty()
        || segments[0].start != 0
        || segments.last().map(|s| s.end) != Some(i1 - i0)
    {
        segments = vec![straight(&points, 0, points.len() - 1)];
    }
    FittedChain { points, segments }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> (BreakOptions, LsqOptions) {
        (
            BreakOptions::for_image(50.0, 256, 256),
            LsqOptions::for_tolerance(0.3, false),
        )
    }

    #[test]
    fn an_open_arc_keeps_its_ends_and_stays_within_tolerance() {
        let (b, l) = opts();
        // A quarter of a circle of radius 40, points every ~0.8 px.
        let line: Vec<Point> = (0..=78)
            .map(|k| {
                let t = std::f64::consts::FRAC_PI_2 * f64::from(k) / 78.0;
                Point::new(50.0 + 40.0 * t.cos(), 50.0 + 40.0 * t.sin())
            })
            .collect();
        let f = fit_boundary(&line, false, &b, &l);
        assert_eq!(f.segments[0].curve.points[0], line[0]);
        assert_eq!(f.segments.last().unwrap().curve.points[3], line[78]);
        for s in &f.segments {
            assert!(s.error.max_distance <= 0.3, "{}", s.error.max_distance);
        }
        assert!(f.segments.len() <= 2, "{} segments", f.segments.len());
        // Consecutive segments share their joints.
        for w in f.segments.windows(2) {
            assert_eq!(w[0].curve.points[3], w[1].curve.points[0]);
        }
    }

    #[test]
    fn a_straight_boundary_is_one_segment() {
        let (b, l) = opts();
        let line: Vec<Point> = (0..=20).map(|k| Point::new(f64::from(k), 3.0)).collect();
        let f = fit_boundary(&line, false, &b, &l);
        assert_eq!(f.segments.len(), 1);
        assert!(f.segments[0].error.max_distance < 1e-9);
    }
}
