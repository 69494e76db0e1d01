//! The traced outline as every writer sees it: shapes (an outer border with its holes),
//! each contour as drawn cubics, as exact rational pieces, or as a polygon flattened
//! within a bound.

use crate::curve::{CubicBez, RationalCubic};
use crate::fit::FittedContour;
use crate::geom::Point;
use crate::merge::outline::{drawing_pieces, walk_pieces, MergedCurve, Piece};
use crate::trace::TraceResult;

/// For every contour, the holes cut into it (contours are outer borders when not holes),
/// and the holes with no outer border to cut into (which have segments: drawn alone, a
/// hole would be filled, so writers leave them out and say so).
pub(crate) fn holes_of(result: &TraceResult) -> (Vec<Vec<usize>>, Vec<usize>) {
    let contours = &result.contours;
    let mut holes: Vec<Vec<usize>> = vec![Vec::new(); contours.len()];
    let mut orphans = Vec::new();
    for (i, c) in contours.iter().enumerate() {
        if !c.is_hole {
            continue;
        }
        match c.parent {
            Some(p) if p < contours.len() && !contours[p].is_hole => holes[p].push(i),
            _ if !c.segments.is_empty() => orphans.push(i),
            _ => {}
        }
    }
    (holes, orphans)
}

/// One drawing command after the start of a loop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Cmd {
    /// A straight line to the point.
    Line(Point),
    /// A polynomial cubic with these inner control points and end.
    Cubic([Point; 3]),
}

impl Cmd {
    /// Where the command ends.
    pub(crate) fn end(&self) -> Point {
        match *self {
            Cmd::Line(p) => p,
            Cmd::Cubic([_, _, p]) => p,
        }
    }
}

/// A closed contour as drawn: a start and commands, closed back to the start.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Loop {
    pub(crate) start: Point,
    pub(crate) cmds: Vec<Cmd>,
}

/// A contour's loop, or why there is none (as SVG's comments name them).
pub(crate) enum Drawn {
    Loop(Loop),
    /// The contour has no segments.
    Empty,
    /// Some coordinate of the curves or of their cubics is not finite.
    NonFinite,
}

/// What the SVG draws of the contour ([`drawing_pieces`]), or `None` when a coordinate of
/// its curves or of their cubics is not finite. The contour must have segments.
pub(crate) fn finite_pieces(
    contour: &FittedContour,
    merged: &[MergedCurve],
    bound: f64,
) -> Option<Vec<(Point, Vec<CubicBez>)>> {
    let pieces = drawing_pieces(contour, merged, bound);
    let finite = contour
        .segments
        .iter()
        .all(|s| s.curve.points.iter().all(|p| p.is_finite()))
        && pieces.iter().all(|(start, cubics)| {
            start.is_finite()
                && cubics
                    .iter()
                    .all(|c| c.points.iter().all(|p| p.is_finite()))
        });
    finite.then_some(pieces)
}

/// The contour as drawn: its polynomial cubics within `bound` of the fitted (or merged)
/// curves, a cubic whose inner control points lie within `straight` of its chord written
/// as a line, and a line bridging any gap between pieces wider than `straight`.
pub(crate) fn drawn_loop(
    contour: &FittedContour,
    merged: &[MergedCurve],
    bound: f64,
    straight: f64,
) -> Drawn {
    if contour.segments.is_empty() {
        return Drawn::Empty;
    }
    let Some(pieces) = finite_pieces(contour, merged, bound) else {
        return Drawn::NonFinite;
    };
    let start = pieces[0].0;
    let mut pen = start;
    let mut cmds = Vec::new();
    for (from, cubics) in &pieces {
        if from.distance(pen) > straight {
            cmds.push(Cmd::Line(*from));
        }
        pen = *from;
        for c in cubics {
            let end = c.points[3];
            if is_straight(c, straight) {
                cmds.push(Cmd::Line(end));
            } else {
                cmds.push(Cmd::Cubic([c.points[1], c.points[2], end]));
            }
            pen = end;
        }
    }
    Drawn::Loop(Loop { start, cmds })
}

/// True when a cubic draws a straight line from its start to its end: both inner control
/// points lie within `tolerance` of the chord and between its ends, so the curve (inside
/// the hull of its control points) stays within `tolerance` of the line drawn instead.
pub(crate) fn is_straight(c: &CubicBez, tolerance: f64) -> bool {
    let [p0, p1, p2, p3] = c.points;
    let chord = p3 - p0;
    let length = chord.length();
    if length <= tolerance {
        return false;
    }
    let u = chord * (1.0 / length);
    [p1, p2].iter().all(|&p| {
        let d = p - p0;
        let along = d.dot(u);
        d.cross(u).abs() <= tolerance && along >= -tolerance && along <= length + tolerance
    })
}

/// The contour as a chain of rational cubics, each fitted segment exactly and a merged
/// run as the polynomial cubics (weights 1) that draw its centre curve within `bound`.
/// Consecutive pieces share their end points exactly (the last ends where the first
/// starts). `None` when the contour has no segments or a coordinate is not finite.
pub(crate) fn exact_pieces(
    contour: &FittedContour,
    merged: &[MergedCurve],
    bound: f64,
) -> Option<Vec<RationalCubic>> {
    if contour.segments.is_empty() {
        return None;
    }
    let mut out: Vec<RationalCubic> = Vec::new();
    for piece in walk_pieces(contour, merged) {
        match piece {
            Piece::Segment(k) => out.push(contour.segments[k].curve),
            Piece::Merged(m) => out.extend(
                m.center_cubics(bound)
                    .into_iter()
                    .map(|c| RationalCubic::new(c.points, [1.0, 1.0])),
            ),
        }
    }
    let finite = out.iter().all(|c| {
        c.points.iter().all(|p| p.is_finite())
            && c.weights.iter().all(|w| w.is_finite() && *w > 0.0)
    });
    if !finite || out.is_empty() {
        return None;
    }
    // Close every joint exactly: the fit's joints agree to rounding, and a spline needs
    // one shared control point.
    for k in 0..out.len() {
        let next = out[(k + 1) % out.len()].points[0];
        out[k].points[3] = next;
    }
    Some(out)
}

/// The loop as a closed polygon (its first point not repeated at the end) within
/// `tolerance` of the drawn curves: each cubic cut into equal parameter steps, as many as
/// its second derivative needs (a curve with |B''| ≤ K strays at most K h² / 8 from the
/// chords of steps h).
pub(crate) fn flatten(l: &Loop, tolerance: f64) -> Vec<Point> {
    let mut out = vec![l.start];
    let mut pen = l.start;
    for cmd in &l.cmds {
        match *cmd {
            Cmd::Line(p) => out.push(p),
            Cmd::Cubic([p1, p2, p3]) => {
                let c = CubicBez::new(pen, p1, p2, p3);
                let a = (pen - p1 * 2.0 + p2).length();
                let b = (p1 - p2 * 2.0 + p3).length();
                let k = 6.0 * a.max(b);
                let steps = ((k / (8.0 * tolerance)).sqrt().ceil() as usize).clamp(1, 10_000);
                out.extend((1..=steps).map(|j| c.eval(j as f64 / steps as f64)));
            }
        }
        pen = cmd.end();
    }
    // Closed back to the start: drop the repeated end point and any repeats in between.
    out.dedup();
    while out.len() > 1 && out.last() == out.first() {
        out.pop();
    }
    out
}

/// Twice the signed area of a closed polygon (positive when it turns counter-clockwise
/// with y up, that is clockwise on screen with y down).
pub(crate) fn signed_area2(ring: &[Point]) -> f64 {
    let n = ring.len();
    (0..n).map(|i| ring[i].cross(ring[(i + 1) % n])).sum()
}

/// Maps image pixels (y down, origin top left) to a page with y up and its origin at the
/// bottom left, `per_pixel` units to the pixel: what PDF, PostScript, DXF and GeoJSON use.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FlipY {
    pub(crate) height: f64,
    pub(crate) per_pixel: f64,
}

impl FlipY {
    pub(crate) fn apply(&self, p: Point) -> Point {
        Point::new(p.x * self.per_pixel, (self.height - p.y) * self.per_pixel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::svg::tests::{circle, result};

    #[test]
    fn flattened_circle_stays_within_the_tolerance() {
        let c = circle(Point::new(30.0, 20.0), 12.0, false, None);
        let Drawn::Loop(l) = drawn_loop(&c, &[], 0.01, 0.005) else {
            panic!("no loop");
        };
        for tol in [0.5, 0.05, 0.005] {
            let ring = flatten(&l, tol);
            assert!(ring.len() >= 8);
            for w in 0..ring.len() {
                let (a, b) = (ring[w], ring[(w + 1) % ring.len()]);
                // Vertices on the circle (to the cubics' bound), chords' midpoints within
                // the flattening tolerance of it.
                assert!((a.distance(Point::new(30.0, 20.0)) - 12.0).abs() < 0.011);
                let mid = a.lerp(b, 0.5).distance(Point::new(30.0, 20.0));
                assert!(12.0 - mid <= tol + 0.011, "{tol}: {mid}");
            }
            // Outer borders turn clockwise on screen: positive with y down here.
            let area = 0.5 * signed_area2(&ring);
            let exact = std::f64::consts::PI * 144.0;
            assert!(
                (area - exact).abs() < exact * (2.0 * tol / 12.0) + 0.5,
                "{area}"
            );
        }
    }

    #[test]
    fn exact_pieces_share_their_joints() {
        let c = circle(Point::new(5.0, 5.0), 3.0, false, None);
        let pieces = exact_pieces(&c, &[], 0.02).unwrap();
        assert_eq!(pieces.len(), 4);
        for k in 0..4 {
            assert_eq!(pieces[k].points[3], pieces[(k + 1) % 4].points[0]);
            assert_eq!(pieces[k].weights, c.segments[k].curve.weights);
        }
        let r = result(10, 10, vec![c]);
        let (holes, orphans) = holes_of(&r);
        assert_eq!(holes, vec![Vec::<usize>::new()]);
        assert!(orphans.is_empty());
    }
}
